#include "algorithms/model/stochastic_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "algorithms/allan/avar_covariance.h"
#include "algorithms/allan/deviation.h"
#include "algorithms/allan/nnls.h"
#include "algorithms/allan/noise_model.h"
#include "algorithms/common/units.h"

namespace fogpipe::model {
namespace {

allan::Term AllanTerm(Term term) {
  switch (term) {
    case Term::kQuantization:
      return allan::Term::kQuantization;
    case Term::kWhite:
      return allan::Term::kAngleRandomWalk;
    case Term::kBiasInstability:
      return allan::Term::kBiasInstability;
    case Term::kRateRandomWalk:
      return allan::Term::kRateRandomWalk;
    case Term::kRateRamp:
      return allan::Term::kRateRamp;
    default:
      return allan::Term::kGaussMarkov;
  }
}

struct NnlsResult {
  Eigen::VectorXd coefficients;
  Eigen::VectorXd se;
  double cost = std::numeric_limits<double>::infinity();
};

// min ||W^1/2 (A c - b)||^2, c >= 0 (Lawson-Hanson, fogpipe::allan), columns scaled to unit norm.
// Standard errors from the weighted normal matrix on the free terms.
NnlsResult Nnls(const Eigen::MatrixXd& design, const Eigen::VectorXd& target,
                const Eigen::VectorXd& weights) {
  const long num_columns = design.cols();
  NnlsResult result;
  const Eigen::VectorXd sqrt_weights = weights.cwiseSqrt();
  const Eigen::MatrixXd weighted_design = sqrt_weights.asDiagonal() * design;
  const Eigen::VectorXd weighted_target = sqrt_weights.asDiagonal() * target;
  const Eigen::VectorXd column_scale =
      weighted_design.colwise().norm().cwiseMax(1e-300).cwiseInverse().transpose();
  const Eigen::MatrixXd scaled_design = weighted_design * column_scale.asDiagonal();
  const allan::NnlsResult solution = allan::SolveNnls(scaled_design, weighted_target);
  result.coefficients = column_scale.asDiagonal() * solution.x;
  result.se = Eigen::VectorXd::Zero(num_columns);
  result.cost = (weighted_design * result.coefficients - weighted_target).squaredNorm();
  std::vector<long> free;
  for (long j = 0; j < num_columns; ++j)
    if (solution.x[j] > 0) free.push_back(j);
  if (!free.empty()) {
    Eigen::MatrixXd free_design(scaled_design.rows(), free.size());
    for (size_t j = 0; j < free.size(); ++j) free_design.col(j) = scaled_design.col(free[j]);
    const Eigen::MatrixXd covariance =
        (free_design.transpose() * free_design)
            .ldlt()
            .solve(Eigen::MatrixXd::Identity(free.size(), free.size()));
    for (size_t j = 0; j < free.size(); ++j)
      result.se[free[j]] = column_scale[free[j]] * std::sqrt(std::max(covariance(j, j), 0.0));
  }
  return result;
}

struct Fitted {
  NnlsResult nnls;
  double tc = 0;
  Eigen::MatrixXd design;   // unit Allan laws at the fit's taus, one column per term
  Eigen::VectorXd weights;  // the last iteration's weights
  Eigen::VectorXd model;    // the fitted Allan variance, bands included
};

constexpr double kChiSquare1At95 = 3.841458820694124;  // chi-square(1) 0.95 quantile
constexpr double kNormal975 = 1.959963984540054;       // its square root

struct ProfileInterval {
  double low = 0, high = 0;  // log Tc
};

// The log-Tc range where the profiled cost is within `threshold` of its minimum (cost_min at
// log_tc_min), each edge found by bisection on `cost_at` between a point under the level and one
// above it: on the lower side the lowest grid point under the level (the minimum itself when no
// grid point below it is) and its grid neighbour below; the upper side alike. A profile with two
// valleys under the level gives the range that holds both. The grid's end where the cost never
// rises above the level before it. (Interpolating the grid instead makes the interval short: the
// cost is convex between grid points 0.36-0.49 apart in ln Tc, and with no grid point under the
// level the interval collapsed to Tc itself.)
template <typename CostAt>
ProfileInterval ProfileIntervalOf(const std::vector<double>& log_tc,
                                  const std::vector<double>& cost, double log_tc_min,
                                  double cost_min, double threshold, const CostAt& cost_at) {
  const double level = cost_min + threshold;
  const int n = static_cast<int>(log_tc.size());
  const auto edge = [&](double inside, double outside) {
    for (int iteration = 0; iteration < 12; ++iteration) {  // 2^-12 of a grid step
      const double middle = 0.5 * (inside + outside);
      (cost_at(middle) <= level ? inside : outside) = middle;
    }
    return 0.5 * (inside + outside);
  };
  // Grid points below and above the minimum: the outermost one under the level on each side,
  // and the innermost one on each side (the neighbour of the minimum).
  int lowest_under = -1, highest_under = -1, below = -1, above = -1;
  for (int i = 0; i < n; ++i) {
    if (log_tc[i] < log_tc_min) {
      below = i;
      if (lowest_under < 0 && cost[i] <= level) lowest_under = i;
    } else if (log_tc[i] > log_tc_min) {
      if (above < 0) above = i;
      if (cost[i] <= level) highest_under = i;
    }
  }
  ProfileInterval interval{log_tc_min, log_tc_min};
  if (lowest_under == 0 || (lowest_under < 0 && below < 0)) {
    interval.low = log_tc[0];
  } else if (lowest_under > 0) {
    interval.low = edge(log_tc[lowest_under], log_tc[lowest_under - 1]);
  } else {
    interval.low = edge(log_tc_min, log_tc[below]);
  }
  if (highest_under == n - 1 || (highest_under < 0 && above < 0)) {
    interval.high = log_tc[n - 1];
  } else if (highest_under >= 0) {
    interval.high = edge(log_tc[highest_under], log_tc[highest_under + 1]);
  } else {
    interval.high = edge(log_tc_min, log_tc[above]);
  }
  interval.low = std::min(interval.low, log_tc_min);
  interval.high = std::max(interval.high, log_tc_min);
  return interval;
}

Fitted FitAt(const std::vector<double>& tau, const Eigen::VectorXd& avar,
             const Eigen::VectorXd& offset, const Eigen::VectorXd& edf,
             const std::vector<Term>& terms, double correlation_time_s, double floor_squared) {
  const int rows = static_cast<int>(tau.size()), num_terms = static_cast<int>(terms.size());
  Eigen::MatrixXd design(rows, num_terms);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < num_terms; ++j)
      design(i, j) = UnitAllanLaw(terms[j], tau[i], correlation_time_s);
  // Relative variance of s2: 2 / edf + floor^2. Weights start from the data, then the model.
  Eigen::VectorXd model_avar = avar;
  const Eigen::VectorXd target = avar - offset;
  Fitted fitted;
  fitted.tc = correlation_time_s;
  for (int iteration = 0; iteration < 3; ++iteration) {
    Eigen::VectorXd weights(rows);
    for (int i = 0; i < rows; ++i) {
      const double model_value = std::max(model_avar[i], 1e-6 * avar[i]);
      weights[i] = 1.0 / ((2.0 / edf[i] + floor_squared) * model_value * model_value);
    }
    fitted.nnls = Nnls(design, target, weights);
    fitted.weights = weights;
    model_avar = design * fitted.nnls.coefficients + offset;
  }
  fitted.model = model_avar;
  fitted.design = std::move(design);
  return fitted;
}

// Averaging factors m = tau fs and difference counts n + 1 - 2m of the overlapping Allan
// variances behind `tau` (views.h ResidualAllan: integer factors of an n-sample record); false
// when tau is not on that grid.
bool OverlappingGrid(const std::vector<double>& tau, double fs, double record_s,
                     std::vector<long long>* m, std::vector<long long>* count) {
  const long long n = std::llround(record_s * fs);
  for (double t : tau) {
    const long long factor = std::llround(t * fs);
    const long long differences =
        allan::DifferenceCount(allan::Deviation::kOverlappingAllan, n, factor);
    if (factor < 1 || std::abs(t * fs - factor) > 1e-6 * factor || differences < 1) return false;
    m->push_back(factor);
    count->push_back(differences);
  }
  return true;
}

// Sandwich covariance of the Gauss-Markov fit's free parameters (the positive coefficients and,
// when sigma^2 > 0, log Tc), Huber (1967) / White (1980) for a weighted least-squares
// M-estimator: V = B^-1 X' W C W X B^-1 with B = X' W X, X the fit's Jacobian (the free columns
// and sigma^2 dg/dlog Tc), W its final weights and C the covariance of the Allan points: their
// sampling covariance under the fitted model (allan/avar_covariance.h, with its Gauss-Markov
// term; neighbouring overlapping points are strongly correlated, which W, diagonal, ignores) plus
// the weights' relative shape tolerance on the diagonal. Why a sandwich and not GLS: the point
// estimates stay those of the diagonal fit, which does not lean on C being right (GLS on nearly
// collinear Allan points follows the modelled correlations off the data where the model is
// rejected, cf. allan/noise_fit.cpp's discrepancy term), and C is built once, at the fitted Tc,
// where GLS would need it at every Tc of the search. The narrow bands are a fixed offset and
// their sampling variance is not in C. V is multiplied by the dispersion: the weighted cost over
// its expectation under C, tr(W R C R') with R = I - X B^-1 X' W, when above 1 (a model the data
// reject). Returns false if C cannot be built (tau off the overlapping grid) or B is singular.
struct Sandwich {
  // Per term (0 for a term at 0): the variance of the coefficient given log Tc and its regression
  // on log Tc, V_cl / V_ll (the variance itself when sigma^2 = 0 and Tc is not in the fit).
  Eigen::VectorXd conditional_variance, slope_on_log_tc;
};

bool GaussMarkovSandwich(const Fitted& fit, const std::vector<double>& tau, double fs,
                         double record_s, const std::vector<Term>& terms, double floor_squared,
                         Sandwich* out) {
  std::vector<long long> m, count;
  if (!OverlappingGrid(tau, fs, record_s, &m, &count)) return false;
  const int rows = static_cast<int>(tau.size());
  std::array<double, 4> theta{};
  double r2 = 0, gm_sigma2 = 0;
  int gm_column = -1;
  std::vector<int> free;
  for (size_t j = 0; j < terms.size(); ++j) {
    const double c = fit.nnls.coefficients[static_cast<Eigen::Index>(j)];
    if (c > 0) free.push_back(static_cast<int>(j));
    // theta's order in allan::AvarCovarianceModel: Q^2, N^2, B^2, K^2.
    const Term order[4] = {Term::kQuantization, Term::kWhite, Term::kBiasInstability,
                           Term::kRateRandomWalk};
    for (int k = 0; k < 4; ++k)
      if (terms[j] == order[k]) theta[static_cast<size_t>(k)] = c;
    if (terms[j] == Term::kRateRamp) r2 = c;
    if (terms[j] == Term::kGaussMarkov) gm_sigma2 = c, gm_column = static_cast<int>(j);
  }
  if (free.empty()) return false;
  const bool with_tc = gm_column >= 0 && gm_sigma2 > 0;
  const int cols = static_cast<int>(free.size()) + (with_tc ? 1 : 0);
  Eigen::MatrixXd x(rows, cols);
  for (size_t k = 0; k < free.size(); ++k)
    x.col(static_cast<Eigen::Index>(k)) = fit.design.col(free[k]);
  if (with_tc) {
    const double h = 1e-4;
    for (int i = 0; i < rows; ++i)
      x(i, cols - 1) = gm_sigma2 *
                       (UnitAllanLaw(Term::kGaussMarkov, tau[i], fit.tc * std::exp(h)) -
                        UnitAllanLaw(Term::kGaussMarkov, tau[i], fit.tc * std::exp(-h))) /
                       (2.0 * h);
  }
  Eigen::MatrixXd c =
      allan::AvarCovarianceModel(m, count, 1.0 / fs, fit.tc).Covariance(theta, r2, gm_sigma2);
  c.diagonal() += floor_squared * fit.model.cwiseAbs2();
  // Columns scaled to unit weighted norm (the laws span many decades), unscaled in v.
  const Eigen::VectorXd column_scale = (fit.weights.cwiseSqrt().asDiagonal() * x)
                                           .colwise()
                                           .norm()
                                           .cwiseMax(1e-300)
                                           .cwiseInverse()
                                           .transpose();
  const Eigen::MatrixXd xs = x * column_scale.asDiagonal();
  const Eigen::MatrixXd wx = fit.weights.asDiagonal() * xs;
  const Eigen::LDLT<Eigen::MatrixXd> bread(xs.transpose() * wx);
  if (bread.info() != Eigen::Success || !(bread.rcond() > 1e-12)) return false;
  const Eigen::MatrixXd b_inv_xtw =
      column_scale.asDiagonal() * bread.solve(wx.transpose());  // B^-1 X' W, unscaled
  const Eigen::MatrixXd v = b_inv_xtw * c * b_inv_xtw.transpose();
  const Eigen::MatrixXd residual_map = Eigen::MatrixXd::Identity(rows, rows) - x * b_inv_xtw;  // R
  const double expected_cost =
      (fit.weights.asDiagonal() * residual_map * c * residual_map.transpose()).trace();
  const double scale = expected_cost > 0 ? std::max(1.0, fit.nnls.cost / expected_cost) : 1.0;
  out->conditional_variance = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(terms.size()));
  out->slope_on_log_tc = out->conditional_variance;
  const Eigen::Index l = cols - 1;
  for (size_t k = 0; k < free.size(); ++k) {
    const Eigen::Index i = static_cast<Eigen::Index>(k);
    out->conditional_variance[free[k]] = scale * v(i, i);
    if (with_tc && v(l, l) > 0) {
      out->slope_on_log_tc[free[k]] = v(i, l) / v(l, l);
      out->conditional_variance[free[k]] = scale * (v(i, i) - v(i, l) * v(i, l) / v(l, l));
    }
  }
  return true;
}

}  // namespace

