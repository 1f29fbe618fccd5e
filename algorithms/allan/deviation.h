// Allan-type variances of rate samples as finite differences of the phase (NIST SP 1065, 5.2).
//
// With x the mean-removed phase (phase.h) in units of rate x tau0 and m the averaging factor
// (tau = m tau0), the d-th difference at lag m is
//   d = 2 (Allan):    D_i = x_{i+2m} - 2 x_{i+m} + x_i
//   d = 3 (Hadamard): D_i = x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i
// and the variance is  sum_i D_i^2 / (c_d m^2 count),  c_2 = 2, c_3 = 6  (SP 1065 eqs. 8, 10, 17,
// 19 with x in tau0 units). "Overlapping" takes every start i = 0, 1, ..., N - d m - 1 (N = n + 1
// phase points); the classic non-overlapping estimator takes i = 0, m, 2m, ....
//
// Modified Allan (SP 1065 eq. 14): the second difference of the phase averaged over m starts,
//   S_j = sum_{i=j}^{j+m-1} (x_{i+2m} - 2 x_{i+m} + x_i),   Mod sigma^2 = sum_j S_j^2 / (2 m^4
//   count),
// count = N - 3m + 1; TDEV^2 = tau^2 Mod sigma^2 / 3 (SP 1065 eq. 15), an angle for a gyro.
// Total (SP 1065 eq. 25): the overlapping Allan terms at every centre i = 1 .. N - 2 of the phase
// extended by odd reflection about both ends (x*_{-k} = 2 x_0 - x_k, x*_{N-1+k} = 2 x_{N-1} -
// x_{N-1-k}), divided by 2 m^2 (N - 2).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace fogpipe::allan {

enum class Deviation {
  kOverlappingAllan,     ///< OADEV (default): d = 2, all starts.
  kAllan,                ///< ADEV, non-overlapping: d = 2, starts every m.
  kOverlappingHadamard,  ///< OHDEV: d = 3, all starts. Blind to a constant rate ramp.
  kHadamard,             ///< HDEV, non-overlapping: d = 3, starts every m.
  kModifiedAllan,        ///< MDEV: d = 2 on m-averaged phase, all starts. Separates white PM.
  kTime,                 ///< TDEV = tau MDEV / sqrt(3): an angle (rate unit x s), not a rate.
  kTotal,                ///< TOTDEV: overlapping Allan on the doubly reflected phase.
};

/// Every kind, in the order the CLI lists them.
const std::vector<Deviation>& AllDeviations();

/// "oadev", "adev", "ohdev", "hdev", "mdev", "tdev", "totdev".
const char* ToString(Deviation deviation);
/// The inverse of ToString; false for any other text.
bool ParseDeviation(const std::string& text, Deviation* deviation);

/// 2 for the Allan-type variances (ADEV, OADEV, MDEV, TDEV, TOTDEV), 3 for the Hadamard ones:
/// the order of the phase difference, which also bounds the noise types it can measure
/// (alpha > 1 - 2 d) and is the d of noise identification and of Greenhall's EDF.
int DifferenceOrder(Deviation deviation);
/// True for the estimators that take every start (all but ADEV and HDEV).
bool IsOverlapping(Deviation deviation);
/// True for MDEV and TDEV (Greenhall's filter factor F = 1 instead of F = m).
bool IsModified(Deviation deviation);
/// True for TDEV, whose sigma is in rate unit x seconds (an angle for a gyro).
bool IsTimeDeviation(Deviation deviation);
/// True where the IEEE Std 952 Annex C terms (sigma^2 = 3 Q^2 / tau^2 + N^2 / tau + ...) describe
/// the variance: ADEV and OADEV only. The Hadamard, modified and total variances have other
/// responses to the same noises (e.g. Mod sigma^2 = 3 Q^2 / (... tau^3) for white PM).
bool IeeeModelApplies(Deviation deviation);

/// Largest averaging factor that keeps at least one difference term for n rate samples:
/// floor(n / 2) for ADEV / OADEV, floor(n / 3) for the Hadamard and modified variances (their
/// span is 3 m), floor((n - 1) / 2) for TOTDEV (SP 1065 / Stable32: tau up to T / 2).
long long MaxAveragingFactor(Deviation deviation, long long n_rate_samples);

/// Number of difference terms (Stable32's "#") for n rate samples and factor m; <= 0 if none.
long long DifferenceCount(Deviation deviation, long long n_rate_samples, long long m);

/// Variances sigma^2(m tau0), in (rate unit)^2, for each factor in `m` (each must be in
/// [1, MaxAveragingFactor]). `phase` is MeanRemovedPhase() of the rate samples.
///
/// For TDEV the values are (rate unit x tau0)^2: multiply the deviation by tau0 for seconds.
///
/// Speed: the overlapping sums are computed in one sweep over cache-sized blocks of the phase,
/// every factor taking its share of each block while the block is hot (the short factors then
/// cost no memory traffic of their own); sums are vectorized Eigen reductions per block.
/// MDEV / TDEV use the same sweep on a prefix sum of the phase (S_j above is its third difference
/// at lag m, O(1) per term whatever m), kept as an unevaluated double-double (hi + lo, 2 (N + 1)
/// doubles) so that the window sums P_{j+m} - P_j keep full precision however large P grows.
/// TOTDEV adds the 2 (m - 1) reflected terms at the ends to the overlapping Allan sweep.
/// `threads` > 1 shares fixed chunks of the sweep among that many threads; the chunks' sums are
/// added in a fixed order, so the values are the same for every thread count.
std::vector<double> DeviationVariances(const Eigen::VectorXd& phase, Deviation deviation,
                                       const std::vector<long long>& m, int threads = 1);

namespace internal {

/// out[k] = sum over starts j in [begin, begin + len) of the squared d-th difference of x at lag
/// m[k] (d = 2: x_{j+2m} - 2 x_{j+m} + x_j; d = 3: x_{j+3m} - 3 x_{j+2m} + 3 x_{j+m} - x_j), four
/// lags at once, each with the bits of the Eigen expression (x2 - 2.0 * x1 + x0).squaredNorm()
/// over the segments (x3 - 3.0 * x2 + 3.0 * x1 - x0 for d = 3; common/eigen_sums.h).
void OverlappingBlockSums4(const double* x, int d, const long long (&m)[4], Eigen::Index begin,
                           Eigen::Index len, double (&out)[4]);

}  // namespace internal

}  // namespace fogpipe::allan
