// Allan deviation engine: OADEV (default), ADEV, MDEV, TDEV, OHDEV, HDEV and TOTDEV of rate
// samples, with confidence intervals (IEEE Std 952-1997 Annex C; NIST SP 1065; Stable32
// conventions).
//
//   rate y (any unit) -> mean-removed cumulative sum (phase.h) -> finite differences at each
//   averaging factor (deviation.h) -> noise type by lag-1 ACF / B1 (noise_id.h) -> EDF (edf.h:
//   Greenhall; SP 1065 for TOTDEV) -> chi-square bounds sigma sqrt(edf / chi2)
//   (common/chi_square.h).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "algorithms/allan/deviation.h"
#include "algorithms/allan/noise_id.h"
#include "algorithms/allan/tau_grid.h"
#include "algorithms/common/status.h"

namespace fogpipe::allan {

struct AllanOptions {
  Deviation deviation = Deviation::kOverlappingAllan;
  TauGridOptions grid;  ///< Octave by default.
  /// Compute noise identification, EDF and confidence bounds (Stable32's Min/Max Sigma).
  bool confidence_intervals = true;
  /// Two-sided confidence level of [ci_low, ci_high]; 0.683 = one sigma, as Stable32.
  double confidence = 0.683;
  /// EDF convention (edf.h): true (default) = exact for phase sampled as the running sum of the
  /// rate, as a gyro's angle is; false = Greenhall & Riley as printed and as Stable32. They differ
  /// for white FM at m <= 33 by up to 17 % in EDF (up to ~8 % in bound width); on simulated white
  /// FM the printed convention's interval at m = 1 covers 63.0 % against 66.7 % for the sampled
  /// one (docs/allan-statistics.md). Stable32's bounds need false with NoiseIdRule::kStable32.
  bool sampled_phase_edf = true;
  /// Noise identification along the tau grid (noise_id.h): kCalibrated (default) is chosen by
  /// the measured coverage of the intervals; kStable32 reproduces Stable32's Alpha column.
  NoiseIdRule noise_id = NoiseIdRule::kCalibrated;
  /// Threads for the deviation sums (deviation.h); the numbers do not depend on it. Default 1:
  /// `run` already computes its tables side by side.
  int threads = 1;

  bool IsValid(std::string* error) const;
};

/// What a row's EDF (and so its interval) rests on.
enum class EdfSource {
  kNone,       ///< no EDF (intervals off, or no noise type)
  kNoiseType,  ///< Greenhall's EDF of the identified power law alpha (edf.h)
  kModel,      ///< the fitted noise model's Allan-variance covariance (model_edf.h)
};
const char* ToString(EdfSource source);  ///< "none", "noise_type", "model"
/// ToString of each source, for string columns.
std::vector<std::string> EdfSourceNames(const std::vector<EdfSource>& sources);

/// One row per averaging factor. sigma, ci_low and ci_high are in the unit of the input rate
/// (rad/s for fogpipe's gyro data).
struct AllanTable {
  std::vector<double> tau_s;    ///< Averaging time m / sample_rate_hz [s].
  std::vector<long long> m;     ///< Averaging factor.
  std::vector<double> sigma;    ///< Deviation [rate unit]; TDEV: [rate unit x s] (an angle).
  std::vector<double> ci_low;   ///< Lower bound sigma sqrt(edf / chi2_{(1+c)/2}) [rate unit].
  std::vector<double> ci_high;  ///< Upper bound sigma sqrt(edf / chi2_{(1-c)/2}) [rate unit].
  std::vector<double> edf;      ///< Equivalent degrees of freedom (Greenhall & Riley 2003).
  std::vector<int> alpha;       ///< Identified power-law exponent S_y ~ f^alpha (noise_id.h).
  std::vector<NoiseIdMethod> alpha_method;  ///< How alpha was identified (noise_id.h).
  std::vector<EdfSource> edf_source;        ///< What edf rests on.
  std::vector<long long> count;             ///< Number of difference terms (Stable32's "#").
  Deviation deviation = Deviation::kOverlappingAllan;
  NoiseIdRule noise_id_rule = NoiseIdRule::kCalibrated;  ///< the rule behind alpha

  size_t size() const { return tau_s.size(); }
};

struct AllanSummary {
  Termination termination = Termination::kSuccess;
  std::string message;
  long long samples = 0;  ///< Rate samples used.
  long long taus = 0;     ///< Rows in the table.
};

struct AllanResult {
  AllanTable table;
  AllanSummary summary;
};

/// Deviation of `rate` sampled at sample_rate_hz. Non-finite input gives kNumericalFailure; fewer
/// than 2 (Allan) or 3 (Hadamard) samples give kInsufficientData. When confidence intervals are
/// off, ci_low / ci_high / edf are NaN, alpha is 0, alpha_method and edf_source kNone. Every EDF
/// is that of the identified noise type; ApplyModelEdf (model_edf.h) replaces it with the fitted
/// model's where that model describes the curve.
/// The EDF and the confidence bounds ComputeAllan gives a row of `options.deviation` at factor m
/// (`count` differences of n rate samples, deviation sigma) whose noise type is alpha: chi-square
/// with the type's EDF, or under the calibrated rule for OADEV and OHDEV the estimate's own law
/// with few averages (estimate_law.h, phase_noise_law.h). edf is NaN or <= 0, and the bounds NaN,
/// where the type has no EDF there.
struct NoiseTypeInterval {
  double edf = std::numeric_limits<double>::quiet_NaN();
  double ci_low = std::numeric_limits<double>::quiet_NaN();   ///< Same unit as sigma.
  double ci_high = std::numeric_limits<double>::quiet_NaN();  ///< Same unit as sigma.
};
NoiseTypeInterval IntervalForNoiseType(const AllanOptions& options, int alpha, long long m,
                                       long long count, long long n, double sigma);

AllanResult ComputeAllan(const Eigen::Ref<const Eigen::VectorXd>& rate, double sample_rate_hz,
                         const AllanOptions& options);
/// The same table, with the phase (n + 1 doubles) formed in *phase_work, whose memory a caller
/// computing many tables of one length reuses (fresh pages are slow: docs/performance.md).
AllanResult ComputeAllan(const Eigen::Ref<const Eigen::VectorXd>& rate, double sample_rate_hz,
                         const AllanOptions& options, Eigen::VectorXd* phase_work);

/// Confidence bounds of a deviation `sigma` with `edf` degrees of freedom at two-sided level
/// `confidence` (NIST SP 1065 eq. 45; Stable32's convention sigma sqrt(edf / chi2)).
void ConfidenceBounds(double sigma, double edf, double confidence, double* low, double* high);
/// One of those bounds from its chi-square quantile q: sigma sqrt(edf / q).
double ChiSquareBound(double sigma, double edf, double quantile);

}  // namespace fogpipe::allan