bool IsFittedOnAllan(Term term) {
  return term == Term::kWhite || term == Term::kQuantization || term == Term::kBiasInstability ||
         term == Term::kRateRandomWalk || term == Term::kRateRamp || term == Term::kGaussMarkov;
}

// The model is sum c_i g_i with c_i = P_i^2 (P = Q, N, B, K, R, sigma).
double UnitAllanLaw(Term term, double tau, double tc) {
  allan::TermParams params;
  params.amplitude = 1.0;
  params.correlation_time_s = tc;
  return allan::TermAllanVariance(AllanTerm(term), params, tau);
}

bool StochasticModel::Has(Term term) const {
  return std::find(terms.begin(), terms.end(), term) != terms.end();
}

double TermAllanVariance(const StochasticModel& model, Term term, double tau) {
  if (!model.Has(term)) return 0.0;
  switch (term) {
    case Term::kQuantization:
      return model.q_rad * model.q_rad * UnitAllanLaw(term, tau, 0);
    case Term::kWhite:
      return model.n_rad_sqrt_s * model.n_rad_sqrt_s * UnitAllanLaw(term, tau, 0);
    case Term::kBiasInstability:
      return model.b_rad_s * model.b_rad_s * UnitAllanLaw(term, tau, 0);
    case Term::kRateRandomWalk:
      return model.k_rad_s_sqrt_s * model.k_rad_s_sqrt_s * UnitAllanLaw(term, tau, 0);
    case Term::kRateRamp:
      return model.r_rad_s2 * model.r_rad_s2 * UnitAllanLaw(term, tau, 0);
    case Term::kGaussMarkov:
      return model.gm_correlation_time_s > 0
                 ? model.gm_sigma_rad_s * model.gm_sigma_rad_s *
                       UnitAllanLaw(term, tau, model.gm_correlation_time_s)
                 : 0.0;
    case Term::kNarrowBand: {
      double sum = 0;
      for (const NarrowBand& band : model.bands) sum += NarrowBandAllanVariance(band, tau);
      return sum;
    }
    default:
      return 0.0;
  }
}

