#include "algorithms/kalman/companion.h"

#include "algorithms/kernels/lanes.h"

namespace fogpipe::kalman {

Eigen::MatrixXd CompanionMatrix(const Eigen::VectorXd& phi) {
  const Eigen::Index p = phi.size();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(p, p);
  if (p == 0) return a;
  a.row(0) = phi.transpose();
  for (Eigen::Index i = 1; i < p; ++i) a(i, i - 1) = 1.0;
  return a;
}

void PredictCovariance(const Eigen::MatrixXd& filtered, const Eigen::VectorXd& phi, double q,
                       Eigen::MatrixXd* predicted) {
  const Eigen::Index p = phi.size();
  Eigen::MatrixXd& out = *predicted;
  out.resize(p, p);
  // (A P A')(i, j) = P(i-1, j-1) for i, j >= 1: the old state shifted down by one lag.
  out.bottomRightCorner(p - 1, p - 1) = filtered.topLeftCorner(p - 1, p - 1);
  // Row 0: (A P A')(0, j) = (phi' P)(j-1) for j >= 1, and (0, 0) = phi' P phi.
  // Every multiply-add is spelled out (kernels::MulAdd) so that the fused step
  // kernels::CovarianceStep (algorithms/kernels/kernels.h), written the same way, gives the same
  // bits.
  using kernels::MulAdd;
  double top = 0.0;
  for (Eigen::Index j = 0; j < p; ++j) {
    double v = 0.0;
    for (Eigen::Index i = 0; i < p; ++i) v = MulAdd(phi[i], filtered(i, j), v);
    top = MulAdd(v, phi[j], top);
    if (j + 1 < p) {
      out(0, j + 1) = v;
      out(j + 1, 0) = v;
    }
  }
  out(0, 0) = top + q;
}

double JosephUpdate(const Eigen::MatrixXd& predicted, double r, Eigen::VectorXd* gain,
                    Eigen::MatrixXd* filtered) {
  const Eigen::Index p = predicted.rows();
  const double s = predicted(0, 0) + r;
  Eigen::VectorXd& g = *gain;
  g = predicted.col(0) / s;
  Eigen::MatrixXd& out = *filtered;
  out.resize(p, p);
  // The lower triangle column by column (contiguous), then mirrored: the same value per element.
  // P - G c' - c G' + S G G', each multiply-add spelled out (see PredictCovariance).
  using kernels::MulAdd;
  for (Eigen::Index j = 0; j < p; ++j) {
    const double cj = predicted(j, 0);
    for (Eigen::Index i = j; i < p; ++i) {
      const double t = MulAdd(-g[i], cj, predicted(i, j));
      out(i, j) = MulAdd(s * g[i], g[j], MulAdd(-predicted(i, 0), g[j], t));
    }
  }
  for (Eigen::Index j = 0; j < p; ++j) {
    for (Eigen::Index i = j + 1; i < p; ++i) out(j, i) = out(i, j);
  }
  return s;
}

}  // namespace fogpipe::kalman
