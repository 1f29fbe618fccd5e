#include "algorithms/ar/yule_walker.h"

#include "algorithms/ar/autocorrelation.h"
#include "algorithms/ar/reflection.h"

namespace fogpipe::ar {

OrderSequence LevinsonDurbin(const Eigen::VectorXd& r) {
  const int max_order = static_cast<int>(r.size()) - 1;
  OrderSequence out;
  out.innovation_variance.setZero(std::max(max_order, 0));
  Eigen::VectorXd phi(0);
  double v = r.size() > 0 ? r(0) : 0.0;
  for (int m = 1; m <= max_order; ++m) {
    if (!(v > 0.0)) break;
    double acc = r(m);
    for (int j = 1; j < m; ++j) acc -= phi(j - 1) * r(m - j);
    const double kappa = acc / v;
    const double shrink = (1.0 - kappa) * (1.0 + kappa);
    if (!(shrink > 0.0)) break;
    StepUpOnce(kappa, &phi);
    v *= shrink;
    if (!(v > 0.0)) break;
    out.phi.push_back(phi);
    out.innovation_variance(m - 1) = v;
    out.reflection.conservativeResize(m);
    out.reflection(m - 1) = kappa;
    out.orders_completed = m;
  }
  out.innovation_variance.conservativeResize(out.orders_completed);
  return out;
}

OrderSequence YuleWalkerAllOrders(const Eigen::Ref<const Eigen::VectorXd>& x_centered,
                                  int max_order) {
  const Eigen::Index n = x_centered.size();
  Eigen::VectorXd r = LaggedProducts(x_centered, max_order) / static_cast<double>(n);
  OrderSequence out = LevinsonDurbin(r);
  out.num_effective = n;
  return out;
}

}  // namespace fogpipe::ar
