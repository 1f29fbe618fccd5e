// Mean-removed cumulative sum of rate samples ("phase" in time-and-frequency terms, angle for a
// gyro). Every Allan-type variance of rate data is a finite difference of this sequence
// (NIST SP 1065, eqs. 7-14), so it is computed once and shared by all averaging factors.
#pragma once

#include <Eigen/Core>

namespace fogpipe::allan {

/// x_0 = 0, x_{k+1} = x_k + (y_k - mean(y)), k = 0..n-1: n+1 values, in units of the rate times
/// one sample interval. The mean is removed first so that x stays O(sqrt(n)) for noise instead of
/// growing like n * mean (a gyro's bias is many times its noise); finite differences of order >= 1
/// of x are unchanged by it. The mean and the running sum are compensated (Kahan-Babuska-Neumaier
/// summation with Knuth's TwoSum; Neumaier 1974), so each stored x_k is within about one rounding
/// of the exact value even for 1e8 samples. Returns an empty vector for empty input.
Eigen::VectorXd MeanRemovedPhase(const Eigen::Ref<const Eigen::VectorXd>& rate);
/// The same values into *phase (resized to n + 1; its memory is reused when it already has that
/// size, so a caller computing many tables of one length touches no fresh pages).
void MeanRemovedPhase(const Eigen::Ref<const Eigen::VectorXd>& rate, Eigen::VectorXd* phase);

}  // namespace fogpipe::allan
