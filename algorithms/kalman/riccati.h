// Steady state of the AR(p) Kalman filter: the filtering discrete algebraic Riccati equation
//
//   P = A P A' - A P H' (H P H' + R)^-1 H P A' + Q                       (DARE)
//
// for the companion A = companion(phi), H = [1 0 ... 0], Q = diag(q, 0, ..., 0) and scalar R > 0.
// P is the steady a-priori covariance P(k|k-1) of the paper's eqs. 8-10 (docs/method.md).
//
// Solver: the structure-preserving doubling algorithm (SDA) of Chu, Fan, Lin & Wang (2004),
// "Structure-preserving algorithms for periodic discrete-time algebraic Riccati equations",
// Int. J. Control 77(8); convergence analysis in Lin & Xu (2006), SIAM J. Matrix Anal. Appl. 28(1).
// By the matrix inversion lemma the DARE is X = A X (I + G X)^-1 A' + Q with G = H' R^-1 H, and the
// SDA iterates
//   W_k = I + G_k H_k,
//   A_{k+1} = A_k W_k^-1 A_k,  G_{k+1} = G_k + A_k W_k^-1 G_k A_k',  H_{k+1} = H_k + A_k' H_k
//   W_k^-1 A_k
// from A_0 = A', G_0 = G, H_0 = Q. H_k equals the Riccati recursion after 2^k steps, so it
// converges quadratically to the stabilizing solution whenever one exists (the companion pair (A,
// H) is always observable and (A, sqrt(Q)) controllable for q > 0), including the near-unit-circle
// AR polynomials of the slow IMFs where the plain recursion needs thousands of steps. The equation
// is solved for R = 1 and Q = q / R (P scales with R), which keeps G_k and H_k of order one.
//
// Refinement: for the lightly damped slow-IMF models P is ill-conditioned (cond ~1e9 for imf6 at
// q/R = 1e-10) and the doubling result can be off by ~1e-7 relative. It is then polished by defect
// correction (Newton's method on the DARE, Hewer 1971; Mehrmann & Tan 1988): the Riccati map
// F(P) = A (I - G H) P A' + Q computed with the same structured O(p^2) step the time-varying filter
// uses has derivative D -> L D L', L = A (I - G H), so the correction D solves the Stein equation
// D - L D L' = F(P) - P (Smith's doubling). This lands on the fixed point of the filter's own
// arithmetic, which is what the time-varying gain converges to and what the switch compares with.
//
// Extended precision: the slow components of a long record (IMFs whose AR(p) roots cluster within
// 1e-3..1e-5 of z = 1, with q/R down to 1e-28) make the doubling's W_k = I + G_k H_k
// ill-conditioned to ~1e13 and beyond: in double the result can be off by 1e-2 relative, with a
// gain that does not even stabilize the loop (measured on a 1 h 100 Hz simulated recording: 9 of 16
// components; the exact solution, computed with 113-bit mpmath, is stabilizing). The doubling is
// then rerun once in long double (64-bit mantissa on x86: three more digits, which is what those
// cases need to land within reach of the Newton refinement above; 1e-7 residual before refinement
// in the case above).
#pragma once

#include <Eigen/Core>
#include <string>

#include "algorithms/common/status.h"

namespace fogpipe::kalman {

struct DareOptions {
  /// Doubling steps allowed; k steps cover 2^k steps of the Riccati recursion.
  int max_iterations = 64;
  /// Stop when ||H_{k+1} - H_k||_F <= relative_tolerance * ||H_{k+1}||_F.
  double relative_tolerance = 1e-15;
  /// Defect-correction steps after the doubling (stops early when the residual stops shrinking).
  int max_refinement_steps = 6;
  /// Rerun the doubling in the difference basis, then in long double, when the first result is not
  /// a stabilizing solution with a relative residual <= retry_residual. The best attempt is
  /// returned: a stabilizing one before one that is not, then the smallest residual.
  bool extended_precision_retry = true;
  double retry_residual = 1e-10;

  bool IsValid(std::string* error) const;
};

struct DareSummary {
  Termination termination = Termination::kInvalidOptions;
  std::string message;
  int iterations = 0;               ///< Doubling steps taken.
  int refinement_steps = 0;         ///< Defect-correction steps taken.
  bool difference_basis = false;    ///< The result comes from the difference-basis rerun.
  bool extended_precision = false;  ///< The result comes from the long double rerun.
  /// ||P - (A P A' - A P H'(H P H'+R)^-1 H P A' + Q)||_F / ||P||_F at the returned P.
  double relative_residual = 0.0;
  /// Spectral radius of the closed loop A (I - G H) (eigenvalues): < 1 for the stabilizing
  /// solution. It sets the filter's memory: errors decay like radius^k. A loop whose powers do not
  /// decay (e.g. q = 0 with a unit root, where the doubling returns P = 0) is reported as
  /// kNoConvergence.
  double closed_loop_spectral_radius = 0.0;
};

struct DareSolution {
  Eigen::MatrixXd predicted_covariance;  ///< P(k|k-1) in steady state, units of x^2.
  Eigen::MatrixXd filtered_covariance;   ///< P(k|k) = (I - G H) P(k|k-1), units of x^2.
  Eigen::VectorXd gain;                  ///< G = P H' / (H P H' + R), dimensionless.
  double innovation_variance = 0.0;      ///< S = H P H' + R, units of x^2.
  DareSummary summary;
};

/// Solves the DARE above. Requires phi non-empty and finite, q >= 0, r > 0 (else kInvalidOptions,
/// as data). kNoConvergence when the cap is hit (e.g. q = 0 with a unit root: no stabilizing
/// solution); the last iterate is returned and its residual reported.
DareSolution SolveDare(const Eigen::VectorXd& phi, double q, double r,
                       const DareOptions& options = DareOptions());

/// The closed loop A (I - G H) of a constant gain G.
Eigen::MatrixXd ClosedLoopMatrix(const Eigen::VectorXd& phi, const Eigen::VectorXd& gain);
/// Whether the constant-gain loop forgets its state: the powers of A (I - G H) decay (tested by
/// repeated squaring in the difference basis, see above).
bool IsStableLoop(const Eigen::VectorXd& phi, const Eigen::VectorXd& gain);

/// The relative Frobenius residual of the DARE at a given a-priori covariance P.
double DareRelativeResidual(const Eigen::VectorXd& phi, double q, double r,
                            const Eigen::MatrixXd& predicted_covariance);

}  // namespace fogpipe::kalman
