#include "algorithms/ar/ar_model.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "algorithms/ar/stationarity.h"

namespace fogpipe::ar {

Eigen::VectorXcd CharacteristicRoots(const Eigen::VectorXd& phi) {
  const Eigen::Index p = phi.size();
  if (p == 0) return Eigen::VectorXcd(0);
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(p, p);
  companion.row(0) = phi.transpose();
  for (Eigen::Index i = 1; i < p; ++i) companion(i, i - 1) = 1.0;
  Eigen::EigenSolver<Eigen::MatrixXd> solver(companion, /*computeEigenvectors=*/false);
  return solver.eigenvalues();
}

Eigen::MatrixXd ScaledInverseAutocovariance(const Eigen::VectorXd& phi) {
  const Eigen::Index p = phi.size();
  Eigen::VectorXd a(p + 1);  // A(z) = 1 + a_1 z + ... + a_p z^p, a_i = -phi_i.
  a(0) = 1.0;
  a.tail(p) = -phi;
  Eigen::MatrixXd l1 = Eigen::MatrixXd::Zero(p, p);
  Eigen::MatrixXd l2 = Eigen::MatrixXd::Zero(p, p);
  for (Eigen::Index i = 0; i < p; ++i) {
    for (Eigen::Index j = 0; j <= i; ++j) {
      l1(i, j) = a(i - j);
      l2(i, j) = a(p - (i - j));
    }
  }
  return l1 * l1.transpose() - l2 * l2.transpose();
}

ArModel MakeArModel(const Eigen::VectorXd& phi, double innovation_variance, double mean,
                    Eigen::Index num_samples) {
  ArModel model;
  model.order = static_cast<int>(phi.size());
  model.phi = phi;
  model.innovation_variance = innovation_variance;
  model.mean = mean;
  model.num_samples = num_samples;
  // MaxRootModulusAsStored is below 1 exactly when IsStationaryAsStored holds.
  model.max_root_modulus = MaxRootModulusAsStored(phi);
  model.stationary = model.max_root_modulus < 1.0;
  model.phi_std_error.setConstant(phi.size(), std::numeric_limits<double>::quiet_NaN());
  if (model.stationary && num_samples > 0) {
    const Eigen::VectorXd var =
        ScaledInverseAutocovariance(phi).diagonal() / static_cast<double>(num_samples);
    for (Eigen::Index i = 0; i < var.size(); ++i) {
      if (var(i) > 0.0) model.phi_std_error(i) = std::sqrt(var(i));
    }
  }
  return model;
}

}  // namespace fogpipe::ar
