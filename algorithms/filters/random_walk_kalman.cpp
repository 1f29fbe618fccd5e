#include "algorithms/filters/random_walk_kalman.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "algorithms/filters/search.h"

namespace fogpipe::filters {
namespace {

/// The recursion with R = 1 and q = ratio. Returns sum e_k^2 / f_k and sets *sum_log_f; fills
/// filtered (when given) and gain (when given: the gains K_k = P_{k|k} until the steady state,
/// whose value is *steady_gain from index gain->size() on).
double RunFilter(const Eigen::VectorXd& y, double ratio, double* sum_log_f,
                 Eigen::VectorXd* filtered, std::vector<double>* gain, double* steady_gain) {
  const Eigen::Index n = y.size();
  double x = y[0], p = 1.0;
  if (filtered) (*filtered)[0] = x;
  if (gain) {
    // Room for every gain at once: at the small q/R of a static record the gain may not settle
    // within the record, and a growing vector would double past N (and copy). Pages not reached
    // are never touched.
    gain->reserve(static_cast<std::size_t>(n));
    gain->assign(1, p);
  }
  double sum_e2 = 0.0;
  // log prod f_k, with the product renormalised every 64 steps (f_k <= 2 + ratio).
  double product = 1.0;
  long long exponent = 0;
  Eigen::Index k = 1;
  for (; k < n; ++k) {
    const double pp = p + ratio;
    const double f = pp + 1.0;
    const double gain_k = pp / f;
    const double e = y[k] - x;
    sum_e2 += e * e / f;
    x += gain_k * e;
    if (filtered) (*filtered)[k] = x;
    product *= f;
    if ((k & 63) == 0) {
      int e2 = 0;
      product = std::frexp(product, &e2);
      exponent += e2;
    }
    const bool steady = std::abs(gain_k - p) <= 1e-15 * gain_k;
    p = gain_k;
    if (gain) gain->push_back(p);
    if (steady) {
      ++k;
      break;
    }
  }
  // Constant gain from here on: f and K no longer change in double precision.
  const double f = p + ratio + 1.0;
  const double gain_k = (p + ratio) / f;
  const double inv_f = 1.0 / f;
  double sum_e2_tail = 0.0;
  const Eigen::Index tail_start = k;
  for (; k < n; ++k) {
    const double e = y[k] - x;
    sum_e2_tail += e * e;
    x += gain_k * e;
    if (filtered) (*filtered)[k] = x;
  }
  if (steady_gain) *steady_gain = p;
  *sum_log_f = std::log(product) + exponent * std::log(2.0) +
               static_cast<double>(n - tail_start) * std::log(f);
  return sum_e2 + sum_e2_tail * inv_f;
}

/// RunFilter's return value and *sum_log_f (no outputs) for `lanes` (<= kLanes) ratios in one
/// walk: each lane does exactly RunFilter's operations in RunFilter's order.
constexpr int kLanes = 4;
void RunFilterLanes(const Eigen::VectorXd& y, const double* ratio, int lanes, double* s,
                    double* sum_log_f) {
  const Eigen::Index n = y.size();
  double x[kLanes], p[kLanes], sum_e2[kLanes], product[kLanes], f_tail[kLanes], gain_tail[kLanes],
      sum_e2_tail[kLanes];
  long long exponent[kLanes];
  Eigen::Index tail_start[kLanes];
  bool steady[kLanes];
  for (int l = 0; l < lanes; ++l) {
    x[l] = y[0];
    p[l] = 1.0;
    sum_e2[l] = 0.0;
    product[l] = 1.0;
    exponent[l] = 0;
    steady[l] = false;
    tail_start[l] = n;
    f_tail[l] = gain_tail[l] = sum_e2_tail[l] = 0.0;
  }
  for (Eigen::Index k = 1; k < n; ++k) {
    const double yk = y[k];
    for (int l = 0; l < lanes; ++l) {
      if (steady[l]) {
        const double e = yk - x[l];
        sum_e2_tail[l] += e * e;
        x[l] += gain_tail[l] * e;
        continue;
      }
      const double pp = p[l] + ratio[l];
      const double f = pp + 1.0;
      const double gain_k = pp / f;
      const double e = yk - x[l];
      sum_e2[l] += e * e / f;
      x[l] += gain_k * e;
      product[l] *= f;
      if ((k & 63) == 0) {
        int e2 = 0;
        product[l] = std::frexp(product[l], &e2);
        exponent[l] += e2;
      }
      steady[l] = std::abs(gain_k - p[l]) <= 1e-15 * gain_k;
      p[l] = gain_k;
      if (steady[l]) {
        tail_start[l] = k + 1;
        f_tail[l] = p[l] + ratio[l] + 1.0;
        gain_tail[l] = (p[l] + ratio[l]) / f_tail[l];
      }
    }
  }
  for (int l = 0; l < lanes; ++l) {
    // A lane that never settled ends as RunFilter's does: the constant gain from p, no tail.
    const double f = steady[l] ? f_tail[l] : p[l] + ratio[l] + 1.0;
    sum_log_f[l] = std::log(product[l]) + exponent[l] * std::log(2.0) +
                   static_cast<double>(n - tail_start[l]) * std::log(f);
    s[l] = sum_e2[l] + sum_e2_tail[l] * (1.0 / f);
  }
}

/// RunFilterLanes over `count` ratios, kLanes at a time: s[i] and sum_log_f[i] for ratios[i].
void RunFilterBatch(const Eigen::VectorXd& y, const double* ratios, int count, double* s,
                    double* sum_log_f) {
  for (int start = 0; start < count; start += kLanes) {
    RunFilterLanes(y, ratios + start, std::min(kLanes, count - start), s + start,
                   sum_log_f + start);
  }
}

double ProfileLikelihood(Eigen::Index n, double s, double sum_log_f, double* r_hat) {
  const double m = static_cast<double>(n - 1);
  const double r = s / m;
  if (r_hat) *r_hat = r;
  return -0.5 * m * std::log(r) - 0.5 * sum_log_f;
}

/// -2 ln L of the known-r model from the R = 1 recursion at lambda = q / r: the innovations are
/// the same and F_k = r f_k, so sum (log F_k + e_k^2 / F_k) = (N - 1) log r + sum log f_k + s / r.
double MinusTwoLogLikelihood(Eigen::Index n, double s, double sum_log_f, double r) {
  return static_cast<double>(n - 1) * std::log(r) + sum_log_f + s / r;
}

double MinusTwoLogLikelihoodAtRatio(const Eigen::VectorXd& y, double ratio, double r) {
  double sum_log_f = 0.0;
  const double s = RunFilter(y, ratio, &sum_log_f, nullptr, nullptr, nullptr);
  return MinusTwoLogLikelihood(y.size(), s, sum_log_f, r);
}

/// MinimizeRandomWalkMinusTwoLogLikelihood's golden-section stop (header).
constexpr double kWalkVarianceRelativeTolerance = 1e-3;

}  // namespace

bool RandomWalkKalmanOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* what) {
    if (error) *error = what;
    return false;
  };
  if ((q < 0.0) != (r < 0.0)) return fail("random-walk Kalman: give both q and r, or neither");
  if (r == 0.0) return fail("random-walk Kalman r must be > 0");
  if (!(min_ratio_times_n2 > 0.0) || !(max_ratio > 0.0))
    return fail("random-walk Kalman ratio bounds must be > 0");
  if (grid_points < 3) return fail("random-walk Kalman grid_points must be >= 3");
  if (!(relative_tolerance > 0.0)) return fail("random-walk Kalman relative_tolerance must be > 0");
  return true;
}

