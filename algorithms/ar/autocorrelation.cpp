#include "algorithms/ar/autocorrelation.h"

#include <algorithm>

#include "algorithms/common/eigen_sums.h"

namespace fogpipe::ar {
namespace {

constexpr Eigen::Index kBlock = 2048;  // 16 KiB of x plus max_lag samples stay in L1.

}  // namespace

Eigen::VectorXd LaggedProducts(const Eigen::Ref<const Eigen::VectorXd>& x, int max_lag) {
  const Eigen::Index n = x.size();
  Eigen::VectorXd c = Eigen::VectorXd::Zero(max_lag + 1);
  for (Eigen::Index t0 = 0; t0 < n; t0 += kBlock) {
    const Eigen::Index t1 = std::min(n, t0 + kBlock);
    int k = 0;
    if (t1 + max_lag <= n) {
      // Every lag has the whole block: four lags at a time, each sum with the bits of its own
      // Eigen dot product (common/eigen_sums.h), the rest one by one below.
      const double* a = x.data() + t0;
      for (; k + 4 <= max_lag + 1; k += 4) {
        double sums[4];
        DotsWithEigensOrder<4>({a, a, a, a}, {a + k, a + k + 1, a + k + 2, a + k + 3}, t1 - t0,
                               sums);
        for (int j = 0; j < 4; ++j) c(k + j) += sums[j];
      }
    }
    for (; k <= max_lag; ++k) {
      // Terms t in [t0, t1) with t + k < N.
      const Eigen::Index end = std::min(t1, n - k);
      if (end <= t0) break;
      c(k) += x.segment(t0, end - t0).dot(x.segment(t0 + k, end - t0));
    }
  }
  return c;
}

}  // namespace fogpipe::ar
