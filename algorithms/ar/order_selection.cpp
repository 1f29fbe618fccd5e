#include "algorithms/ar/order_selection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace fogpipe::ar {

Eigen::VectorXd Bic(const Eigen::VectorXd& innovation_variance, Eigen::Index num_effective) {
  const double n = static_cast<double>(num_effective);
  Eigen::VectorXd bic(innovation_variance.size());
  for (Eigen::Index i = 0; i < bic.size(); ++i) {
    const double s2 = innovation_variance(i);
    bic(i) = s2 > 0.0 ? n * std::log(s2) + static_cast<double>(i + 1) * std::log(n)
                      : std::numeric_limits<double>::infinity();
  }
  return bic;
}

int SelectOrderByBic(const Eigen::VectorXd& bic) {
  int best = 0;
  for (Eigen::Index i = 0; i < bic.size(); ++i) {
    if (best == 0 || bic(i) < bic(best - 1)) best = static_cast<int>(i + 1);
  }
  return best;
}

int SelectStationaryOrder(const Eigen::VectorXd& bic, int requested,
                          const std::function<bool(int)>& stationary) {
  const int top = static_cast<int>(bic.size());
  if (top == 0) return 0;
  if (requested > 0) {
    for (int q = std::min(requested, top); q >= 1; --q) {
      if (stationary(q)) return q;
    }
    return requested;
  }
  std::vector<int> orders(static_cast<std::size_t>(top));
  std::iota(orders.begin(), orders.end(), 1);
  // Best BIC first, the lower order on ties (as SelectOrderByBic); infinite BICs never qualify.
  std::stable_sort(orders.begin(), orders.end(),
                   [&bic](int a, int b) { return bic(a - 1) < bic(b - 1); });
  for (int q : orders) {
    if (std::isfinite(bic(q - 1)) && stationary(q)) return q;
  }
  return SelectOrderByBic(bic);
}

}  // namespace fogpipe::ar
