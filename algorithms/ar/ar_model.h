// The fitted AR(p) model: coefficients, innovation variance, standard errors and stationarity.
//
// Sign convention (read this before comparing with MATLAB or the paper's Table 2):
//   phi holds the RECURSION coefficients of the mean-removed series,
//     x_k - mean = phi_1 (x_{k-1} - mean) + ... + phi_p (x_{k-p} - mean) + e_k,
//   e_k white with variance innovation_variance.
//   MATLAB's `ar`/`arburg` and the paper's Table 2 report the A(q) polynomial,
//     A(q) y = e,  A(q) = 1 + a_1 q^-1 + ... + a_p q^-p,   so  a_i = -phi_i   (MatlabA()).
#pragma once

#include <Eigen/Core>
#include <complex>

namespace fogpipe::ar {

struct ArModel {
  /// Model order p (number of coefficients).
  int order = 0;
  /// Recursion coefficients phi_1..phi_p (see the file comment). Size `order`.
  Eigen::VectorXd phi;
  /// Asymptotic standard error of each phi_i: sqrt(diag(sigma^2 Gamma_p^{-1} / N)), Gamma_p the
  /// p x p autocovariance matrix of the fitted model (Box, Jenkins & Reinsel, sec. 7.2.2; Brockwell
  /// & Davis 1991, Thm 8.1.1). Gamma_p^{-1} is taken in closed form from phi (Gohberg-Semencul), so
  /// no ill-conditioned matrix is inverted. NaN for a non-stationary model, where it is undefined.
  Eigen::VectorXd phi_std_error;
  /// Variance of the innovation e_k, in the squared units of x.
  double innovation_variance = 0.0;
  /// Mean removed from x before fitting, in the units of x.
  double mean = 0.0;
  /// Number of samples the model was fitted to (N of the standard errors).
  Eigen::Index num_samples = 0;
  /// True when every root of z^p - phi_1 z^{p-1} - ... - phi_p lies strictly inside the unit
  /// circle, for phi exactly as stored, decided in extended precision (stationarity.h).
  bool stationary = false;
  /// Largest modulus of those roots (stationarity.h). >= 1: not stationary.
  double max_root_modulus = 0.0;

  /// MATLAB's A(q) coefficients a_1..a_p = -phi (the paper's Table 2 convention).
  Eigen::VectorXd MatlabA() const { return -phi; }
};

/// Builds an ArModel from coefficients: fills order, stationarity, max root modulus and the
/// asymptotic standard errors for `num_samples` samples.
ArModel MakeArModel(const Eigen::VectorXd& phi, double innovation_variance, double mean,
                    Eigen::Index num_samples);

/// Roots of the characteristic polynomial z^p - phi_1 z^{p-1} - ... - phi_p, computed as the
/// eigenvalues of the companion matrix (its first row is phi, its subdiagonal ones).
Eigen::VectorXcd CharacteristicRoots(const Eigen::VectorXd& phi);

/// sigma^2 Gamma_p^{-1} for the stationary AR(p) model phi, by the Gohberg-Semencul formula
/// (Gohberg & Semencul 1972; Box, Jenkins & Reinsel, eq. A7.4.5):
///   sigma^2 Gamma_p^{-1} = L1 L1' - L2 L2',
/// L1, L2 lower-triangular Toeplitz with first columns (1, -phi_1, ..., -phi_{p-1}) and
/// (-phi_p, ..., -phi_1). Exact for a stationary model; meaningless otherwise.
Eigen::MatrixXd ScaledInverseAutocovariance(const Eigen::VectorXd& phi);

}  // namespace fogpipe::ar
