#include "algorithms/model/long_tau_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "algorithms/ar/diagnostics.h"
#include "algorithms/common/chi_square.h"
#include "algorithms/common/units.h"
#include "algorithms/model/spectrum.h"

namespace fogpipe::model {

double KurtosisNormalDeviate(double b2, int m) {
  const double n = m;
  const double mean = 3 * (n - 1) / (n + 1);
  const double variance = 24 * n * (n - 2) * (n - 3) / ((n + 1) * (n + 1) * (n + 3) * (n + 5));
  const double x = (b2 - mean) / std::sqrt(variance);
  const double root_beta1 = 6 * (n * n - 5 * n + 2) / ((n + 7) * (n + 9)) *
                            std::sqrt(6 * (n + 3) * (n + 5) / (n * (n - 2) * (n - 3)));
  const double a =
      6 + 8 / root_beta1 * (2 / root_beta1 + std::sqrt(1 + 4 / (root_beta1 * root_beta1)));
  const double denominator = 1 + x * std::sqrt(2 / (a - 4));
  const double cube = std::cbrt((1 - 2 / a) / denominator);
  return (1 - 2 / (9 * a) - cube) / std::sqrt(2 / (9 * a));
}

// P(Binomial(a + b - 1, x) >= a) (Abramowitz & Stegun 26.5.24), summed in logs.
double BetaCdf(double x, int a, int b) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  const int n = a + b - 1;
  const double log_n_factorial = std::lgamma(n + 1.0), log_x = std::log(x),
               log_1mx = std::log1p(-x);
  double sum = 0;
  for (int i = a; i <= n; ++i)
    sum += std::exp(log_n_factorial - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) + i * log_x +
                    (n - i) * log_1mx);
  return std::min(1.0, sum);
}

