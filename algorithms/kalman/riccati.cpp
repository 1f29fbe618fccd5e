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
  if (!(retry_residual >= 0.0) || !std::isfinite(retry_residual)) {
    if (error) *error = "DareOptions::retry_residual must be finite and >= 0";
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

namespace {

struct Doubled {
  Eigen::MatrixXd h;  ///< The doubling's P for R = 1, in double.
  int iterations = 0;
  bool converged = false;
  bool finite = true;
};

// The difference (delta-operator) basis of the companion state, Delta^i x(k) = sum_j (-1)^j C(i,j)
// x(k-j): T(i, j) = (-1)^j C(i, j). T is an involution (T T = I: x(k-i) = (1 - Delta)^i x(k)).
Eigen::MatrixXd DeltaBasis(Eigen::Index p) {
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(p, p);
  for (Eigen::Index i = 0; i < p; ++i) {
    double binomial = 1.0;  // C(i, j)
    for (Eigen::Index j = 0; j <= i; ++j) {
      t(i, j) = (j % 2 ? -1.0 : 1.0) * binomial;
      binomial = binomial * static_cast<double>(i - j) / static_cast<double>(j + 1);
    }
  }
  return t;
}

// The SDA iteration (see riccati.h) for R = 1, Q = diag(q_over_r, 0, ...), in Scalar arithmetic,
// in the companion basis or in the difference basis (A -> T A T^-1 = T A T, Q -> T Q T', H T^-1 =
// H); the returned P is in the companion basis.
template <typename Scalar>
Doubled Doubling(const Eigen::VectorXd& phi, double q_over_r, bool delta_basis,
                 const DareOptions& options) {
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  const Eigen::Index p = phi.size();
  const Eigen::MatrixXd t = delta_basis ? DeltaBasis(p) : Eigen::MatrixXd::Identity(p, p);
  Matrix ak = (t * CompanionMatrix(phi) * t).transpose().cast<Scalar>();
  Matrix gk = Matrix::Zero(p, p);
  gk(0, 0) = Scalar(1);
  // Q = q e1 e1' -> q (T e1)(T e1)'.
  const Eigen::VectorXd te1 = t.col(0);
  Matrix hk = (q_over_r * te1 * te1.transpose()).cast<Scalar>();
  const Matrix identity = Matrix::Identity(p, p);
  Doubled out;
  while (out.iterations < options.max_iterations) {
    ++out.iterations;
    const Eigen::PartialPivLU<Matrix> lu(identity + gk * hk);
    const Matrix winv_a = lu.solve(ak);
    const Matrix winv_g = lu.solve(gk);
    Matrix h_next = hk + ak.transpose() * hk * winv_a;
    Matrix g_next = gk + ak * winv_g * ak.transpose();
    ak = ak * winv_a;
    // The exact iterates are symmetric; keep them so under rounding.
    h_next = Scalar(0.5) * (h_next + h_next.transpose()).eval();
    g_next = Scalar(0.5) * (g_next + g_next.transpose()).eval();
    if (!h_next.allFinite() || !g_next.allFinite() || !ak.allFinite()) {
      out.finite = false;
      return out;
    }
    const Scalar change = (h_next - hk).norm();
    hk.swap(h_next);
    gk.swap(g_next);
    if (change <= Scalar(options.relative_tolerance) * hk.norm()) {
      out.converged = true;
      break;
    }
  }
  out.h = t * hk.template cast<double>() * t.transpose();
  return out;
}

// Whether the powers of m decay: squares m until its norm is below 1e-8 (stable), or non-finite,
// or 64 squarings (2^64 steps) have not brought it down. Unlike the eigenvalues, which for the
// clustered near-unit roots of slow components are only accurate to ~1e-5 (eps^(1/m) for an
// m-fold cluster), this measures what the loop does to its state. Squared in the companion basis
// and, if that does not show the decay, in the difference basis, where near-unit modes are well
// scaled (but whose binomial entries, up to C(p-1, (p-1)/2), make it poorly conditioned for high
// orders such as a direct AR(20)); rounding makes powers grow, not decay, so either showing the
// decay is evidence of stability.
bool PowersDecayIn(Eigen::MatrixXd power) {
  for (int it = 0; it < 64; ++it) {
    const double norm = power.norm();
    if (!std::isfinite(norm) || norm > 1e150) return false;
    if (norm < 1e-8) return true;
    power = (power * power).eval();
  }
  return false;
}

bool PowersDecay(const Eigen::MatrixXd& m) {
  if (PowersDecayIn(m)) return true;
  const Eigen::MatrixXd t = DeltaBasis(m.rows());
  return PowersDecayIn(t * m * t);
}

// Whether an attempt's solution is better than the best one so far: a result beats none, a
// stabilizing solution (kSuccess) beats one that is not, and between two of the same standing the
// smaller residual wins (a NaN residual loses); on a tie the earlier attempt is kept.
bool Better(const DareSummary& candidate, const DareSummary& best) {
  if (!HasResult(best.termination)) return HasResult(candidate.termination);
  const bool candidate_ok = candidate.termination == Termination::kSuccess;
  const bool best_ok = best.termination == Termination::kSuccess;
  if (candidate_ok != best_ok) return candidate_ok;
  if (std::isnan(best.relative_residual)) return !std::isnan(candidate.relative_residual);
  return candidate.relative_residual < best.relative_residual;
}

}  // namespace

Eigen::MatrixXd ClosedLoopMatrix(const Eigen::VectorXd& phi, const Eigen::VectorXd& gain) {
  const Eigen::MatrixXd a = CompanionMatrix(phi);
  Eigen::MatrixXd closed_loop = a;
  closed_loop -= (a * gain) * Eigen::RowVectorXd::Unit(a.rows(), 0);
  return closed_loop;
}

bool IsStableLoop(const Eigen::VectorXd& phi, const Eigen::VectorXd& gain) {
  return PowersDecay(ClosedLoopMatrix(phi, gain));
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

  // Normalised problem: R = 1, Q = q / r. First in double in the companion basis; if that does not
  // give a stabilizing solution at a small residual, in the difference basis, then in long double
  // (see riccati.h).
  for (int attempt = 0; attempt < 3; ++attempt) {
    const bool delta_basis = attempt >= 1, extended = attempt == 2;
    if (attempt > 0 && !options.extended_precision_retry) break;
    const Doubled d = extended ? Doubling<long double>(phi, q / r, delta_basis, options)
                               : Doubling<double>(phi, q / r, delta_basis, options);
    if (!d.finite) {
      if (attempt > 0) continue;
      out.summary.termination = Termination::kNumericalFailure;
      out.summary.message = "non-finite doubling iterate";
      out.summary.iterations = d.iterations;
      continue;
    }
    DareSolution candidate;
    candidate.predicted_covariance = r * d.h;
    candidate.summary.refinement_steps =
        Refine(phi, q, r, options.max_refinement_steps, &candidate.predicted_covariance);
    candidate.innovation_variance = JosephUpdate(candidate.predicted_covariance, r, &candidate.gain,
                                                 &candidate.filtered_covariance);
    candidate.summary.iterations = d.iterations;
    candidate.summary.extended_precision = extended;
    candidate.summary.difference_basis = delta_basis;
    candidate.summary.relative_residual =
        DareRelativeResidual(phi, q, r, candidate.predicted_covariance);
    const Eigen::MatrixXd closed_loop = ClosedLoopMatrix(phi, candidate.gain);
    candidate.summary.closed_loop_spectral_radius =
        Eigen::EigenSolver<Eigen::MatrixXd>(closed_loop, false).eigenvalues().cwiseAbs().maxCoeff();
    const bool stabilizing = PowersDecay(closed_loop);
    if (d.converged && stabilizing) {
      candidate.summary.termination = Termination::kSuccess;
      candidate.summary.message = "doubling converged";
    } else if (d.converged) {
      candidate.summary.termination = Termination::kNoConvergence;
      candidate.summary.message =
          "the solution is not stabilizing (the closed loop's powers do not decay)";
    } else {
      candidate.summary.termination = Termination::kNoConvergence;
      candidate.summary.message = "doubling hit max_iterations (no stabilizing solution?)";
    }
    if (delta_basis) candidate.summary.message += " (difference basis)";
    if (extended) candidate.summary.message += " (long double)";
    // A rerun can be worse than the attempt before it (e.g. the difference basis of a high-order,
    // well-damped model is poorly conditioned, PowersDecay above): keep the best attempt.
    if (Better(candidate.summary, out.summary)) out = std::move(candidate);
    if (out.summary.termination == Termination::kSuccess &&
        out.summary.relative_residual <= options.retry_residual)
      break;
  }
  return out;
}

}  // namespace fogpipe::kalman
