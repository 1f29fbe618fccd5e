#include "algorithms/ar/maximum_likelihood.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/ar/least_squares.h"
#include "algorithms/ar/reflection.h"

namespace fogpipe::ar {
namespace {

constexpr double kStalledDecrement = 1e-3;

// ln cosh(t) without overflow: |t| + log1p(exp(-2|t|)) - ln 2.
double LogCosh(double t) {
  const double a = std::abs(t);
  return a + std::log1p(std::exp(-2.0 * a)) - std::log(2.0);
}

// S(phi) = ||R [-phi; 1]||^2 + ||u0 + U phi||^2 - ||V phi||^2, with the last two terms
// x_p' (L1 L1' - L2 L2') x_p written as linear maps of phi (see ScaledInverseAutocovariance).
struct SumOfSquares {
  Eigen::MatrixXd r;   // (p+1) x (p+1) lagged QR factor
  Eigen::VectorXd u0;  // L1' x_p at phi = 0
  Eigen::MatrixXd u;   // d(L1' x_p)/d phi
  Eigen::MatrixXd v;   // d(L2' x_p)/d phi  (L2' x_p is linear in phi, zero at phi = 0)

  SumOfSquares(const Eigen::Ref<const Eigen::VectorXd>& x, int p)
      : r(LaggedTriangularFactor(x, p)),
        u0(x.head(p)),
        u(Eigen::MatrixXd::Zero(p, p)),
        v(Eigen::MatrixXd::Zero(p, p)) {
    // (L1' x)_i = sum_{j>=i} a_{j-i} x_j, a_0 = 1, a_k = -phi_k.
    for (int i = 0; i < p; ++i)
      for (int k = 1; i + k <= p - 1; ++k) u(i, k - 1) = -x(i + k);
    // (L2' x)_i = sum_{j>=i} a_{p-(j-i)} x_j: coefficient a_k multiplies x_{i+p-k}, k = i+1..p.
    for (int i = 0; i < p; ++i)
      for (int k = i + 1; k <= p; ++k) v(i, k - 1) = -x(i + p - k);
  }

