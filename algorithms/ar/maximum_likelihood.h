// Exact Gaussian maximum likelihood of a stationary AR(p), refined from a starting model (Burg).
//
// Likelihood (Box, Jenkins & Reinsel, sec. 7.4; Brockwell & Davis 1991, sec. 8.7): the first p
// values have the stationary covariance Gamma_p, the rest are one-step predictions, so with
// e_t = x_t - sum phi_i x_{t-i}, V_p = Gamma_p / sigma^2,
//   -2 ln L = N ln(2 pi sigma^2) + ln det V_p + S(phi) / sigma^2,
//   S(phi) = x_p' V_p^{-1} x_p + sum_{t=p}^{N-1} e_t^2,   x_p = (x_0, ..., x_{p-1}).
// Concentrated over sigma^2 (sigma^2 = S / N):
//   F = N ln(S / N) + ln det V_p   (+ N (1 + ln 2 pi)),   ln det V_p = -sum_m m ln(1 - kappa_m^2),
// the last identity from det Gamma_p = prod_{j<p} v_j with v_j the order-j prediction variance.
// The conditional part of S is evaluated as ||R [-phi; 1]||^2 from the QR factor R of the lagged
// matrix (least_squares.h), which never squares the condition number; the start part as a sum of
// non-negative Durbin-Levinson innovation terms. For the derivatives, V_p^{-1} is written as the
// Gohberg-Semencul matrix (ar_model.h), which makes S an exact quadratic in phi.
//
// Optimisation: Gauss-Newton on theta, kappa_m = tanh(theta_m), so every iterate is stationary
// (the partial-autocorrelation parameterisation, Jones 1980, Monahan 1984). The Hessian model is
// (N/S) J' (d^2 S / d phi^2) J + diag(2 m sech^2 theta_m), J = d phi / d theta through the Durbin
// step-up, with a backtracking line search on F. Stops when the predicted decrease of F (the
// Newton decrement, in units of -2 ln L) falls below `decrement_tolerance`.
//
// How much ML moves Burg: for long records the two agree to O(1/N) in phi, far inside the
// O(1/sqrt(N)) standard error. Measured in tests/algorithms/ar/maximum_likelihood_test.cpp:
// see the numbers quoted in fit_ar.h.
#pragma once

#include <Eigen/Core>

namespace fogpipe::ar {

struct MaximumLikelihoodOptions {
  /// Gauss-Newton iterations before giving up (kNoConvergence in FitAr).
  int max_iterations = 50;
  /// Converged when the Newton decrement g' H^{-1} g / 2 is below this (units of -2 ln L). A unit
  /// change of -2 ln L is a one-standard-error move of one parameter, so 1e-6 means the remaining
  /// step is ~0.001 standard errors; the rounding of F on long records (~1e-16 |F|, |F| ~ 1e8)
  /// makes much smaller tolerances unreachable.
  double decrement_tolerance = 1e-6;
};

struct MaximumLikelihoodResult {
  Eigen::VectorXd phi;             ///< Recursion coefficients at the optimum.
  double innovation_variance = 0;  ///< S(phi) / N, the concentrated ML estimate of sigma^2.
  double objective_start = 0;      ///< F at the starting model.
  double objective = 0;            ///< F at the returned model (F = -2 ln L - N (1 + ln 2 pi)).
  int iterations = 0;
  bool converged = false;
  bool valid = false;  ///< False if some |kappa_start| >= 1 or S was not positive.
};

/// Maximises the exact likelihood of `x_centered` (mean removed) over stationary AR(p),
/// p = kappa_start.size(), starting from the model with reflection coefficients kappa_start (all
/// |kappa| < 1; e.g. OrderSequence::reflection from Burg). Starting from the reflection
/// coefficients rather than phi matters on trends and the slowest IMFs: there the step-down of a
/// rounded phi can fail although Burg's kappa are all inside (-1, 1).
MaximumLikelihoodResult FitMaximumLikelihood(const Eigen::Ref<const Eigen::VectorXd>& x_centered,
                                             const Eigen::VectorXd& kappa_start,
                                             const MaximumLikelihoodOptions& options);

}  // namespace fogpipe::ar
