#include "algorithms/allan/model_edf.h"

#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/allan/avar_covariance.h"
#include "algorithms/allan/estimate_law.h"

namespace fogpipe::allan {

namespace {

double Square(double a) { return std::isfinite(a) ? a * a : 0.0; }

// The amplitudes with NaN (a term not fitted) as 0.
NoiseTerms FiniteAmplitudes(const NoiseTerms& terms) {
  NoiseTerms t = terms;
  for (double* a : {&t.q_rad, &t.n_rad_sqrt_s, &t.b_rad_s, &t.k_rad_s_sqrt_s, &t.r_rad_s2})
    *a = std::sqrt(Square(*a));
  return t;
}

bool InMisfitRange(const NoiseFitResult& fit, double tau_s) {
  for (const TauRange& r : fit.misfit_ranges)
    if (tau_s >= r.low_s && tau_s <= r.high_s) return true;
  return false;
}

// The estimate's law with few averages (estimate_law.h) where the model's frequency noises carry
// the row: white PM and the ramp (whose D are not continuous, or not centred) below 1 % of the
// model variance. `terms` are finite (FiniteAmplitudes). Empty where chi-square is kept.
std::vector<double> FewAveragesLaw(const NoiseTerms& terms, long long m, long long count,
                                   double t0) {
  if (!FewAverages(2, m, count)) return {};
  const double tau = static_cast<double>(m) * t0;
  NoiseTerms white_pm_and_ramp;
  white_pm_and_ramp.q_rad = terms.q_rad;
  white_pm_and_ramp.r_rad_s2 = terms.r_rad_s2;
  if (!(NoiseModelVariance(white_pm_and_ramp, tau) < 0.01 * NoiseModelVariance(terms, tau)))
    return {};
  const double n2 = terms.n_rad_sqrt_s * terms.n_rad_sqrt_s, b2 = terms.b_rad_s * terms.b_rad_s,
               k2 = terms.k_rad_s_sqrt_s * terms.k_rad_s_sqrt_s;
  return OverlappingLawWeights(2, {0.0, n2 * t0, b2 * t0 * t0, k2 * t0 * t0 * t0}, m, count);
}

}  // namespace

bool ModelEdfOptions::IsValid(std::string* error) const {
  if (!(min_p_value >= 0.0 && min_p_value < 1.0) || !(confidence > 0.0 && confidence < 1.0)) {
    if (error) *error = "need 0 <= min_p_value < 1 and 0 < confidence < 1";
    return false;
  }
  return true;
}

double ModelOverlappingAllanEdf(const NoiseTerms& terms, long long m, long long count,
                                double sample_period_s) {
  const double tau_s = static_cast<double>(m) * sample_period_s;
  const NoiseTerms t = FiniteAmplitudes(terms);
  const double mean = NoiseModelVariance(t, tau_s);
  if (!(mean > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const AvarCovarianceModel covariance({m}, {count}, sample_period_s);
  const double variance = covariance.Covariance(
      {Square(t.q_rad), Square(t.n_rad_sqrt_s), Square(t.b_rad_s), Square(t.k_rad_s_sqrt_s)},
      Square(t.r_rad_s2))(0, 0);
  if (!(variance > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return 2.0 * mean * mean / variance;
}

int ApplyModelEdf(const NoiseFitResult& fit, const ModelEdfOptions& options, AllanTable* table) {
  if (!options.IsValid(nullptr)) return -1;
  if (table->deviation != Deviation::kOverlappingAllan ||
      table->noise_id_rule != NoiseIdRule::kCalibrated || !fit.generalized ||
      fit.model_discrepancy > 0.0 || !(fit.p_value >= options.min_p_value))
    return 0;
  const size_t rows = table->size();
  if (table->edf.size() != rows) return 0;
  if (table->edf_source.size() != rows) table->edf_source.assign(rows, EdfSource::kNone);
  const NoiseTerms terms = FiniteAmplitudes(fit.terms);
  int changed = 0;
  for (size_t k = 0; k < rows; ++k) {
    const double tau = table->tau_s[k];
    if (k >= table->m.size() || k >= table->count.size() || table->m[k] < 1 ||
        table->count[k] < 1 || !(table->sigma[k] > 0.0) || !std::isfinite(table->sigma[k]))
      continue;
    if (tau < fit.fitted_range.low_s || tau > fit.fitted_range.high_s || InMisfitRange(fit, tau))
      continue;
    const double t0 = tau / static_cast<double>(table->m[k]);
    const double edf = ModelOverlappingAllanEdf(terms, table->m[k], table->count[k], t0);
    if (!(edf > 0.0) || !std::isfinite(edf)) continue;
    table->edf[k] = edf;
    const std::vector<double> law = FewAveragesLaw(terms, table->m[k], table->count[k], t0);
    if (!law.empty())
      LawBounds(table->sigma[k], law, options.confidence, &table->ci_low[k], &table->ci_high[k]);
    else
      ConfidenceBounds(table->sigma[k], edf, options.confidence, &table->ci_low[k],
                       &table->ci_high[k]);
    table->edf_source[k] = EdfSource::kModel;
    ++changed;
  }
  return changed;
}

NoiseFitResult FitNoiseTermsAndModelEdf(const NoiseFitOptions& options, double confidence,
                                        AllanTable* table) {
  NoiseFitResult fit = FitNoiseTerms(*table, options);
  ModelEdfOptions model;
  model.confidence = confidence;
  ApplyModelEdf(fit, model, table);
  return fit;
}

}  // namespace fogpipe::allan