  Eigen::VectorXd Residual(const Eigen::VectorXd& phi) const {
    Eigen::VectorXd w(phi.size() + 1);
    w.head(phi.size()) = -phi;
    w(phi.size()) = 1.0;
    return r.triangularView<Eigen::Upper>() * w;
  }
  // The value uses the stable form below; this difference-of-squares form of the start term is
  // used for the derivatives only (it cancels badly when roots approach the unit circle).
  Eigen::VectorXd Gradient(const Eigen::VectorXd& phi) const {
    const Eigen::Index p = phi.size();
    return -2.0 * r.leftCols(p).transpose() * Residual(phi) + 2.0 * u.transpose() * (u0 + u * phi) -
           2.0 * v.transpose() * (v * phi);
  }
  Eigen::MatrixXd Hessian(Eigen::Index p) const {
    const Eigen::MatrixXd rp = r.leftCols(p);
    return 2.0 * (rp.transpose() * rp + u.transpose() * u - v.transpose() * v);
  }
};

// x_p' V_p^{-1} x_p = sum_{j<p} eps_j^2 prod_{k=j+1}^{p} (1 - kappa_k^2), eps_j the error of the
// order-j predictor of x_j from x_0..x_{j-1} (Durbin-Levinson innovations; Brockwell & Davis 1991,
// sec. 5.2). Every term is >= 0, so unlike ||L1' x_p||^2 - ||L2' x_p||^2 nothing cancels even with
// kappa_m -> +-1 (trends, the slowest IMFs). sech^2(theta) = 1 - kappa^2 without cancellation.
double StartQuadratic(const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::VectorXd& theta) {
  const Eigen::Index p = theta.size();
  Eigen::VectorXd sech2(p);
  for (Eigen::Index m = 0; m < p; ++m) sech2(m) = 1.0 / std::pow(std::cosh(theta(m)), 2);
  double total = 0.0;
  Eigen::VectorXd phi(0);  // order-j model
  for (Eigen::Index j = 0; j < p; ++j) {
    double eps = x(j);
    for (Eigen::Index i = 1; i <= j; ++i) eps -= phi(i - 1) * x(j - i);
    double weight = 1.0;
    for (Eigen::Index k = j; k < p; ++k) weight *= sech2(k);  // kappa_{j+1}..kappa_p
    total += weight * eps * eps;
    StepUpOnce(std::tanh(theta(j)), &phi);
  }
  return total;
}

// phi(theta) and J = d phi / d theta through kappa = tanh(theta) and the Durbin step-up.
void PhiAndJacobian(const Eigen::VectorXd& theta, Eigen::VectorXd* phi, Eigen::MatrixXd* jac) {
  const Eigen::Index p = theta.size();
  Eigen::VectorXd a(0);
  Eigen::MatrixXd d(0, p);  // d a / d kappa
  for (Eigen::Index m = 1; m <= p; ++m) {
    const double kappa = std::tanh(theta(m - 1));
    Eigen::VectorXd next(m);
    Eigen::MatrixXd dnext = Eigen::MatrixXd::Zero(m, p);
    for (Eigen::Index j = 0; j + 1 < m; ++j) {
      next(j) = a(j) - kappa * a(m - 2 - j);
      dnext.row(j) = d.row(j) - kappa * d.row(m - 2 - j);
      dnext(j, m - 1) -= a(m - 2 - j);
    }
    next(m - 1) = kappa;
    dnext(m - 1, m - 1) = 1.0;
    a.swap(next);
    d.swap(dnext);
  }
  for (Eigen::Index m = 0; m < p; ++m) {
    const double c = std::cosh(theta(m));
    d.col(m) /= c * c;  // d kappa / d theta = sech^2 theta
  }
  *phi = a;
  *jac = d;
}

}  // namespace

MaximumLikelihoodResult FitMaximumLikelihood(const Eigen::Ref<const Eigen::VectorXd>& x,
                                             const Eigen::VectorXd& kappa,
                                             const MaximumLikelihoodOptions& options) {
  MaximumLikelihoodResult out;
  const int p = static_cast<int>(kappa.size());
  const double n = static_cast<double>(x.size());
  if (p < 1 || x.size() <= 2 * p || !(kappa.array().abs() < 1.0).all()) return out;
  out.phi = StepUp(kappa);

  const SumOfSquares ss(x, p);
  const Eigen::MatrixXd hess_s = ss.Hessian(p);
  Eigen::VectorXd weight(p);  // m, the multiplicity of kappa_m in ln det V_p
  for (int m = 0; m < p; ++m) weight(m) = m + 1;

  auto objective = [&](const Eigen::VectorXd& theta, Eigen::VectorXd* phi_out, double* s_out) {
    Eigen::VectorXd phi;
    Eigen::MatrixXd jac;
    PhiAndJacobian(theta, &phi, &jac);
    const double s = ss.Residual(phi).squaredNorm() + StartQuadratic(x, theta);
    double logdet = 0.0;
    for (int m = 0; m < p; ++m) logdet += 2.0 * weight(m) * LogCosh(theta(m));
    if (phi_out) *phi_out = phi;
    if (s_out) *s_out = s;
    return s > 0.0 ? n * std::log(s / n) + logdet : std::numeric_limits<double>::infinity();
  };

  // Keep |kappa| strictly below 1 so atanh is finite.
  Eigen::VectorXd theta(p);
  for (int m = 0; m < p; ++m)
    theta(m) = std::atanh(std::clamp(kappa(m), -1.0 + 1e-15, 1.0 - 1e-15));
  Eigen::VectorXd phi;
  double s = 0.0;
  double f = objective(theta, &phi, &s);
  if (!std::isfinite(f)) return out;
  out.objective_start = f;
  out.valid = true;

  for (int iter = 0; iter < options.max_iterations; ++iter) {
    Eigen::VectorXd phi_now;
    Eigen::MatrixXd jac;
    PhiAndJacobian(theta, &phi_now, &jac);
    const Eigen::VectorXd grad_phi = ss.Gradient(phi_now);
    Eigen::VectorXd g = (n / s) * jac.transpose() * grad_phi;
    Eigen::MatrixXd h = (n / s) * jac.transpose() * hess_s * jac;
    for (int m = 0; m < p; ++m) {
      const double tk = std::tanh(theta(m));
      g(m) += 2.0 * weight(m) * tk;
      h(m, m) += 2.0 * weight(m) * (1.0 - tk * tk);
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(h);
    const Eigen::VectorXd step = ldlt.solve(g);
    const double decrement = 0.5 * g.dot(step);
    out.iterations = iter + 1;
    if (!step.allFinite() || !(decrement >= 0.0)) break;
    if (decrement < options.decrement_tolerance) {
      out.converged = true;
      break;
    }
    // Backtracking (Armijo) on F.
    double alpha = 1.0;
    bool moved = false;
    for (int ls = 0; ls < 40; ++ls) {
      const Eigen::VectorXd trial = theta - alpha * step;
      Eigen::VectorXd phi_trial;
      double s_trial = 0.0;
      const double f_trial = objective(trial, &phi_trial, &s_trial);
      if (f_trial < f - 1e-4 * alpha * 2.0 * decrement) {  // strict: equal F is no progress
        theta = trial;
        phi = phi_trial;
        s = s_trial;
        f = f_trial;
        moved = true;
        break;
      }
      alpha *= 0.5;
    }
    if (!moved) {
      // F cannot be lowered beyond its rounding (~1e-16 |F|, |F| up to ~1e8 for 1e7 samples).
      // A remaining decrement below 1e-3 moves each parameter by under ~0.05 of its standard
      // error (a unit change of -2 ln L is a one-sigma shift), so that still counts as converged.
      out.converged = decrement < kStalledDecrement;
      break;
    }
  }
  out.phi = phi;
  out.innovation_variance = s / n;
  out.objective = f;
  return out;
}

}  // namespace fogpipe::ar
