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
std::vector<std::complex<double>> StepDft(long n, long step_index, long half) {
  std::vector<std::complex<double>> dft(half);
  for (long k = 1; k < half; ++k) {
    const double phase = -2.0 * units::kPi * static_cast<double>(k) / n;
    const std::complex<double> z = std::polar(1.0, phase);
    dft[k] = (std::polar(1.0, phase * static_cast<double>(step_index)) - 1.0) / (1.0 - z);
  }
  return dft;
}

// DFT of x_i = rho^i: (1 - rho^n) / (1 - rho z).
std::vector<std::complex<double>> DecayDft(long n, double rho, long half) {
  std::vector<std::complex<double>> dft(half);
  const double rho_to_n = std::pow(rho, static_cast<double>(n));
  for (long k = 1; k < half; ++k) {
    const std::complex<double> z = std::polar(1.0, -2.0 * units::kPi * static_cast<double>(k) / n);
    dft[k] = (1.0 - rho_to_n) / (1.0 - rho * z);
  }
  return dft;
}

// Arc length of the unit Gauss-Markov score direction over log Tc in [lo, hi] (Davies 1987):
// the GM column of the Allan fit, weighted like the fit and projected off the model's columns.
double GaussMarkovArcLength(const std::vector<double>& tau, const std::vector<double>& weights,
                            const StochasticModel& model, double log_tc_low, double log_tc_high) {
  const long rows = static_cast<long>(tau.size());
  std::vector<Term> columns;  // the fitted columns (narrow bands are a fixed offset)
  for (Term term : model.terms)
    if (IsFittedOnAllan(term)) columns.push_back(term);
  const long num_terms = static_cast<long>(columns.size());
  Eigen::MatrixXd design(rows, num_terms);
  for (long i = 0; i < rows; ++i)
    for (long j = 0; j < num_terms; ++j)
      design(i, j) = weights[i] * UnitAllanLaw(columns[j], tau[i], 0.0);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(design);
  const Eigen::MatrixXd basis =
      qr.householderQ() * Eigen::MatrixXd::Identity(rows, std::min(rows, num_terms));
  constexpr int kGrid = 400;
  double length = 0;
  Eigen::VectorXd previous;
  for (int k = 0; k < kGrid; ++k) {
    const double correlation_time =
        std::exp(log_tc_low + (log_tc_high - log_tc_low) * k / (kGrid - 1));
    Eigen::VectorXd direction(rows);
    for (long i = 0; i < rows; ++i)
      direction[i] = weights[i] * UnitAllanLaw(Term::kGaussMarkov, tau[i], correlation_time);
    if (num_terms > 0) direction -= basis * (basis.transpose() * direction);
    const double norm = direction.norm();
    if (!(norm > 0)) continue;
    direction /= norm;
    if (previous.size() == direction.size()) length += (direction - previous).norm();
    previous = direction;
  }
  return length;
}

}  // namespace

StochasticModel RefitNoise(const Eigen::VectorXd& x, double fs, const StochasticModel& model,
                           const ViewOptions& options) {
  const AllanData allan = ResidualAllan(x, fs, options);
  StochasticFitOptions fit_options;
  fit_options.relative_floor = options.relative_floor;
  const StochasticFit fit = FitStochastic(allan.tau_s, allan.avar, allan.edf, fs, x.size() / fs,
                                          model.terms, fit_options, model.bands);
  return HasResult(fit.summary.termination) ? fit.model : model;
}

std::vector<std::complex<double>> MeanRemovedDft(const Eigen::VectorXd& x) {
  std::vector<double> in(x.size());
  const double mean = x.mean();
  for (long i = 0; i < x.size(); ++i) in[i] = x[i] - mean;
  return RealDftHalf(in);
}

std::vector<double> WhittleWeights(const StochasticModel& model, long n, double fs) {
  std::vector<double> weights(std::max(0L, n / 2), 0.0);  // bins 1 .. n/2 - 1 (no mean, no Nyquist)
  for (long k = 1; k < n / 2; ++k)
    weights[k] = n * fs * ModelOneSidedPsd(model, fs * k / n, fs) / 2.0;
  return weights;
}

