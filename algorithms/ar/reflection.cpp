#include "algorithms/ar/reflection.h"

#include <cmath>

namespace fogpipe::ar {

void StepUpOnce(double kappa, Eigen::VectorXd* phi) {
  const Eigen::Index m = phi->size() + 1;
  Eigen::VectorXd next(m);
  for (Eigen::Index j = 0; j + 1 < m; ++j) next(j) = (*phi)(j)-kappa * (*phi)(m - 2 - j);
  next(m - 1) = kappa;
  phi->swap(next);
}

Eigen::VectorXd StepUp(const Eigen::Ref<const Eigen::VectorXd>& kappa) {
  Eigen::VectorXd phi(0);
  for (Eigen::Index m = 0; m < kappa.size(); ++m) StepUpOnce(kappa(m), &phi);
  return phi;
}

bool StepDown(const Eigen::Ref<const Eigen::VectorXd>& phi, Eigen::VectorXd* kappa) {
  const Eigen::Index p = phi.size();
  kappa->setZero(p);
  Eigen::VectorXd a = phi;
  for (Eigen::Index m = p; m >= 1; --m) {
    const double k = a(m - 1);
    (*kappa)(m - 1) = k;
    const double denom = 1.0 - k * k;
    if (!(std::abs(k) < 1.0) || !(denom > 0.0)) return false;
    // Inverse of phi_{m,j} = phi_{m-1,j} - k phi_{m-1,m-j}.
    Eigen::VectorXd prev(m - 1);
    for (Eigen::Index j = 0; j + 1 < m; ++j) prev(j) = (a(j) + k * a(m - 2 - j)) / denom;
    a.swap(prev);
  }
  return true;
}

}  // namespace fogpipe::ar
