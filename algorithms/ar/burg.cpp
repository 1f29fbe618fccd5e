#include "algorithms/ar/burg.h"

#include <algorithm>
#include <cmath>

#include "algorithms/ar/autocorrelation.h"
#include "algorithms/ar/reflection.h"
#include "algorithms/common/eigen_sums.h"

namespace fogpipe::ar {
namespace {

// Block length of the fused update + sums: two blocks of 1024 doubles (16 KiB) stay in L1.
constexpr Eigen::Index kBlock = 1024;

}  // namespace

OrderSequence BurgAllOrders(const Eigen::Ref<const Eigen::VectorXd>& x, int max_order, double mean,
                            BurgWork* work) {
  const Eigen::Index n = x.size();
  OrderSequence out;
  out.num_effective = n;
  out.innovation_variance.setZero(max_order);
  out.reflection.setZero(max_order);
  if (n < 2 || max_order < 1) return out;

  // Layout after Collomb (2009): forward error of order m at time t is f[t] (t = m..N-1); backward
  // error of order m that predicts x_t from the m samples after it is b[t] (t = 0..N-1-m). Order m
  // pairs f[t + m + 1] with b[t], t = 0..N-m-2.
  BurgWork local;
  BurgWork& arrays = work != nullptr ? *work : local;
  Eigen::VectorXd& f = arrays.forward;
  Eigen::VectorXd& b = arrays.backward;
  f = x.array() - mean;
  b = f;
  double* fp = f.data();
  double* bp = b.data();

  double sigma2 = f.squaredNorm() / static_cast<double>(n);
  double num = f.tail(n - 1).dot(b.head(n - 1));
  double den = f.tail(n - 1).squaredNorm() + b.head(n - 1).squaredNorm();
  Eigen::VectorXd phi(0);

  for (int m = 0; m < max_order; ++m) {
    if (!(den > 0.0) || !std::isfinite(num) || !std::isfinite(den)) break;
    const double kappa = 2.0 * num / den;
    const double shrink = (1.0 - kappa) * (1.0 + kappa);  // 1 - kappa^2 without cancellation
    if (!(shrink > 0.0)) break;
    sigma2 *= shrink;
    if (!(sigma2 > 0.0)) break;
    StepUpOnce(kappa, &phi);
    out.phi.push_back(phi);
    out.innovation_variance(m) = sigma2;
    out.reflection(m) = kappa;
    out.orders_completed = m + 1;
    if (m + 1 == max_order) break;

    // Update order m -> m+1 and accumulate the sums of order m+1 (pairs fo[t + 1] * b[t]) block by
    // block, while the block is still in cache.
    const Eigen::Index len = n - m - 1;  // pairs of order m
    double* fo = fp + m + 1;
    double next_num = 0.0;
    double next_den = 0.0;
    for (Eigen::Index c0 = 0; c0 < len; c0 += kBlock) {
      const Eigen::Index c1 = std::min(len, c0 + kBlock);
      for (Eigen::Index t = c0; t < c1; ++t) {
        const double ft = fo[t];
        const double bt = bp[t];
        fo[t] = ft - kappa * bt;
        bp[t] = bt - kappa * ft;
      }
      const Eigen::Index s0 = std::max<Eigen::Index>(c0 - 1, 0);
      const Eigen::Index count = (c1 - 1) - s0;  // t = s0 .. c1-2
      if (count > 0) {
        // fs.dot(bs), fs.squaredNorm() and bs.squaredNorm() of the block's pairs in one pass.
        const double* fs = fo + s0 + 1;
        const double* bs = bp + s0;
        double sums[3];
        DotsWithEigensOrder<3>({fs, fs, bs}, {bs, fs, bs}, count, sums);
        next_num += sums[0];
        next_den += sums[1] + sums[2];
      }
    }
    num = next_num;
    den = next_den;
  }
  out.innovation_variance.conservativeResize(out.orders_completed);
  out.reflection.conservativeResize(out.orders_completed);
  return out;
}

OrderSequence BurgAllOrdersFromAutocorrelation(const Eigen::Ref<const Eigen::VectorXd>& x,
                                               int max_order) {
  const Eigen::Index n = x.size();
  OrderSequence out;
  out.num_effective = n;
  out.innovation_variance.setZero(max_order);
  if (max_order < 1 || n <= 2 * static_cast<Eigen::Index>(max_order) + 1) return out;
  const Eigen::VectorXd c = LaggedProducts(x, max_order + 1);
  double sigma2 = c(0) / static_cast<double>(n);
  Eigen::VectorXd a = Eigen::VectorXd::Ones(1);  // A(z) of the current order, a_0 = 1
  for (int k = 0; k < max_order; ++k) {
    // Phi(i, j) = sum_{t=k+1}^{N-1} x_{t-i} x_{t-j}, i, j = 0..k+1: c(d) minus the head products
    // (lower index 0..k-M) and the tail products (lower index N-M..N-1-d), M = max(i, j).
    const int s = k + 2;
    Eigen::MatrixXd phi_mat(s, s);
    for (int i = 0; i < s; ++i) {
      for (int j = i; j < s; ++j) {
        const int d = j - i;
        const int big = j;
        double v = c(d);
        for (int t = 0; t <= k - big; ++t) v -= x(t) * x(t + d);
        for (Eigen::Index t = n - big; t <= n - 1 - d; ++t) v -= x(t) * x(t + d);
        phi_mat(i, j) = phi_mat(j, i) = v;
      }
    }
    Eigen::VectorXd alpha = Eigen::VectorXd::Zero(s);
    Eigen::VectorXd beta = Eigen::VectorXd::Zero(s);
    alpha.head(k + 1) = a;
    beta.tail(k + 1) = a.reverse();
    const double num = alpha.dot(phi_mat * beta);
    const double den = alpha.dot(phi_mat * alpha) + beta.dot(phi_mat * beta);
    if (!(den > 0.0) || !std::isfinite(num)) break;
    const double kappa = 2.0 * num / den;
    const double shrink = (1.0 - kappa) * (1.0 + kappa);
    if (!(shrink > 0.0)) break;
    sigma2 *= shrink;
    if (!(sigma2 > 0.0)) break;
    a = alpha - kappa * beta;  // A_{k+1}(z) = A_k(z) - kappa z^{k+1} A_k(1/z)
    out.phi.push_back(-a.tail(k + 1));
    out.innovation_variance(k) = sigma2;
    out.reflection.conservativeResize(k + 1);
    out.reflection(k) = kappa;
    out.orders_completed = k + 1;
  }
  out.innovation_variance.conservativeResize(out.orders_completed);
  return out;
}

}  // namespace fogpipe::ar
