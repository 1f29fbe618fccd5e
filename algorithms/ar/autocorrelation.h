// Lagged products sum_t x_t x_{t+k}, the raw material of Yule-Walker and of the Ljung-Box test.
#pragma once

#include <Eigen/Core>

namespace fogpipe::ar {

/// c(k) = sum_{t=0}^{N-1-k} x_t x_{t+k} for k = 0..max_lag (0 where k >= N). One pass over x in
/// cache-sized blocks (all lags of a block are summed while the block is in cache), so the cost is
/// O(N max_lag) arithmetic but only one stream of x from memory. Block-wise partial sums also keep
/// the rounding error near eps * (block + N / block) instead of eps * N.
Eigen::VectorXd LaggedProducts(const Eigen::Ref<const Eigen::VectorXd>& x, int max_lag);

}  // namespace fogpipe::ar
