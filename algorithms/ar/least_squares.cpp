#include "algorithms/ar/least_squares.h"

#include <Eigen/Dense>
#include <algorithm>

namespace fogpipe::ar {
namespace {

constexpr Eigen::Index kRowsPerBlock = 512;

}  // namespace

Eigen::MatrixXd LaggedTriangularFactor(const Eigen::Ref<const Eigen::VectorXd>& x, int order) {
  const Eigen::Index n = x.size();
  const Eigen::Index cols = order + 1;
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(cols, cols);
  Eigen::MatrixXd stacked(kRowsPerBlock + cols, cols);
  bool have_r = false;
  for (Eigen::Index t0 = order; t0 < n; t0 += kRowsPerBlock) {
    const Eigen::Index rows = std::min(kRowsPerBlock, n - t0);
    const Eigen::Index top = have_r ? cols : 0;
    stacked.resize(top + rows, cols);
    if (have_r) stacked.topRows(cols) = r;
    for (Eigen::Index i = 0; i < rows; ++i) {
      const Eigen::Index t = t0 + i;
      for (int j = 0; j < order; ++j) stacked(top + i, j) = x(t - 1 - j);
      stacked(top + i, order) = x(t);
    }
    Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(stacked);  // in place
    const Eigen::Index k = std::min(stacked.rows(), cols);
    r.setZero();
    r.topRows(k) = stacked.topRows(k).triangularView<Eigen::Upper>();
    have_r = true;
  }
  return r;
}

OrderSequence LeastSquaresAllOrders(const Eigen::Ref<const Eigen::VectorXd>& x_centered,
                                    int max_order) {
  OrderSequence out;
  const Eigen::Index n_eff = x_centered.size() - max_order;
  out.num_effective = n_eff;
  out.innovation_variance.setZero(max_order);
  if (n_eff <= max_order) return out;
  const Eigen::MatrixXd r = LaggedTriangularFactor(x_centered, max_order);
  const Eigen::VectorXd rhs = r.col(max_order);
  for (int p = 1; p <= max_order; ++p) {
    if (!(std::abs(r(p - 1, p - 1)) > 0.0)) break;  // rank deficient: stop
    Eigen::VectorXd phi = r.topLeftCorner(p, p).triangularView<Eigen::Upper>().solve(rhs.head(p));
    const double rss = rhs.segment(p, max_order + 1 - p).squaredNorm();
    if (!(rss > 0.0) || !phi.allFinite()) break;
    out.phi.push_back(phi);
    out.innovation_variance(p - 1) = rss / static_cast<double>(n_eff);
    out.orders_completed = p;
  }
  out.innovation_variance.conservativeResize(out.orders_completed);
  return out;
}

}  // namespace fogpipe::ar
