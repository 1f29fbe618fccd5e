#include "algorithms/allan/allan.h"

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "algorithms/allan/edf.h"
#include "algorithms/allan/estimate_law.h"
#include "algorithms/allan/noise_id.h"
#include "algorithms/allan/phase.h"
#include "algorithms/allan/phase_noise_law.h"
#include "algorithms/common/chi_square.h"

namespace fogpipe::allan {

bool AllanOptions::IsValid(std::string* error) const {
  if (!grid.IsValid(error)) return false;
  if (threads < 1) {
    if (error) *error = "threads must be at least 1";
    return false;
  }
  if (!(confidence > 0.0 && confidence < 1.0)) {
    if (error) *error = "confidence must be in (0, 1)";
    return false;
  }
  return true;
}

const char* ToString(EdfSource source) {
  switch (source) {
    case EdfSource::kNoiseType:
      return "noise_type";
    case EdfSource::kModel:
      return "model";
    case EdfSource::kNone:
      break;
  }
  return "none";
}

std::vector<std::string> EdfSourceNames(const std::vector<EdfSource>& sources) {
  std::vector<std::string> names;
  names.reserve(sources.size());
  for (EdfSource s : sources) names.emplace_back(ToString(s));
  return names;
}

void ConfidenceBounds(double sigma, double edf, double confidence, double* low, double* high) {
  const double tail = 0.5 * (1.0 - confidence);
  *low = ChiSquareBound(sigma, edf, stats::ChiSquareQuantile(1.0 - tail, edf));
  *high = ChiSquareBound(sigma, edf, stats::ChiSquareQuantile(tail, edf));
}

double ChiSquareBound(double sigma, double edf, double quantile) {
  return sigma * std::sqrt(edf / quantile);
}

namespace {

// The overlapping Allan variance at the factors with fewer than 30 averages (B1's denominator in
// noise_id.h; NaN elsewhere): for OADEV the result itself, otherwise one extra blocked sweep over
// those few long factors.
std::vector<double> OverlappingAllanBelow30Averages(const Eigen::VectorXd& phase,
                                                    Deviation deviation,
                                                    const std::vector<long long>& m,
                                                    const std::vector<double>& variance) {
  if (deviation == Deviation::kOverlappingAllan) return variance;
  const long long n = phase.size() - 1;
  std::vector<double> out(m.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<long long> few;
  std::vector<size_t> where;
  for (size_t k = 0; k < m.size(); ++k)
    if (n / m[k] < 30 && m[k] <= MaxAveragingFactor(Deviation::kOverlappingAllan, n))
      few.push_back(m[k]), where.push_back(k);
  const std::vector<double> v = DeviationVariances(phase, Deviation::kOverlappingAllan, few);
  for (size_t i = 0; i < few.size(); ++i) out[where[i]] = v[i];
  return out;
}

// The law of the estimate of one noise type with few averages (estimate_law.h for frequency
// noise, phase_noise_law.h for phase noise); empty where chi-square serves.
WeightedChiSquareLaw FewAveragesLaw(int d, int alpha, long long m, long long count) {
  if (alpha == 1 || alpha == 2) return PhaseNoiseLaw(d, alpha, m, count);
  if (alpha > 2 || alpha < -2) return {};
  std::array<double, 4> theta{};
  theta[static_cast<size_t>(1 - alpha)] = 1.0;  // 0 -> N, -1 -> B, -2 -> K
  return OverlappingLawWeights(d, theta, m, count);
}

// A row's interval apart from its sigma (IntervalForNoiseType): the EDF and the two quantiles
// its bounds divide by, of the estimate's law or of chi-square(edf).
struct IntervalQuantiles {
  double edf = std::numeric_limits<double>::quiet_NaN();
  bool from_law = false;
  double for_low = std::numeric_limits<double>::quiet_NaN();   // at 1 - tail: gives ci_low
  double for_high = std::numeric_limits<double>::quiet_NaN();  // at tail: gives ci_high
};

IntervalQuantiles FindIntervalQuantiles(const AllanOptions& options, int alpha, long long m,
                                        long long count, long long n) {
  IntervalQuantiles out;
  const int d = DifferenceOrder(options.deviation);
  // The estimate's own law with few averages (estimate_law.h) belongs to the calibrated rule;
  // Stable32's rule keeps its chi-square bounds.
  const bool law_applies = (options.deviation == Deviation::kOverlappingAllan ||
                            options.deviation == Deviation::kOverlappingHadamard) &&
                           options.noise_id == NoiseIdRule::kCalibrated &&
                           options.sampled_phase_edf;
  // Phase noise under the calibrated rule: the EDF of the sampled process's own covariance
  // (phase_noise_law.h), which for flicker PM is above Greenhall's kernel's.
  out.edf = law_applies && (alpha == 1 || alpha == 2)
                ? PhaseNoiseEdf(d, alpha, m, count)
                : DeviationEdf(options.deviation, alpha, m, n, options.sampled_phase_edf);
  if (!(out.edf > 0.0)) return out;
  const WeightedChiSquareLaw law =
      law_applies ? FewAveragesLaw(d, alpha, m, count) : WeightedChiSquareLaw();
  const double tail = 0.5 * (1.0 - options.confidence);
  out.from_law = !law.empty();
  out.for_low = out.from_law ? WeightedChiSquareQuantile(law, 1.0 - tail)
                             : stats::ChiSquareQuantile(1.0 - tail, out.edf);
  out.for_high =
      out.from_law ? WeightedChiSquareQuantile(law, tail) : stats::ChiSquareQuantile(tail, out.edf);
  return out;
}

// FindIntervalQuantiles with the last results on this thread kept: they depend on the row's
// shape only (not on the data), their laws take an eigendecomposition and saddlepoint
// quantiles, and tables of one record length (a parameter sweep scores hundreds) repeat them.
IntervalQuantiles CachedIntervalQuantiles(const AllanOptions& options, int alpha, long long m,
                                          long long count, long long n) {
  struct Kept {
    Deviation deviation;
    NoiseIdRule rule;
    bool sampled_phase_edf;
    double confidence;
    int alpha;
    long long m, count, n;
    IntervalQuantiles value;
  };
  constexpr size_t kKept = 256;
  thread_local std::vector<Kept> kept;
  thread_local size_t next_slot = 0;
  for (const Kept& k : kept)
    if (k.m == m && k.count == count && k.n == n && k.alpha == alpha &&
        k.deviation == options.deviation && k.rule == options.noise_id &&
        k.sampled_phase_edf == options.sampled_phase_edf && k.confidence == options.confidence)
      return k.value;
  const Kept found{options.deviation,
                   options.noise_id,
                   options.sampled_phase_edf,
                   options.confidence,
                   alpha,
                   m,
                   count,
                   n,
                   FindIntervalQuantiles(options, alpha, m, count, n)};
  if (kept.size() < kKept)
    kept.push_back(found);
  else
    kept[next_slot] = found;
  next_slot = (next_slot + 1) % kKept;
  return found.value;
}

}  // namespace

NoiseTypeInterval IntervalForNoiseType(const AllanOptions& options, int alpha, long long m,
                                       long long count, long long n, double sigma) {
  NoiseTypeInterval out;
  const IntervalQuantiles q = CachedIntervalQuantiles(options, alpha, m, count, n);
  out.edf = q.edf;
  if (!(out.edf > 0.0)) return out;
  out.ci_low = q.from_law ? LawBound(sigma, q.for_low) : ChiSquareBound(sigma, q.edf, q.for_low);
  out.ci_high = q.from_law ? LawBound(sigma, q.for_high) : ChiSquareBound(sigma, q.edf, q.for_high);
  return out;
}

AllanResult ComputeAllan(const Eigen::Ref<const Eigen::VectorXd>& rate, double sample_rate_hz,
                         const AllanOptions& options) {
  Eigen::VectorXd phase_work;
  return ComputeAllan(rate, sample_rate_hz, options, &phase_work);
}

AllanResult ComputeAllan(const Eigen::Ref<const Eigen::VectorXd>& rate, double sample_rate_hz,
                         const AllanOptions& options, Eigen::VectorXd* phase_work) {
  AllanResult result;
  AllanSummary& summary = result.summary;
  AllanTable& table = result.table;
  table.deviation = options.deviation;
  table.noise_id_rule = options.noise_id;
  std::string error;
  if (!options.IsValid(&error) || !(sample_rate_hz > 0.0) || !std::isfinite(sample_rate_hz)) {
    summary.termination = Termination::kInvalidOptions;
    summary.message = error.empty() ? "sample_rate_hz must be finite and positive" : error;
    return result;
  }
  const long long n = rate.size();
  summary.samples = n;
  const long long max_m = MaxAveragingFactor(options.deviation, n);
  if (max_m < 1) {
    summary.termination = Termination::kInsufficientData;
    summary.message = "too few samples for one difference term";
    return result;
  }
  if (!rate.allFinite()) {
    summary.termination = Termination::kNumericalFailure;
    summary.message = "rate contains non-finite values";
    return result;
  }
  table.m = AveragingFactors(options.grid, max_m, n);
  MeanRemovedPhase(rate, phase_work);
  const Eigen::VectorXd& phase = *phase_work;
  const std::vector<double> variance =
      DeviationVariances(phase, options.deviation, table.m, options.threads);

  const size_t rows = table.m.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  table.tau_s.resize(rows);
  table.sigma.resize(rows);
  table.count.resize(rows);
  table.ci_low.assign(rows, nan);
  table.ci_high.assign(rows, nan);
  table.edf.assign(rows, nan);
  table.alpha.assign(rows, 0);
  table.alpha_method.assign(rows, NoiseIdMethod::kNone);
  table.edf_source.assign(rows, EdfSource::kNone);
  for (size_t k = 0; k < rows; ++k) {
    table.tau_s[k] = static_cast<double>(table.m[k]) / sample_rate_hz;
    // TDEV comes in rate x tau0 (deviation.h): tau0 = 1 / sample_rate_hz makes it rate x s.
    table.sigma[k] =
        std::sqrt(variance[k]) / (IsTimeDeviation(options.deviation) ? sample_rate_hz : 1.0);
    table.count[k] = DifferenceCount(options.deviation, n, table.m[k]);
  }
  if (options.confidence_intervals) {
    const std::vector<double> b1_avar =
        OverlappingAllanBelow30Averages(phase, options.deviation, table.m, variance);
    const std::vector<NoiseId> ids =
        IdentifyNoiseTypes(phase, table.m, table.count, b1_avar, DifferenceOrder(options.deviation),
                           options.noise_id, options.threads);
    for (size_t k = 0; k < rows; ++k) {
      table.alpha[k] = ids[k].alpha;
      table.alpha_method[k] = ids[k].method;
      const NoiseTypeInterval interval = IntervalForNoiseType(options, ids[k].alpha, table.m[k],
                                                              table.count[k], n, table.sigma[k]);
      table.edf[k] = interval.edf;
      if (!(interval.edf > 0.0)) continue;
      table.edf_source[k] = EdfSource::kNoiseType;
      table.ci_low[k] = interval.ci_low;
      table.ci_high[k] = interval.ci_high;
    }
  }
  summary.taus = static_cast<long long>(rows);
  summary.termination = Termination::kSuccess;
  summary.message = std::string(ToString(options.deviation)) + " at " + std::to_string(rows) +
                    " averaging factors of " + std::to_string(n) + " samples";
  return result;
}

}  // namespace fogpipe::allan