// Bisection to 2^-60.
double BetaQuantile(double p, int a, int b) {
  double lo = 0, hi = 1;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (BetaCdf(mid, a, b) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

bool WhitenedInnovations(const std::vector<double>& d, const std::vector<double>& gamma,
                         std::vector<double>* e) {
  const int m = static_cast<int>(d.size());
  e->assign(m, 0.0);
  std::vector<double> phi, previous;
  double v = gamma[0];
  if (!(v > 0)) return false;
  (*e)[0] = d[0] / std::sqrt(v);
  for (int t = 1; t < m; ++t) {
    double numerator = gamma[t];
    for (int i = 1; i < t; ++i) numerator -= phi[i - 1] * gamma[t - i];
    const double reflection = numerator / v;
    previous = phi;
    phi.resize(t);
    phi[t - 1] = reflection;
    for (int i = 1; i < t; ++i) phi[i - 1] = previous[i - 1] - reflection * previous[t - i - 1];
    v *= 1.0 - reflection * reflection;
    if (!(v > 1e-12 * gamma[0])) return false;
    double prediction = 0;
    for (int i = 1; i <= t; ++i) prediction += phi[i - 1] * d[t - i];
    (*e)[t] = (d[t] - prediction) / std::sqrt(v);
  }
  return true;
}

namespace {

struct Statistics {
  double jump = 0;  // largest |e_j - mean| / sd
  int jump_index = 0;
  double kurtosis_z = 0;
  double portmanteau = 0;
  double low_frequency = 0;
};

Statistics Compute(const std::vector<double>& e, int lags, int low_bins) {
  const int m = static_cast<int>(e.size());
  double mean = 0;
  for (double x : e) mean += x;
  mean /= m;
  std::vector<double> centred(m);
  for (int j = 0; j < m; ++j) centred[j] = e[j] - mean;
  double ss = 0;
  for (double x : centred) ss += x * x;
  Statistics s;
  const double sd = std::sqrt(ss / (m - 1));
  for (int j = 0; j < m; ++j) {
    const double g = std::abs(centred[j]) / sd;
    if (g > s.jump) {
      s.jump = g;
      s.jump_index = j;
    }
  }
  double fourth = 0;
  for (double x : centred) fourth += std::pow(x, 4);
  s.kurtosis_z = KurtosisNormalDeviate(m * fourth / (ss * ss), m);
  s.portmanteau = ar::LjungBox(Eigen::Map<const Eigen::VectorXd>(e.data(), m), lags, 0).statistic;
  // The share of the periodogram's first M = (m - 1) / 2 ordinates (k = 1 .. M: independent
  // exponentials for white e, the mean and the Nyquist ordinate left out) in the lowest J, over
  // J / M: 1 expected, (M / J) Beta(J, M - J) distributed.
  const std::vector<std::complex<double>> dft = RealDftHalf(centred);
  const int half = (m - 1) / 2;
  double low = 0, all = 0;
  for (int k = 1; k <= half; ++k) {
    all += std::norm(dft[k]);
    if (k <= low_bins) low += std::norm(dft[k]);
  }
  s.low_frequency = all > 0 ? (low / low_bins) / (all / half) : 1.0;
  return s;
}

// How far outside its band the low-frequency ratio is (1 on the edge), on a log scale.
double LowFrequencyExcess(const LongTauPoint& p) {
  const double ratio = std::max(p.low_frequency, 1e-300);
  return ratio < 1 ? std::log(ratio) / std::log(p.low_frequency_low)
                   : std::log(ratio) / std::log(p.low_frequency_high);
}

// The largest of the three statistics over its critical value.
double Excess(const LongTauPoint& p) {
  return std::max({p.kurtosis_z / p.kurtosis_critical, p.portmanteau / p.portmanteau_critical,
                   LowFrequencyExcess(p)});
}

}  // namespace

bool LongTauCheckOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* message) {
    if (error) *error = message;
    return false;
  };
  if (!(alpha > 0 && alpha < 1)) return fail("long_tau.alpha must be in (0, 1)");
  if (!(min_share > 0 && min_share <= 1)) return fail("long_tau.min_share must be in (0, 1]");
  // Anscombe & Glynn's kurtosis deviate is for 20 values or more.
  if (min_blocks < 21) return fail("long_tau.min_blocks must be >= 21");
  if (max_blocks < min_blocks) return fail("long_tau.max_blocks must be >= min_blocks");
  if (max_lags < 1) return fail("long_tau.max_lags must be >= 1");
  return true;
}

double AngleGeneralisedCovariance(const StochasticModel& model, double h) {
  double c = 0;
  if (model.Has(Term::kQuantization) && h == 0) c += model.q_rad * model.q_rad;
  if (model.Has(Term::kWhite)) c -= 0.5 * model.n_rad_sqrt_s * model.n_rad_sqrt_s * h;
  if (model.Has(Term::kBiasInstability) && h > 0)
    c += model.b_rad_s * model.b_rad_s * h * h * std::log(h) / (2 * units::kPi);
  if (model.Has(Term::kRateRandomWalk))
    c += model.k_rad_s_sqrt_s * model.k_rad_s_sqrt_s * h * h * h / 12.0;
  if (model.Has(Term::kGaussMarkov) && model.gm_correlation_time_s > 0) {
    const double tc = model.gm_correlation_time_s;
    // u - 1 + exp(-u) - u^2 / 2 (u = h / Tc): the quadratic part, which second differences
    // annihilate, is left out (a generalised covariance of order 1 is defined up to a + b h^2),
    // so that the u^3 term that remains is not lost to rounding at h << Tc.
    const double u = h / tc;
    double shape = 0;
    if (u < 0.5) {
      double term = -u * u * u / 6;
      for (int k = 3; k < 30 && term != 0; ++k) {
        shape += term;
        term *= -u / (k + 1);
      }
    } else {
      shape = u + std::expm1(-u) - u * u / 2;
    }
    c -= model.gm_sigma_rad_s * model.gm_sigma_rad_s * tc * tc * shape;
  }
  return c;
}

