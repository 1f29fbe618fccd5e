#include "algorithms/kalman/riccati.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>

#include "algorithms/kalman/companion.h"

namespace fogpipe::kalman {

bool DareOptions::IsValid(std::string* error) const {
  if (max_iterations < 1) {
    if (error) *error = "DareOptions::max_iterations must be >= 1";
    return false;
  }
  if (max_refinement_steps < 0) {
    if (error) *error = "DareOptions::max_refinement_steps must be >= 0";
    return false;
  }
  if (!(relative_tolerance >= 0.0) || !std::isfinite(relative_tolerance)) {
    if (error) *error = "DareOptions::relative_tolerance must be finite and >= 0";
    return false;
  }
  return true;
}

namespace {

// F(P) - P for one Riccati step (measurement update, then prediction); also returns the gain.
Eigen::MatrixXd RiccatiDefect(const Eigen::VectorXd& phi, double q, double r,
                              const Eigen::MatrixXd& predicted, Eigen::VectorXd* gain) {
  Eigen::MatrixXd filtered, next;
  JosephUpdate(predicted, r, gain, &filtered);
  PredictCovariance(filtered, phi, q, &next);
  return next - predicted;
}

double RelativeNorm(const Eigen::MatrixXd& defect, const Eigen::MatrixXd& p) {
  const double norm = p.norm();
  return norm > 0.0 ? defect.norm() / norm : defect.norm();
}

// Solves D - L D L' = C by Smith's doubling, D = sum_j L^j C L'^j. False if L is not stable.
bool SolveStein(Eigen::MatrixXd l, const Eigen::MatrixXd& c, Eigen::MatrixXd* d) {
  *d = c;
  for (int it = 0; it < 64; ++it) {
    const Eigen::MatrixXd next = *d + l * (*d) * l.transpose();
    l = (l * l).eval();
    const double change = (next - *d).norm();
    *d = next;
    if (!d->allFinite()) return false;
    if (change <= 1e-17 * d->norm()) return true;
  }
  return false;
}

// Defect correction on P (see riccati.h). Returns the number of accepted steps.
int Refine(const Eigen::VectorXd& phi, double q, double r, int max_steps, Eigen::MatrixXd* p) {
  const Eigen::Index n = phi.size();
  const Eigen::MatrixXd a = CompanionMatrix(phi);
  Eigen::VectorXd gain;
  Eigen::MatrixXd defect = RiccatiDefect(phi, q, r, *p, &gain);
  double residual = RelativeNorm(defect, *p);
  int accepted = 0;
  for (int step = 0; step < max_steps && residual > 0.0; ++step) {
    Eigen::MatrixXd l = a;
    l -= (a * gain) * Eigen::RowVectorXd::Unit(n, 0);  // A (I - G H)
    Eigen::MatrixXd correction;
    if (!SolveStein(l, defect, &correction)) break;
    Eigen::MatrixXd candidate = *p + correction;
    candidate = 0.5 * (candidate + candidate.transpose()).eval();
    Eigen::VectorXd candidate_gain;
    const Eigen::MatrixXd candidate_defect = RiccatiDefect(phi, q, r, candidate, &candidate_gain);
    const double candidate_residual = RelativeNorm(candidate_defect, candidate);
    if (!(candidate_residual < residual)) break;  // at the rounding floor
    *p = std::move(candidate);
    defect = candidate_defect;
    gain = candidate_gain;
    residual = candidate_residual;
    ++accepted;
  }
  return accepted;
}

}  // namespace

double DareRelativeResidual(const Eigen::VectorXd& phi, double q, double r,
                            const Eigen::MatrixXd& predicted_covariance) {
  Eigen::VectorXd gain;
  return RelativeNorm(RiccatiDefect(phi, q, r, predicted_covariance, &gain), predicted_covariance);
}

DareSolution SolveDare(const Eigen::VectorXd& phi, double q, double r, const DareOptions& options) {
  DareSolution out;
  std::string error;
  if (!options.IsValid(&error)) {
    out.summary.message = error;
    return out;
  }
  if (phi.size() == 0 || !phi.allFinite()) {
    out.summary.message = "phi must be non-empty and finite";
    return out;
  }
  if (!(q >= 0.0) || !std::isfinite(q) || !(r > 0.0) || !std::isfinite(r)) {
    out.summary.message = "need finite q >= 0 and r > 0";
    return out;
  }
  const Eigen::Index p = phi.size();
  const Eigen::MatrixXd a = CompanionMatrix(phi);

  // Normalised problem: R = 1, Q = q / r.
  Eigen::MatrixXd ak = a.transpose();
  Eigen::MatrixXd gk = Eigen::MatrixXd::Zero(p, p);
  gk(0, 0) = 1.0;
  Eigen::MatrixXd hk = Eigen::MatrixXd::Zero(p, p);
  hk(0, 0) = q / r;
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(p, p);

  bool converged = false;
  int iterations = 0;
  while (iterations < options.max_iterations) {
    ++iterations;
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(identity + gk * hk);
    const Eigen::MatrixXd winv_a = lu.solve(ak);
    const Eigen::MatrixXd winv_g = lu.solve(gk);
    Eigen::MatrixXd h_next = hk + ak.transpose() * hk * winv_a;
    Eigen::MatrixXd g_next = gk + ak * winv_g * ak.transpose();
    ak = ak * winv_a;
    // The exact iterates are symmetric; keep them so under rounding.
    h_next = 0.5 * (h_next + h_next.transpose()).eval();
    g_next = 0.5 * (g_next + g_next.transpose()).eval();
    if (!h_next.allFinite() || !g_next.allFinite() || !ak.allFinite()) {
      out.summary.termination = Termination::kNumericalFailure;
      out.summary.message = "non-finite doubling iterate";
      out.summary.iterations = iterations;
      return out;
    }
    const double change = (h_next - hk).norm();
    hk.swap(h_next);
    gk.swap(g_next);
    if (change <= options.relative_tolerance * hk.norm()) {
      converged = true;
      break;
    }
  }

  out.predicted_covariance = r * hk;
  out.summary.refinement_steps =
      Refine(phi, q, r, options.max_refinement_steps, &out.predicted_covariance);
  out.innovation_variance =
      JosephUpdate(out.predicted_covariance, r, &out.gain, &out.filtered_covariance);
  out.summary.iterations = iterations;
  out.summary.relative_residual = DareRelativeResidual(phi, q, r, out.predicted_covariance);
  Eigen::MatrixXd closed_loop = a;
  closed_loop -= (a * out.gain) * Eigen::RowVectorXd::Unit(p, 0);
  out.summary.closed_loop_spectral_radius =
      Eigen::EigenSolver<Eigen::MatrixXd>(closed_loop, false).eigenvalues().cwiseAbs().maxCoeff();
  if (converged && out.summary.closed_loop_spectral_radius < 1.0) {
    out.summary.termination = Termination::kSuccess;
    out.summary.message = "doubling converged";
  } else if (converged) {
    out.summary.termination = Termination::kNoConvergence;
    out.summary.message = "the solution is not stabilizing (closed-loop spectral radius >= 1)";
  } else {
    out.summary.termination = Termination::kNoConvergence;
    out.summary.message = "doubling hit max_iterations (no stabilizing solution?)";
  }
  return out;
}

}  // namespace fogpipe::kalman