double ModelAllanVariance(const StochasticModel& model, double tau) {
  double sum = 0;
  for (Term term : model.terms) sum += TermAllanVariance(model, term, tau);
  return sum;
}

double ModelOneSidedPsd(const StochasticModel& model, double frequency_hz, double fs) {
  // Two-sided laws of IEEE Std 952-1997 Annex C, doubled.
  const double angular_frequency = 2 * units::kPi * frequency_hz;
  double psd = 0;
  if (model.Has(Term::kWhite)) psd += model.n_rad_sqrt_s * model.n_rad_sqrt_s;
  if (model.Has(Term::kQuantization)) {
    const double sine = std::sin(units::kPi * frequency_hz / fs);
    psd += 4.0 * model.q_rad * model.q_rad * fs * sine * sine;
  }
  if (frequency_hz > 0) {
    if (model.Has(Term::kBiasInstability))
      psd += model.b_rad_s * model.b_rad_s / (2 * units::kPi * frequency_hz);
    if (model.Has(Term::kRateRandomWalk))
      psd += model.k_rad_s_sqrt_s * model.k_rad_s_sqrt_s / (angular_frequency * angular_frequency);
    if (model.Has(Term::kRateRamp))
      psd += model.r_rad_s2 * model.r_rad_s2 /
             (angular_frequency * angular_frequency * angular_frequency);
  }
  if (model.Has(Term::kGaussMarkov) && model.gm_correlation_time_s > 0) {
    const double correlation_time_s = model.gm_correlation_time_s;
    psd += 2.0 * model.gm_sigma_rad_s * model.gm_sigma_rad_s * correlation_time_s /
           (1.0 + angular_frequency * angular_frequency * correlation_time_s * correlation_time_s);
  }
  psd *= 2.0;
  if (model.Has(Term::kNarrowBand))
    for (const NarrowBand& band : model.bands) psd += NarrowBandOneSidedPsd(band, frequency_hz);
  return psd;
}