// Score (Lagrange multiplier) test of "rate += c * x(t)" under the stochastic model, in the
// frequency domain (Whittle 1953): with R_k the DFT of the residual and X_k that of the regressor,
// E|R_k|^2 = w_k = n fs S(f_k) / 2 (S one-sided), U = sum_k Re(R_k conj X_k) / w_k has variance
// sum_k |X_k|^2 / (2 w_k), and z = U / sd(U) ~ N(0, 1). This is the generalised least-squares
// t-statistic of c with the noise covariance of the fitted model: coloured noise (bias
// instability, rate random walk) is down-weighted where the model says it is strong. With a
// nuisance regressor L: U = <R, X> - <R, L> <L, X> / <L, L>, variance (<X, X> - <L, X>^2 /
// <L, L>) / 2 (the efficient score; Cox & Hinkley 1974, 9.3).
double WhittleScoreZ(const std::vector<std::complex<double>>& series_dft,
                     const std::vector<std::complex<double>>& regressor_dft,
                     const std::vector<double>& weights,
                     const std::vector<std::complex<double>>* nuisance) {
  size_t num_bins = std::min({weights.size(), series_dft.size(), regressor_dft.size()});
  if (nuisance) num_bins = std::min(num_bins, nuisance->size());
  // <a, b> = sum_k Re(a_k conj b_k) / w_k: the GLS inner product (E|R_k|^2 = w_k); a score
  // <R, X> has variance <X, X> / 2.
  double rx = 0, xx = 0, rl = 0, lx = 0, ll = 0;
  for (size_t k = 1; k < num_bins; ++k) {
    if (!(weights[k] > 0)) continue;
    rx += (series_dft[k] * std::conj(regressor_dft[k])).real() / weights[k];
    xx += std::norm(regressor_dft[k]) / weights[k];
    if (nuisance) {
      const std::complex<double> l = (*nuisance)[k];
      rl += (series_dft[k] * std::conj(l)).real() / weights[k];
      lx += (l * std::conj(regressor_dft[k])).real() / weights[k];
      ll += std::norm(l) / weights[k];
    }
  }
  double score = rx, information = xx;
  if (nuisance && ll > 0) {
    score -= rl * lx / ll;
    information -= lx * lx / ll;
  }
  // A regressor that is (nearly) the nuisance itself, e.g. a channel ramping linearly through
  // the record, carries no information of its own: z = 0, not rounding noise.
  return information > 1e-8 * xx ? score / std::sqrt(information / 2.0) : 0.0;
}

std::vector<std::complex<double>> TrendDft(long n) {
  std::vector<std::complex<double>> dft(n / 2 + 1, 0.0);
  for (long k = 1; k <= n / 2; ++k)
    dft[k] = -static_cast<double>(n) /
             (1.0 - std::polar(1.0, -2.0 * units::kPi * static_cast<double>(k) / n));
  return dft;
}

double BridgeSupremumCritical(double alpha, double margin) {
  const double log_range = std::log((1.0 - margin) * (1.0 - margin) / (margin * margin));
  return InvertTail([&](double c) { return c * Phi(c) * log_range + 4.0 * Phi(c) / c; }, alpha);
}

double SmoothSupremumCritical(double alpha, double length, bool two_sided) {
  const double sides = two_sided ? 2.0 : 1.0;
  return InvertTail(
      [&](double c) {
        return sides * UpperTailP(c) + sides * length * std::exp(-0.5 * c * c) / (2.0 * units::kPi);
      },
      alpha);
}

TargetedTest ScanBiasStep(const Eigen::VectorXd& residual, double fs,
                          const std::vector<std::complex<double>>& residual_dft,
                          const StochasticModel& model, const ViewOptions& options, double alpha,
                          double window_s) {
  TargetedTest test;
  DeterministicOptions fit_options;
  fit_options.refinement_passes = 0;  // one component: nothing to coordinate
  const DeterministicFit fit =
      FitDeterministic(residual, fs, nullptr, {Term::kBiasStep}, fit_options);
  if (!HasResult(fit.summary.termination) || fit.model.components.empty()) return test;
  const DeterministicComponent& step = fit.model.components[0];
  const long n = residual.size();
  const long step_index =
      std::clamp(static_cast<long>(std::lround(step.nonlinear * fs)), 1L, n - 1);
  const StochasticModel alternative_noise = RefitNoise(fit.residual, fs, model, options);
  test.z = WhittleScoreZ(residual_dft, StepDft(n, step_index, n / 2),
                         WhittleWeights(alternative_noise, n, fs));
  test.critical = BridgeSupremumCritical(alpha, fit_options.step_margin_fraction);
  test.location = step.nonlinear;
  test.size = step.coefficients[0];
  const double half = std::max(window_s, 3.0 * step.nonlinear_se);
  test.from = std::max(0.0, step.nonlinear - half);
  test.to = std::min(n / fs, step.nonlinear + half);
  test.evaluated = true;
  return test;
}