std::vector<double> BlockDifferenceAutocovariance(const StochasticModel& model, double tau,
                                                  int count) {
  static constexpr double a[3] = {1, -2, 1};
  std::vector<double> gamma(count, 0.0);
  const double ramp =
      model.Has(Term::kRateRamp) ? model.r_rad_s2 * model.r_rad_s2 * tau * tau : 0.0;
  // C at the lags 0 .. count + 1 (in units of tau), each evaluated once: gamma_k reads C at
  // |k + q - p| for p, q in 0..2.
  std::vector<double> c(count + 2);
  for (int j = 0; j < count + 2; ++j) c[j] = AngleGeneralisedCovariance(model, j * tau);
  for (int k = 0; k < count; ++k) {
    double sum = 0;
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) sum += a[p] * a[q] * c[std::abs(k + q - p)];
    gamma[k] = sum / (tau * tau) + ramp;
  }
  return gamma;
}

LongTauCheck CheckLongTauTerms(const Eigen::VectorXd& residual, double fs,
                               const StochasticModel& model, const LongTauCheckOptions& options) {
  LongTauCheck check;
  std::string err;
  if (!options.IsValid(&err) || !(fs > 0)) {
    check.message = fs > 0 ? err : "sample_rate_hz must be > 0";
    return check;
  }
  if (!options.enabled) {
    check.message = "not run";
    return check;
  }
  check.run = true;
  const Eigen::Index n = residual.size();
  if (!residual.allFinite()) {
    check.message = "not evaluated: the residual has non-finite samples";
    return check;
  }
  struct Candidate {
    Eigen::Index length;
    int blocks;
    double b, k, r, share;  // B, K, R Allan variances at tau, (rad/s)^2, and their share
  };
  std::vector<Candidate> candidates;
  for (Eigen::Index length = 1; n / length >= options.min_blocks; length *= 2) {
    if (n / length > options.max_blocks) continue;
    const int blocks = static_cast<int>(n / length);
    const double tau = static_cast<double>(length) / fs;
    const double total = ModelAllanVariance(model, tau);
    const double b = TermAllanVariance(model, Term::kBiasInstability, tau);
    const double k = TermAllanVariance(model, Term::kRateRandomWalk, tau);
    const double r = TermAllanVariance(model, Term::kRateRamp, tau);
    // The narrow bands are not in the increments' covariance (their Allan variance is negligible
    // at the long taus this check is for): a tau where they are not is skipped.
    const double bands = TermAllanVariance(model, Term::kNarrowBand, tau);
    if (total > 0 && b + k + r >= options.min_share * total && bands <= 0.01 * total)
      candidates.push_back({length, blocks, b, k, r, (b + k + r) / total});
  }
  if (candidates.empty()) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "not evaluated: bias instability, rate random walk and rate ramp carry less "
                  "than %.3g of the model's Allan variance at every tau with %d blocks or more",
                  options.min_share, options.min_blocks);
    check.message = text;
    check.nothing_to_absorb = true;
    return check;
  }
  // Three statistics per tau, one family.
  const double alpha = options.alpha / (3.0 * candidates.size());
  std::vector<double> d, e;
  for (const Candidate& candidate : candidates) {
    const double tau = static_cast<double>(candidate.length) / fs;
    std::vector<double> means(candidate.blocks);
    for (int j = 0; j < candidate.blocks; ++j)
      means[j] = residual.segment(j * candidate.length, candidate.length).mean();
    d.resize(candidate.blocks - 1);
    for (int j = 0; j + 1 < candidate.blocks; ++j) d[j] = means[j + 1] - means[j];
    const int m = static_cast<int>(d.size());
    const std::vector<double> gamma = BlockDifferenceAutocovariance(model, tau, m);
    if (!WhitenedInnovations(d, gamma, &e)) continue;
    LongTauPoint point;
    point.tau_s = tau;
    point.blocks = candidate.blocks;
    const double b = candidate.b, k = candidate.k, r = candidate.r;
    point.dominant_term = ToString(k >= b && k >= r ? Term::kRateRandomWalk
                                   : b >= r         ? Term::kBiasInstability
                                                    : Term::kRateRamp);
    point.share = candidate.share;
    point.lags = std::min(options.max_lags, std::max(2, m / 4));
    const int half = (m - 1) / 2;
    point.low_bins = std::min({16, std::max(2, m / 8), half - 1});
    const Statistics s = Compute(e, point.lags, point.low_bins);
    if (!std::isfinite(s.kurtosis_z) || !std::isfinite(s.portmanteau) ||
        !std::isfinite(s.low_frequency))
      continue;
    point.jump = s.jump;
    point.jump_time_s = (s.jump_index + 1) * tau;
    point.kurtosis_z = s.kurtosis_z;
    point.kurtosis_critical = UpperTailZ(alpha);
    point.portmanteau = s.portmanteau;
    point.portmanteau_critical = stats::ChiSquareQuantile(1.0 - alpha, point.lags);
    point.low_frequency = s.low_frequency;
    const double scale = static_cast<double>(half) / point.low_bins;
    point.low_frequency_level = 1.0 - alpha;
    point.low_frequency_low =
        scale * BetaQuantile(alpha / 2, point.low_bins, half - point.low_bins);
    point.low_frequency_high =
        scale * BetaQuantile(1.0 - alpha / 2, point.low_bins, half - point.low_bins);
    point.flagged = point.kurtosis_z > point.kurtosis_critical ||
                    point.portmanteau > point.portmanteau_critical ||
                    point.low_frequency < point.low_frequency_low ||
                    point.low_frequency > point.low_frequency_high;
    check.flagged = check.flagged || point.flagged;
    check.points.push_back(point);
  }
  if (check.points.empty()) {
    check.message =
        "not evaluated: the model's block-difference covariance is singular or the statistics "
        "are not finite";
    return check;
  }
  check.evaluated = true;
  const auto worst = std::max_element(
      check.points.begin(), check.points.end(),
      [](const LongTauPoint& x, const LongTauPoint& y) { return Excess(x) < Excess(y); });
  char text[400];
  const double from = check.points.front().tau_s, to = check.points.back().tau_s;
  if (!check.flagged) {
    std::snprintf(text, sizeof(text),
                  "the increments of the block means at tau %.4g-%.4g s behave as the fitted "
                  "noise predicts",
                  from, to);
  } else if (Excess(*worst) == worst->kurtosis_z / worst->kurtosis_critical) {
    std::snprintf(text, sizeof(text),
                  "%s may be absorbing a slow effect: the %.4g s block means move in jumps "
                  "(kurtosis z %.3g, critical %.3g under the fitted noise; the largest, %.3g "
                  "standard deviations, at %.5g s)",
                  worst->dominant_term.c_str(), worst->tau_s, worst->kurtosis_z,
                  worst->kurtosis_critical, worst->jump, worst->jump_time_s);
  } else if (Excess(*worst) == LowFrequencyExcess(*worst)) {
    std::snprintf(text, sizeof(text),
                  "%s may be absorbing a slow effect: the %.4g s block means %s (their "
                  "increments' power at the lowest %d frequencies is %.3g of the fitted noise's, "
                  "%.4g %% band %.3g-%.3g)",
                  worst->dominant_term.c_str(), worst->tau_s,
                  worst->low_frequency < 1
                      ? "return to their levels more than the fitted noise does"
                      : "drift more smoothly than the fitted noise does",
                  worst->low_bins, worst->low_frequency, 100 * worst->low_frequency_level,
                  worst->low_frequency_low, worst->low_frequency_high);
  } else {
    std::snprintf(text, sizeof(text),
                  "%s may be absorbing a slow effect: the increments of the %.4g s block means "
                  "are correlated (Ljung-Box %.3g over %d lags, critical %.3g under the fitted "
                  "noise)",
                  worst->dominant_term.c_str(), worst->tau_s, worst->portmanteau, worst->lags,
                  worst->portmanteau_critical);
  }
  check.message = text;
  return check;
}

}  // namespace fogpipe::model
