#include "algorithms/ar/order_selection.h"

#include <cmath>
#include <limits>

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

}  // namespace fogpipe::ar