TargetedTest ScanWarmup(const Eigen::VectorXd& residual, double fs,
                        const std::vector<std::complex<double>>& residual_dft,
                        const StochasticModel& model, const ViewOptions& options, double alpha) {
  TargetedTest test;
  DeterministicOptions fit_options;
  fit_options.refinement_passes = 0;
  const double record_s = residual.size() / fs;
  const double min_tau_s = std::max(fit_options.min_warmup_tau_s, 3.0 / fs),
               max_tau_s = record_s / 3.0;
  if (!(max_tau_s > min_tau_s)) return test;
  const DeterministicFit fit =
      FitDeterministic(residual, fs, nullptr, {Term::kWarmup}, fit_options);
  if (!HasResult(fit.summary.termination) || fit.model.components.empty()) return test;
  const DeterministicComponent& warmup = fit.model.components[0];
  const long n = residual.size();
  const StochasticModel alternative_noise = RefitNoise(fit.residual, fs, model, options);
  const double rho = std::exp(-1.0 / (fs * warmup.nonlinear));
  test.z = WhittleScoreZ(residual_dft, DecayDft(n, rho, n / 2),
                         WhittleWeights(alternative_noise, n, fs));
  // Arc length of the regressor family in log tau_w: sqrt(lambda_2) L = L / 2.
  test.critical = SmoothSupremumCritical(alpha, 0.5 * std::log(max_tau_s / min_tau_s), true);
  test.location = warmup.nonlinear;
  test.size = warmup.coefficients[0];
  test.from = 0.0;
  test.to = std::min(record_s, 3.0 * warmup.nonlinear);
  test.evaluated = true;
  return test;
}

TargetedTest ScanGaussMarkov(const AllanData& allan, double fs, double record_s,
                             const StochasticModel& model, const ViewOptions& options,
                             double alpha) {
  TargetedTest test;
  if (model.terms.empty() || model.Has(Term::kGaussMarkov)) return test;
  StochasticFitOptions fit_options;
  fit_options.relative_floor = options.relative_floor;
  std::vector<Term> with_gm = model.terms;
  with_gm.push_back(Term::kGaussMarkov);
  const StochasticFit fit_without = FitStochastic(allan.tau_s, allan.avar, allan.edf, fs, record_s,
                                                  model.terms, fit_options, model.bands);
  const StochasticFit fit_with = FitStochastic(allan.tau_s, allan.avar, allan.edf, fs, record_s,
                                               with_gm, fit_options, model.bands);
  if (!HasResult(fit_without.summary.termination) || !HasResult(fit_with.summary.termination))
    return test;
  // The same points and weights as the fit: 1 / sqrt((2 / edf + c^2)) / model.
  std::vector<double> tau, weights;
  const double tolerance_squared = options.relative_floor * options.relative_floor;
  for (size_t i = 0; i < allan.tau_s.size(); ++i) {
    if (!(allan.avar[i] > 0) || !std::isfinite(allan.avar[i])) continue;
    const double edf = std::isfinite(allan.edf[i]) && allan.edf[i] > 0 ? allan.edf[i] : 1.0;
    const double model_avar =
        std::max(ModelAllanVariance(fit_without.model, allan.tau_s[i]), 1e-6 * allan.avar[i]);
    tau.push_back(allan.tau_s[i]);
    weights.push_back(1.0 / (std::sqrt(2.0 / edf + tolerance_squared) * model_avar));
  }
  if (tau.size() < 3) return test;
  const double log_tc_low = std::log(fit_options.min_tc_factor / fs),
               log_tc_high = std::log(record_s / fit_options.max_tc_divisor);
  test.critical = SmoothSupremumCritical(
      alpha, GaussMarkovArcLength(tau, weights, fit_without.model, log_tc_low, log_tc_high), false);
  const double chi_square_drop = fit_without.summary.weighted_rss - fit_with.summary.weighted_rss;
  test.z =
      fit_with.model.gm_sigma_rad_s > 0 && chi_square_drop > 0 ? std::sqrt(chi_square_drop) : 0.0;
  test.location = fit_with.model.gm_correlation_time_s;
  test.size = fit_with.model.gm_sigma_rad_s;
  // Where the bump shows: the taus at which the GM law is above half its peak (near 1.89 Tc).
  const double correlation_time = test.location;
  if (correlation_time > 0) {
    const double peak = UnitAllanLaw(Term::kGaussMarkov, 1.89 * correlation_time, correlation_time);
    double half_low = 1.89 * correlation_time, half_high = 1.89 * correlation_time;
    while (half_low > 1e-3 * correlation_time &&
           UnitAllanLaw(Term::kGaussMarkov, half_low, correlation_time) > 0.5 * peak)
      half_low /= 1.02;
    while (half_high < 1e3 * correlation_time &&
           UnitAllanLaw(Term::kGaussMarkov, half_high, correlation_time) > 0.5 * peak)
      half_high *= 1.02;
    test.from = half_low;
    test.to = half_high;
  }
  test.evaluated = true;
  return test;
}

}  // namespace fogpipe::model
