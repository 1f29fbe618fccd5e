#include "algorithms/ar/autocorrelation.h"

#include <algorithm>

namespace fogpipe::ar {
namespace {

constexpr Eigen::Index kBlock = 2048;  // 16 KiB of x plus max_lag samples stay in L1.

}  // namespace

Eigen::VectorXd LaggedProducts(const Eigen::Ref<const Eigen::VectorXd>& x, int max_lag) {
  const Eigen::Index n = x.size();
  Eigen::VectorXd c = Eigen::VectorXd::Zero(max_lag + 1);
  for (Eigen::Index t0 = 0; t0 < n; t0 += kBlock) {
    const Eigen::Index t1 = std::min(n, t0 + kBlock);
    for (int k = 0; k <= max_lag; ++k) {
      // Terms t in [t0, t1) with t + k < N.
      const Eigen::Index end = std::min(t1, n - k);
      if (end <= t0) break;
      c(k) += x.segment(t0, end - t0).dot(x.segment(t0 + k, end - t0));
    }
  }
  return c;
}

}  // namespace fogpipe::ar