bool StochasticFitOptions::IsValid(std::string* error) const {
  if (!(relative_floor >= 0 && relative_floor < 1)) {
    if (error) *error = "relative_floor must be in [0, 1)";
    return false;
  }
  if (!(min_tc_factor > 0 && max_tc_divisor >= 1)) {
    if (error) *error = "min_tc_factor must be > 0 and max_tc_divisor >= 1";
    return false;
  }
  return true;
}

StochasticFit FitStochastic(const std::vector<double>& tau, const std::vector<double>& avar,
                            const std::vector<double>& edf_in, double fs, double record_s,
                            const std::vector<Term>& all_terms, const StochasticFitOptions& options,
                            const std::vector<NarrowBand>& bands) {
  StochasticFit result;
  std::string err;
  if (!options.IsValid(&err)) {
    result.summary.termination = Termination::kInvalidOptions;
    result.summary.message = err;
    return result;
  }
  std::vector<Term> terms;
  for (Term term : all_terms)
    if (IsFittedOnAllan(term) && std::find(terms.begin(), terms.end(), term) == terms.end())
      terms.push_back(term);
  result.model.terms = terms;
  if (!bands.empty()) {
    result.model.bands = bands;
    result.model.terms.push_back(Term::kNarrowBand);
  }
  std::vector<double> fit_tau;
  std::vector<double> fit_avar, fit_edf;
  for (size_t i = 0; i < tau.size(); ++i) {
    if (!(avar[i] > 0) || !std::isfinite(avar[i])) continue;
    fit_tau.push_back(tau[i]);
    fit_avar.push_back(avar[i]);
    fit_edf.push_back(std::isfinite(edf_in[i]) && edf_in[i] > 0 ? edf_in[i] : 1.0);
  }
  if (terms.empty() || fit_tau.size() < 2) {
    result.summary.termination =
        terms.empty() ? Termination::kSuccess : Termination::kInsufficientData;
    result.summary.message = terms.empty() ? "no stochastic term" : "fewer than 2 Allan points";
    return result;
  }
  const Eigen::VectorXd avar_points = Eigen::Map<Eigen::VectorXd>(fit_avar.data(), fit_avar.size());
  const Eigen::VectorXd edf = Eigen::Map<Eigen::VectorXd>(fit_edf.data(), fit_edf.size());
  Eigen::VectorXd offset = Eigen::VectorXd::Zero(avar_points.size());
  for (size_t i = 0; i < fit_tau.size(); ++i)
    for (const NarrowBand& band : bands) offset[i] += NarrowBandAllanVariance(band, fit_tau[i]);
  const double floor_squared = options.relative_floor * options.relative_floor;
  const bool has_gauss_markov =
      std::find(terms.begin(), terms.end(), Term::kGaussMarkov) != terms.end();
  Fitted best;
  if (!has_gauss_markov) {
    best = FitAt(fit_tau, avar_points, offset, edf, terms, 0.0, floor_squared);
  } else {
    const double log_tc_low = std::log(options.min_tc_factor / fs),
                 log_tc_high = std::log(record_s / options.max_tc_divisor);
    const int grid = 30;
    best.nnls.cost = std::numeric_limits<double>::infinity();
    int best_index = 0;
    std::vector<double> grid_log_tc(grid), grid_cost(grid);
    for (int i = 0; i < grid; ++i) {
      grid_log_tc[i] = log_tc_low + (log_tc_high - log_tc_low) * i / (grid - 1);
      Fitted fitted =
          FitAt(fit_tau, avar_points, offset, edf, terms, std::exp(grid_log_tc[i]), floor_squared);
      grid_cost[i] = fitted.nnls.cost;
      if (fitted.nnls.cost < best.nnls.cost) {
        best = fitted;
        best_index = i;
      }
    }
    const double step = (log_tc_high - log_tc_low) / (grid - 1);
    double bracket_low = log_tc_low + step * std::max(best_index - 1, 0),
           bracket_high = log_tc_low + step * std::min(best_index + 1, grid - 1);
    const double golden = 0.6180339887498949;
    for (int iteration = 0; iteration < 30; ++iteration) {
      const double inner_low = bracket_high - golden * (bracket_high - bracket_low),
                   inner_high = bracket_low + golden * (bracket_high - bracket_low);
      const Fitted fit_low =
          FitAt(fit_tau, avar_points, offset, edf, terms, std::exp(inner_low), floor_squared);
      const Fitted fit_high =
          FitAt(fit_tau, avar_points, offset, edf, terms, std::exp(inner_high), floor_squared);
      if (fit_low.nnls.cost < fit_high.nnls.cost) {
        bracket_high = inner_high;
        if (fit_low.nnls.cost < best.nnls.cost) best = fit_low;
      } else {
        bracket_low = inner_low;
        if (fit_high.nnls.cost < best.nnls.cost) best = fit_high;
      }
    }
    // Standard error of Tc from the curvature of the cost in log(Tc): a weighted LS cost is a
    // chi-square, so var(log Tc) ~ 2 / cost'' (times the dispersion, below), or from the profile
    // interval where that is wider. (The sandwich's linearised variance of log Tc, below, is not
    // used for it; docs/compare.md compares the two over seeds.)
    const double log_step = 0.05, log_tc = std::log(best.tc);
    const Fitted minus =
        FitAt(fit_tau, avar_points, offset, edf, terms, std::exp(log_tc - log_step), floor_squared);
    const Fitted plus =
        FitAt(fit_tau, avar_points, offset, edf, terms, std::exp(log_tc + log_step), floor_squared);
    const double curvature =
        (plus.nnls.cost - 2 * best.nnls.cost + minus.nnls.cost) / (log_step * log_step);
    const int num_parameters = static_cast<int>(terms.size()) + 1;
    const double dispersion = std::max(
        1.0, best.nnls.cost / std::max(1, static_cast<int>(fit_tau.size()) - num_parameters));
    const ProfileInterval interval = ProfileIntervalOf(
        grid_log_tc, grid_cost, std::log(best.tc), best.nnls.cost, kChiSquare1At95 * dispersion,
        [&](double log_tc_at) {
          return FitAt(fit_tau, avar_points, offset, edf, terms, std::exp(log_tc_at), floor_squared)
              .nnls.cost;
        });
    const double half_width = (interval.high - interval.low) / (2.0 * kNormal975);
    const double log_tc_variance =
        std::max(curvature > 0 ? 2.0 * dispersion / curvature : 1.0, half_width * half_width);
    result.model.gm_correlation_time_low_s = std::exp(interval.low);
    result.model.gm_correlation_time_high_s = std::exp(interval.high);
    result.model.gm_correlation_time_s = best.tc;
    result.model.gm_correlation_time_se = best.tc * std::sqrt(log_tc_variance);
    // The coefficients' standard errors above hold Tc fixed and take the Allan points as
    // independent; Tc is estimated too, and sigma^2 trades against it along the cost valley. The
    // delta method on the profile (first order): var(c) = var(c | log Tc) + (dc / dlog Tc)^2
    // var(log Tc), with var(c | log Tc) and the slope from the sandwich (GaussMarkovSandwich:
    // the conditional variance and the regression on log Tc of its joint covariance), which
    // holds the points' correlations. Where the sandwich cannot be built, var(c | log Tc) is the
    // independent points' times the dispersion and the slope is by central differences of the
    // fits at log Tc +- log_step.
    Sandwich sandwich;
    const bool has_sandwich =
        GaussMarkovSandwich(best, fit_tau, fs, record_s, terms, floor_squared, &sandwich);
    for (long j = 0; j < best.nnls.coefficients.size(); ++j) {
      const double slope = has_sandwich ? sandwich.slope_on_log_tc[j]
                                        : (plus.nnls.coefficients[j] - minus.nnls.coefficients[j]) /
                                              (2.0 * log_step);
      const double conditional_variance = has_sandwich
                                              ? sandwich.conditional_variance[j]
                                              : dispersion * best.nnls.se[j] * best.nnls.se[j];
      best.nnls.se[j] = std::sqrt(conditional_variance + slope * slope * log_tc_variance);
    }
  }
  auto root = [](double coefficient, double se, double* value, double* value_se) {
    *value = std::sqrt(std::max(coefficient, 0.0));
    *value_se = *value > 0 ? se / (2.0 * *value) : std::sqrt(std::max(se, 0.0));
  };
  for (size_t j = 0; j < terms.size(); ++j) {
    const double coefficient = best.nnls.coefficients[j], se = best.nnls.se[j];
    switch (terms[j]) {
      case Term::kQuantization:
        root(coefficient, se, &result.model.q_rad, &result.model.q_se);
        break;
      case Term::kWhite:
        root(coefficient, se, &result.model.n_rad_sqrt_s, &result.model.n_se);
        break;
      case Term::kBiasInstability:
        root(coefficient, se, &result.model.b_rad_s, &result.model.b_se);
        break;
      case Term::kRateRandomWalk:
        root(coefficient, se, &result.model.k_rad_s_sqrt_s, &result.model.k_se);
        break;
      case Term::kRateRamp:
        root(coefficient, se, &result.model.r_rad_s2, &result.model.r_se);
        break;
      case Term::kGaussMarkov:
        root(coefficient, se, &result.model.gm_sigma_rad_s, &result.model.gm_sigma_se);
        break;
      default:
        break;
    }
  }
  result.summary.num_parameters = static_cast<int>(terms.size()) + (has_gauss_markov ? 1 : 0);
  result.summary.weighted_rss = best.nnls.cost;
  result.summary.message =
      "weighted NNLS on " + std::to_string(fit_tau.size()) + " Allan variances";
  return result;
}

}  // namespace fogpipe::model