double RandomWalkProfileLikelihood(const Eigen::VectorXd& x, double ratio, double* r_hat) {
  double sum_log_f = 0.0;
  const double s = RunFilter(x, ratio, &sum_log_f, nullptr, nullptr, nullptr);
  return ProfileLikelihood(x.size(), s, sum_log_f, r_hat);
}

void RandomWalkProfileLikelihoods(const Eigen::VectorXd& x, const double* ratios, int count,
                                  double* values) {
  std::vector<double> s(count), sum_log_f(count);
  RunFilterBatch(x, ratios, count, s.data(), sum_log_f.data());
  for (int i = 0; i < count; ++i)
    values[i] = ProfileLikelihood(x.size(), s[i], sum_log_f[i], nullptr);
}

double RandomWalkMinusTwoLogLikelihood(const Eigen::VectorXd& y, double q, double r) {
  return MinusTwoLogLikelihoodAtRatio(y, q / r, r);
}

WalkVarianceFit MinimizeRandomWalkMinusTwoLogLikelihood(const Eigen::VectorXd& y, double r,
                                                        double min_ratio, double max_ratio) {
  const int grid_points =
      1 + std::max(2, static_cast<int>(std::lround(8.0 * std::log10(max_ratio / min_ratio))));
  const LogSearchResult best =
      MinimizeOnLogScale([&](double ratio) { return MinusTwoLogLikelihoodAtRatio(y, ratio, r); },
                         min_ratio, max_ratio, grid_points, kWalkVarianceRelativeTolerance,
                         [&](const double* ratios, int count, double* values) {
                           std::vector<double> s(count), sum_log_f(count);
                           RunFilterBatch(y, ratios, count, s.data(), sum_log_f.data());
                           for (int i = 0; i < count; ++i)
                             values[i] = MinusTwoLogLikelihood(y.size(), s[i], sum_log_f[i], r);
                         });
  WalkVarianceFit out;
  out.minus_two_log_likelihood = MinusTwoLogLikelihoodAtRatio(y, 0.0, r);
  if (best.value < out.minus_two_log_likelihood) {
    out.q = best.argument * r;
    out.minus_two_log_likelihood = best.value;
  }
  out.at_upper_bound = best.at_upper_bound;
  return out;
}

