// Allan-type variances of rate samples as finite differences of the phase (NIST SP 1065, 5.2).
//
// With x the mean-removed phase (phase.h) in units of rate x tau0 and m the averaging factor
// (tau = m tau0), the d-th difference at lag m is
//   d = 2 (Allan):    D_i = x_{i+2m} - 2 x_{i+m} + x_i
//   d = 3 (Hadamard): D_i = x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i
// and the variance is  sum_i D_i^2 / (c_d m^2 count),  c_2 = 2, c_3 = 6  (SP 1065 eqs. 8, 10, 17,
// 19 with x in tau0 units). "Overlapping" takes every start i = 0, 1, ..., N - d m - 1 (N = n + 1
// phase points); the classic non-overlapping estimator takes i = 0, m, 2m, ....
#pragma once

#include <Eigen/Core>
#include <vector>

namespace fogpipe::allan {

enum class Deviation {
  kOverlappingAllan,     ///< OADEV (default): d = 2, all starts.
  kAllan,                ///< ADEV, non-overlapping: d = 2, starts every m.
  kOverlappingHadamard,  ///< OHDEV: d = 3, all starts. Blind to a constant rate ramp.
  kHadamard,             ///< HDEV, non-overlapping: d = 3, starts every m.
};

/// "oadev", "adev", "ohdev", "hdev".
const char* ToString(Deviation deviation);

/// 2 for the Allan variances, 3 for the Hadamard variance.
int DifferenceOrder(Deviation deviation);
/// True for the overlapping estimators.
bool IsOverlapping(Deviation deviation);

/// Largest averaging factor that keeps at least one difference term for n rate samples:
/// floor(n / d) (SP 1065: tau up to T/2 for the Allan variance, T/3 for the Hadamard variance).
long long MaxAveragingFactor(Deviation deviation, long long n_rate_samples);

/// Number of difference terms (Stable32's "#") for n rate samples and factor m; <= 0 if none.
long long DifferenceCount(Deviation deviation, long long n_rate_samples, long long m);

/// Variances sigma^2(m tau0), in (rate unit)^2, for each factor in `m` (each must be in
/// [1, MaxAveragingFactor]). `phase` is MeanRemovedPhase() of the rate samples.
///
/// Speed: the overlapping sums are computed in one sweep over cache-sized blocks of the phase,
/// every factor taking its share of each block while the block is hot (the short factors then
/// cost no memory traffic of their own); sums are vectorized Eigen reductions per block.
std::vector<double> DeviationVariances(const Eigen::VectorXd& phase, Deviation deviation,
                                       const std::vector<long long>& m);

}  // namespace fogpipe::allan
