// Power-law noise identification at one averaging factor, for choosing the EDF of a variance
// estimate (NIST SP 1065 section 5.6; the same two-method scheme as Stable32).
//
//  - At least 30 averages: the lag-1 autocorrelation method of Riley & Greenhall, "Power law noise
//    identification using the lag 1 autocorrelation", EFTF 2004: the m-averaged frequency series is
//    differenced d times until rho = r1 / (1 + r1) < 0.25 (or d = dmax), then
//    alpha = -2 (rho + d), rounded.
//  - Fewer: the B1 bias ratio (Barnes 1969; Howe, Beard, Greenhall & Riley, PTTI 2000), the
//    N-sample variance of the N = n / m averages over the overlapping Allan variance at m, compared
//    with its expectation for each type (boundaries at geometric means), separates alpha = 0, -1,
//    -2 (and -3 for the Hadamard variance) from phase noise; phase noise is split into white
//    (alpha = 2) and flicker (alpha = 1) by R(n) = Mod AVAR / AVAR (NIST TN 1337, A-6).
//    Stable32 does not document its B1 variant; in the reference reports our types agree with
//    Stable32's in every row with >= 30 averages and in about half of the rows with fewer.
//
// The lag-1 method is one streaming pass over the m-averages computing the sums of all difference
// orders at once (no copies), so identification at m = 1 of 1e7 samples costs one read of them.
#pragma once

#include <Eigen/Core>
#include <limits>

namespace fogpipe::allan {

enum class NoiseIdMethod { kLag1Autocorrelation, kB1Ratio, kB1AndRn, kNone };

struct NoiseId {
  /// Power-law exponent of S_y(f) ~ f^alpha of the rate: 2 white PM (quantization), 1 flicker
  /// PM, 0 white FM (angle random walk), -1 flicker FM (bias instability), -2 random walk FM (rate
  /// random walk), -3, -4 (Hadamard only). Clamped to alpha >= 2 - 2 d.
  int alpha = 0;
  /// Unrounded estimate (lag-1 method only; NaN otherwise).
  double alpha_estimate = 0.0;
  NoiseIdMethod method = NoiseIdMethod::kNone;
};

/// Identifies the dominant noise at averaging factor m from `phase` (MeanRemovedPhase of the rate
/// samples, n + 1 points). d = 2 for Allan variances, 3 for Hadamard. Returns method kNone (and
/// alpha 0) when fewer than 4 averages exist.
///
/// `allan_variance_m` is the Allan variance at m in (phase units / m)^2, i.e. as returned by
/// DeviationVariances, for the B1 ratio's denominator; pass the overlapping one when the caller
/// has it. NaN (default) means: use the two-sample variance of the N averages themselves (Barnes'
/// textbook B1). Either way the cost is O(n / m) unless the R(n) step runs (phase noise at < 30
/// averages), which is O(n).
NoiseId IdentifyNoise(const Eigen::VectorXd& phase, long long m, int d,
                      double allan_variance_m = std::numeric_limits<double>::quiet_NaN());

}  // namespace fogpipe::allan