void RandomWalkFilterSmoother(const Eigen::VectorXd& x, double q, double r,
                              Eigen::VectorXd* filtered, Eigen::VectorXd* smoothed) {
  const double ratio = q / r;
  const Eigen::Index n = x.size();
  filtered->resize(n);
  std::vector<double> gain;
  double steady_gain = 0.0, sum_log_f = 0.0;
  RunFilter(x, ratio, &sum_log_f, filtered, &gain, &steady_gain);
  // RTS: x_{k|N} = x_{k|k} + C_k (x_{k+1|N} - x_{k+1|k}), x_{k+1|k} = x_{k|k},
  // C_k = P_{k|k} / (P_{k|k} + q), in units of R (P_{k|k} = K_k).
  *smoothed = *filtered;
  const auto stored = static_cast<Eigen::Index>(gain.size());
  for (Eigen::Index k = n - 2; k >= 0; --k) {
    const double p = k < stored ? gain[k] : steady_gain;
    const double c = p / (p + ratio);
    (*smoothed)[k] = (*filtered)[k] + c * ((*smoothed)[k + 1] - (*filtered)[k]);
  }
}

RandomWalkKalmanResult RandomWalkKalman(const Eigen::VectorXd& x,
                                        const RandomWalkKalmanOptions& options) {
  RandomWalkKalmanResult out;
  if (!options.IsValid(&out.message)) return out;
  const Eigen::Index n = x.size();
  if (n < 8) {
    out.termination = Termination::kInsufficientData;
    out.message = "random-walk Kalman: fewer than 8 samples";
    return out;
  }
  if (options.r > 0.0) {
    out.q = options.q;
    out.r = options.r;
  } else {
    const double nn = static_cast<double>(n);
    const double lo = options.min_ratio_times_n2 / (nn * nn);
    const LogSearchResult best =
        MinimizeOnLogScale([&](double ratio) { return -RandomWalkProfileLikelihood(x, ratio); }, lo,
                           options.max_ratio, options.grid_points, options.relative_tolerance,
                           [&](const double* ratios, int count, double* values) {
                             RandomWalkProfileLikelihoods(x, ratios, count, values);
                             for (int i = 0; i < count; ++i) values[i] = -values[i];
                           });
    out.log_likelihood = RandomWalkProfileLikelihood(x, best.argument, &out.r);
    out.q = best.argument * out.r;
    out.at_lower_bound = best.at_lower_bound;
  }
  if (!(out.r > 0.0) || !std::isfinite(out.q)) {
    out.termination = Termination::kNumericalFailure;
    out.message = "random-walk Kalman: no positive measurement variance (constant input?)";
    return out;
  }
  RandomWalkFilterSmoother(x, out.q, out.r, &out.filtered, &out.smoothed);
  out.termination = out.filtered.allFinite() && out.smoothed.allFinite()
                        ? Termination::kSuccess
                        : Termination::kNumericalFailure;
  if (!HasResult(out.termination)) out.message = "random-walk Kalman: non-finite output";
  return out;
}

}  // namespace fogpipe::filters
