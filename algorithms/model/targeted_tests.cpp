#include "algorithms/model/targeted_tests.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "algorithms/common/units.h"
#include "algorithms/model/deterministic_fit.h"
#include "algorithms/model/spectrum.h"

namespace fogpipe::model {
namespace {

double Phi(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * units::kPi); }

// Solves tail(c) = alpha for a decreasing tail on [0.5, 40] by bisection.
template <typename F>
double InvertTail(F tail, double alpha) {
  double lo = 0.5, hi = 40.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (tail(mid) > alpha ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// DFT of the step regressor x_i = 1{i >= k0}: sum_{i=k0}^{n-1} z^i = (z^k0 - 1) / (1 - z),
// z = exp(-2 pi i k / n) (z^n = 1). Bins 0 .. half - 1.
std::vector<std::complex<double>> StepDft(long n, long k0, long half) {
  std::vector<std::complex<double>> x(half);
  for (long k = 1; k < half; ++k) {
    const double w = -2.0 * units::kPi * static_cast<double>(k) / n;
    const std::complex<double> z = std::polar(1.0, w);
    x[k] = (std::polar(1.0, w * static_cast<double>(k0)) - 1.0) / (1.0 - z);
  }
  return x;
}

// DFT of x_i = rho^i: (1 - rho^n) / (1 - rho z).
std::vector<std::complex<double>> DecayDft(long n, double rho, long half) {
  std::vector<std::complex<double>> x(half);
  const double rn = std::pow(rho, static_cast<double>(n));
  for (long k = 1; k < half; ++k) {
    const std::complex<double> z = std::polar(1.0, -2.0 * units::kPi * static_cast<double>(k) / n);
    x[k] = (1.0 - rn) / (1.0 - rho * z);
  }
  return x;
}

// Arc length of the unit Gauss-Markov score direction over log Tc in [lo, hi] (Davies 1987):
// the GM column of the Allan fit, weighted like the fit and projected off the model's columns.
double GaussMarkovArcLength(const std::vector<double>& tau, const std::vector<double>& sw,
                            const StochasticModel& m, double lo, double hi) {
  const long rows = static_cast<long>(tau.size());
  const long p = static_cast<long>(m.terms.size());
  Eigen::MatrixXd a(rows, p);
  for (long i = 0; i < rows; ++i)
    for (long j = 0; j < p; ++j) a(i, j) = sw[i] * UnitAllanLaw(m.terms[j], tau[i], 0.0);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(rows, std::min(rows, p));
  constexpr int kGrid = 400;
  double length = 0;
  Eigen::VectorXd prev;
  for (int k = 0; k < kGrid; ++k) {
    const double tc = std::exp(lo + (hi - lo) * k / (kGrid - 1));
    Eigen::VectorXd g(rows);
    for (long i = 0; i < rows; ++i) g[i] = sw[i] * UnitAllanLaw(Term::kGaussMarkov, tau[i], tc);
    if (p > 0) g -= q * (q.transpose() * g);
    const double norm = g.norm();
    if (!(norm > 0)) continue;
    g /= norm;
    if (prev.size() == g.size()) length += (g - prev).norm();
    prev = g;
  }
  return length;
}

}  // namespace

StochasticModel RefitNoise(const Eigen::VectorXd& x, double fs, const StochasticModel& model,
                           const ViewOptions& o) {
  const AllanData a = ResidualAllan(x, fs, o);
  StochasticFitOptions so;
  so.relative_floor = o.relative_floor;
  const StochasticFit f = FitStochastic(a.tau_s, a.avar, a.edf, fs, x.size() / fs, model.terms, so);
  return HasResult(f.summary.termination) ? f.model : model;
}

std::vector<std::complex<double>> MeanRemovedDft(const Eigen::VectorXd& x) {
  std::vector<double> in(x.size());
  const double mean = x.mean();
  for (long i = 0; i < x.size(); ++i) in[i] = x[i] - mean;
  return RealDftHalf(in);
}

std::vector<double> WhittleWeights(const StochasticModel& m, long n, double fs) {
  std::vector<double> w(std::max(0L, n / 2), 0.0);  // bins 1 .. n/2 - 1 (no mean, no Nyquist)
  for (long k = 1; k < n / 2; ++k) w[k] = n * fs * ModelOneSidedPsd(m, fs * k / n, fs) / 2.0;
  return w;
}

// Score (Lagrange multiplier) test of "rate += c * x(t)" under the stochastic model, in the
// frequency domain (Whittle 1953): with R_k the DFT of the residual and X_k that of the regressor,
// E|R_k|^2 = w_k = n fs S(f_k) / 2 (S one-sided), U = sum_k Re(R_k conj X_k) / w_k has variance
// sum_k |X_k|^2 / (2 w_k), and z = U / sd(U) ~ N(0, 1). This is the generalised least-squares
// t-statistic of c with the noise covariance of the fitted model: coloured noise (bias
// instability, rate random walk) is down-weighted where the model says it is strong.
double WhittleScoreZ(const std::vector<std::complex<double>>& r_dft,
                     const std::vector<std::complex<double>>& xd, const std::vector<double>& w) {
  double u = 0, var = 0;
  const size_t m = std::min({w.size(), r_dft.size(), xd.size()});
  for (size_t k = 1; k < m; ++k) {
    if (!(w[k] > 0)) continue;
    u += (r_dft[k] * std::conj(xd[k])).real() / w[k];
    var += std::norm(xd[k]) / (2.0 * w[k]);
  }
  return var > 0 ? u / std::sqrt(var) : 0.0;
}

double BridgeSupremumCritical(double alpha, double margin) {
  const double len = std::log((1.0 - margin) * (1.0 - margin) / (margin * margin));
  return InvertTail([&](double c) { return c * Phi(c) * len + 4.0 * Phi(c) / c; }, alpha);
}

double SmoothSupremumCritical(double alpha, double length, bool two_sided) {
  const double k = two_sided ? 2.0 : 1.0;
  return InvertTail(
      [&](double c) {
        return k * UpperTailP(c) + k * length * std::exp(-0.5 * c * c) / (2.0 * units::kPi);
      },
      alpha);
}

TargetedTest ScanBiasStep(const Eigen::VectorXd& r, double fs,
                          const std::vector<std::complex<double>>& r_dft, const StochasticModel& m,
                          const ViewOptions& o, double alpha, double window_s) {
  TargetedTest t;
  DeterministicOptions d;
  d.refinement_passes = 0;  // one component: nothing to coordinate
  const DeterministicFit f = FitDeterministic(r, fs, nullptr, {Term::kBiasStep}, d);
  if (!HasResult(f.summary.termination) || f.model.components.empty()) return t;
  const DeterministicComponent& c = f.model.components[0];
  const long n = r.size();
  const long k0 = std::clamp(static_cast<long>(std::lround(c.nonlinear * fs)), 1L, n - 1);
  const StochasticModel alt = RefitNoise(f.residual, fs, m, o);
  t.z = WhittleScoreZ(r_dft, StepDft(n, k0, n / 2), WhittleWeights(alt, n, fs));
  t.critical = BridgeSupremumCritical(alpha, d.step_margin_fraction);
  t.location = c.nonlinear;
  t.size = c.coefficients[0];
  const double half = std::max(window_s, 3.0 * c.nonlinear_se);
  t.from = std::max(0.0, c.nonlinear - half);
  t.to = std::min(n / fs, c.nonlinear + half);
  t.evaluated = true;
  return t;
}

TargetedTest ScanWarmup(const Eigen::VectorXd& r, double fs,
                        const std::vector<std::complex<double>>& r_dft, const StochasticModel& m,
                        const ViewOptions& o, double alpha) {
  TargetedTest t;
  DeterministicOptions d;
  d.refinement_passes = 0;
  const double record = r.size() / fs;
  const double lo = std::max(d.min_warmup_tau_s, 3.0 / fs), hi = record / 3.0;
  if (!(hi > lo)) return t;
  const DeterministicFit f = FitDeterministic(r, fs, nullptr, {Term::kWarmup}, d);
  if (!HasResult(f.summary.termination) || f.model.components.empty()) return t;
  const DeterministicComponent& c = f.model.components[0];
  const long n = r.size();
  const StochasticModel alt = RefitNoise(f.residual, fs, m, o);
  const double rho = std::exp(-1.0 / (fs * c.nonlinear));
  t.z = WhittleScoreZ(r_dft, DecayDft(n, rho, n / 2), WhittleWeights(alt, n, fs));
  // Arc length of the regressor family in log tau_w: sqrt(lambda_2) L = L / 2.
  t.critical = SmoothSupremumCritical(alpha, 0.5 * std::log(hi / lo), true);
  t.location = c.nonlinear;
  t.size = c.coefficients[0];
  t.from = 0.0;
  t.to = std::min(record, 3.0 * c.nonlinear);
  t.evaluated = true;
  return t;
}

TargetedTest ScanGaussMarkov(const AllanData& allan, double fs, double record,
                             const StochasticModel& m, const ViewOptions& o, double alpha) {
  TargetedTest t;
  if (m.terms.empty() || m.Has(Term::kGaussMarkov)) return t;
  StochasticFitOptions so;
  so.relative_floor = o.relative_floor;
  std::vector<Term> with = m.terms;
  with.push_back(Term::kGaussMarkov);
  const StochasticFit f0 =
      FitStochastic(allan.tau_s, allan.avar, allan.edf, fs, record, m.terms, so);
  const StochasticFit f1 = FitStochastic(allan.tau_s, allan.avar, allan.edf, fs, record, with, so);
  if (!HasResult(f0.summary.termination) || !HasResult(f1.summary.termination)) return t;
  // The same points and weights as the fit: 1 / sqrt((2 / edf + c^2)) / model.
  std::vector<double> tau, sw;
  const double c2 = o.relative_floor * o.relative_floor;
  for (size_t i = 0; i < allan.tau_s.size(); ++i) {
    if (!(allan.avar[i] > 0) || !std::isfinite(allan.avar[i])) continue;
    const double edf = std::isfinite(allan.edf[i]) && allan.edf[i] > 0 ? allan.edf[i] : 1.0;
    const double model =
        std::max(ModelAllanVariance(f0.model, allan.tau_s[i]), 1e-6 * allan.avar[i]);
    tau.push_back(allan.tau_s[i]);
    sw.push_back(1.0 / (std::sqrt(2.0 / edf + c2) * model));
  }
  if (tau.size() < 3) return t;
  const double lo = std::log(so.min_tc_factor / fs), hi = std::log(record / so.max_tc_divisor);
  t.critical =
      SmoothSupremumCritical(alpha, GaussMarkovArcLength(tau, sw, f0.model, lo, hi), false);
  const double lr = f0.summary.weighted_rss - f1.summary.weighted_rss;
  t.z = f1.model.gm_sigma_rad_s > 0 && lr > 0 ? std::sqrt(lr) : 0.0;
  t.location = f1.model.gm_correlation_time_s;
  t.size = f1.model.gm_sigma_rad_s;
  // Where the bump shows: the taus at which the GM law is above half its peak (near 1.89 Tc).
  const double tc = t.location;
  if (tc > 0) {
    const double peak = UnitAllanLaw(Term::kGaussMarkov, 1.89 * tc, tc);
    double a = 1.89 * tc, b = 1.89 * tc;
    while (a > 1e-3 * tc && UnitAllanLaw(Term::kGaussMarkov, a, tc) > 0.5 * peak) a /= 1.02;
    while (b < 1e3 * tc && UnitAllanLaw(Term::kGaussMarkov, b, tc) > 0.5 * peak) b *= 1.02;
    t.from = a;
    t.to = b;
  }
  t.evaluated = true;
  return t;
}

}  // namespace fogpipe::model
