#include "algorithms/allan/allan.h"

#include <cmath>
#include <limits>

#include "algorithms/common/chi_square.h"
#include "algorithms/allan/edf.h"
#include "algorithms/allan/noise_id.h"
#include "algorithms/allan/phase.h"

namespace fogpipe::allan {

bool AllanOptions::IsValid(std::string* error) const {
  if (!grid.IsValid(error)) return false;
  if (!(confidence > 0.0 && confidence < 1.0)) {
    if (error) *error = "confidence must be in (0, 1)";
    return false;
  }
  return true;
}

void ConfidenceBounds(double sigma, double edf, double confidence, double* low, double* high) {
  const double tail = 0.5 * (1.0 - confidence);
  *low = sigma * std::sqrt(edf / stats::ChiSquareQuantile(1.0 - tail, edf));
  *high = sigma * std::sqrt(edf / stats::ChiSquareQuantile(tail, edf));
}

AllanResult ComputeAllan(const Eigen::Ref<const Eigen::VectorXd>& rate, double sample_rate_hz,
                         const AllanOptions& options) {
  AllanResult result;
  AllanSummary& summary = result.summary;
  AllanTable& table = result.table;
  table.deviation = options.deviation;
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
  table.m = AveragingFactors(options.grid, max_m);
  const Eigen::VectorXd phase = MeanRemovedPhase(rate);
  const std::vector<double> variance = DeviationVariances(phase, options.deviation, table.m);

  const size_t rows = table.m.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  table.tau_s.resize(rows);
  table.sigma.resize(rows);
  table.count.resize(rows);
  table.ci_low.assign(rows, nan);
  table.ci_high.assign(rows, nan);
  table.edf.assign(rows, nan);
  table.alpha.assign(rows, 0);
  const int d = DifferenceOrder(options.deviation);
  // B1's denominator (noise_id.h) is the overlapping Allan variance at m; it is only needed where
  // fewer than 30 averages exist. For OADEV it is the result itself; otherwise it is computed for
  // those few long factors in one extra blocked sweep.
  std::vector<double> b1_avar(rows, std::numeric_limits<double>::quiet_NaN());
  if (options.confidence_intervals) {
    if (options.deviation == Deviation::kOverlappingAllan) {
      b1_avar = variance;
    } else {
      std::vector<long long> few;
      std::vector<size_t> where;
      for (size_t k = 0; k < rows; ++k)
        if (n / table.m[k] < 30 &&
            table.m[k] <= MaxAveragingFactor(Deviation::kOverlappingAllan, n))
          few.push_back(table.m[k]), where.push_back(k);
      const std::vector<double> v = DeviationVariances(phase, Deviation::kOverlappingAllan, few);
      for (size_t i = 0; i < few.size(); ++i) b1_avar[where[i]] = v[i];
    }
  }
  int previous_alpha = 0;
  for (size_t k = 0; k < rows; ++k) {
    const long long m = table.m[k];
    table.tau_s[k] = static_cast<double>(m) / sample_rate_hz;
    // TDEV comes in rate x tau0 (deviation.h): tau0 = 1 / sample_rate_hz makes it rate x s.
    table.sigma[k] = std::sqrt(variance[k]) /
                     (IsTimeDeviation(options.deviation) ? sample_rate_hz : 1.0);
    table.count[k] = DifferenceCount(options.deviation, n, m);
    if (!options.confidence_intervals) continue;
    const NoiseId id = IdentifyNoise(phase, m, d, b1_avar[k]);
    // With too few averages to identify anything, keep the noise type of the shorter tau.
    const int alpha = id.method == NoiseIdMethod::kNone ? previous_alpha : id.alpha;
    previous_alpha = alpha;
    table.alpha[k] = alpha;
    table.edf[k] = DeviationEdf(options.deviation, alpha, m, n, options.sampled_phase_edf);
    if (table.edf[k] > 0.0)
      ConfidenceBounds(table.sigma[k], table.edf[k], options.confidence, &table.ci_low[k],
                       &table.ci_high[k]);
  }
  summary.taus = static_cast<long long>(rows);
  summary.termination = Termination::kSuccess;
  summary.message = std::string(ToString(options.deviation)) + " at " + std::to_string(rows) +
                    " averaging factors of " + std::to_string(n) + " samples";
  return result;
}

}  // namespace fogpipe::allan
