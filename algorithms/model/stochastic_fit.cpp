#include "algorithms/model/stochastic_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/allan/nnls.h"
#include "algorithms/allan/noise_model.h"
#include "algorithms/common/units.h"

namespace fogpipe::model {
namespace {

bool IsStochastic(Term t) {
  return t == Term::kWhite || t == Term::kQuantization || t == Term::kBiasInstability ||
         t == Term::kRateRandomWalk || t == Term::kRateRamp || t == Term::kGaussMarkov;
}

allan::Term AllanTerm(Term t) {
  switch (t) {
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
  Eigen::VectorXd c;
  Eigen::VectorXd se;
  double cost = std::numeric_limits<double>::infinity();
};

// min ||W^1/2 (A c - b)||^2, c >= 0 (Lawson-Hanson, fogpipe::allan), columns scaled to unit norm.
// Standard errors from the weighted normal matrix on the free terms.
NnlsResult Nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& w) {
  const long p = a.cols();
  NnlsResult out;
  const Eigen::VectorXd sw = w.cwiseSqrt();
  const Eigen::MatrixXd aw = sw.asDiagonal() * a;
  const Eigen::VectorXd bw = sw.asDiagonal() * b;
  const Eigen::VectorXd d = aw.colwise().norm().cwiseMax(1e-300).cwiseInverse().transpose();
  const Eigen::MatrixXd as = aw * d.asDiagonal();
  const allan::NnlsResult r = allan::SolveNnls(as, bw);
  out.c = d.asDiagonal() * r.x;
  out.se = Eigen::VectorXd::Zero(p);
  out.cost = (aw * out.c - bw).squaredNorm();
  std::vector<long> free;
  for (long j = 0; j < p; ++j)
    if (r.x[j] > 0) free.push_back(j);
  if (!free.empty()) {
    Eigen::MatrixXd af(as.rows(), free.size());
    for (size_t j = 0; j < free.size(); ++j) af.col(j) = as.col(free[j]);
    const Eigen::MatrixXd cov =
        (af.transpose() * af).ldlt().solve(Eigen::MatrixXd::Identity(free.size(), free.size()));
    for (size_t j = 0; j < free.size(); ++j)
      out.se[free[j]] = d[free[j]] * std::sqrt(std::max(cov(j, j), 0.0));
  }
  return out;
}

struct Fitted {
  NnlsResult nnls;
  double tc = 0;
};

Fitted FitAt(const std::vector<double>& tau, const Eigen::VectorXd& s2, const Eigen::VectorXd& edf,
             const std::vector<Term>& terms, double tc, double floor2) {
  const int rows = static_cast<int>(tau.size()), p = static_cast<int>(terms.size());
  Eigen::MatrixXd a(rows, p);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < p; ++j) a(i, j) = UnitAllanLaw(terms[j], tau[i], tc);
  // Relative variance of s2: 2 / edf + floor^2. Weights start from the data, then the model.
  Eigen::VectorXd model = s2;
  Fitted f;
  f.tc = tc;
  for (int it = 0; it < 3; ++it) {
    Eigen::VectorXd w(rows);
    for (int i = 0; i < rows; ++i) {
      const double m = std::max(model[i], 1e-6 * s2[i]);
      w[i] = 1.0 / ((2.0 / edf[i] + floor2) * m * m);
    }
    f.nnls = Nnls(a, s2, w);
    model = a * f.nnls.c;
  }
  return f;
}

}  // namespace

// The model is sum c_i g_i with c_i = P_i^2 (P = Q, N, B, K, R, sigma).
double UnitAllanLaw(Term t, double tau, double tc) {
  allan::TermParams p;
  p.amplitude = 1.0;
  p.correlation_time_s = tc;
  return allan::TermAllanVariance(AllanTerm(t), p, tau);
}

bool StochasticModel::Has(Term t) const {
  return std::find(terms.begin(), terms.end(), t) != terms.end();
}

double TermAllanVariance(const StochasticModel& m, Term term, double tau) {
  if (!m.Has(term)) return 0.0;
  switch (term) {
    case Term::kQuantization:
      return m.q_rad * m.q_rad * UnitAllanLaw(term, tau, 0);
    case Term::kWhite:
      return m.n_rad_sqrt_s * m.n_rad_sqrt_s * UnitAllanLaw(term, tau, 0);
    case Term::kBiasInstability:
      return m.b_rad_s * m.b_rad_s * UnitAllanLaw(term, tau, 0);
    case Term::kRateRandomWalk:
      return m.k_rad_s_sqrt_s * m.k_rad_s_sqrt_s * UnitAllanLaw(term, tau, 0);
    case Term::kRateRamp:
      return m.r_rad_s2 * m.r_rad_s2 * UnitAllanLaw(term, tau, 0);
    case Term::kGaussMarkov:
      return m.gm_correlation_time_s > 0 ? m.gm_sigma_rad_s * m.gm_sigma_rad_s *
                                               UnitAllanLaw(term, tau, m.gm_correlation_time_s)
                                         : 0.0;
    default:
      return 0.0;
  }
}

double ModelAllanVariance(const StochasticModel& m, double tau) {
  double s = 0;
  for (Term t : m.terms) s += TermAllanVariance(m, t, tau);
  return s;
}

double ModelOneSidedPsd(const StochasticModel& m, double f, double fs) {
  // Two-sided laws of IEEE Std 952-1997 Annex C, doubled.
  const double w = 2 * units::kPi * f;
  double s = 0;
  if (m.Has(Term::kWhite)) s += m.n_rad_sqrt_s * m.n_rad_sqrt_s;
  if (m.Has(Term::kQuantization)) {
    const double sn = std::sin(units::kPi * f / fs);
    s += 4.0 * m.q_rad * m.q_rad * fs * sn * sn;
  }
  if (f > 0) {
    if (m.Has(Term::kBiasInstability)) s += m.b_rad_s * m.b_rad_s / (2 * units::kPi * f);
    if (m.Has(Term::kRateRandomWalk)) s += m.k_rad_s_sqrt_s * m.k_rad_s_sqrt_s / (w * w);
    if (m.Has(Term::kRateRamp)) s += m.r_rad_s2 * m.r_rad_s2 / (w * w * w);
  }
  if (m.Has(Term::kGaussMarkov) && m.gm_correlation_time_s > 0) {
    const double tc = m.gm_correlation_time_s;
    s += 2.0 * m.gm_sigma_rad_s * m.gm_sigma_rad_s * tc / (1.0 + w * w * tc * tc);
  }
  return 2.0 * s;
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
                            const std::vector<Term>& all_terms, const StochasticFitOptions& o) {
  StochasticFit out;
  std::string err;
  if (!o.IsValid(&err)) {
    out.summary.termination = Termination::kInvalidOptions;
    out.summary.message = err;
    return out;
  }
  std::vector<Term> terms;
  for (Term t : all_terms)
    if (IsStochastic(t) && std::find(terms.begin(), terms.end(), t) == terms.end())
      terms.push_back(t);
  out.model.terms = terms;
  std::vector<double> tv;
  std::vector<double> sv, ev;
  for (size_t i = 0; i < tau.size(); ++i) {
    if (!(avar[i] > 0) || !std::isfinite(avar[i])) continue;
    tv.push_back(tau[i]);
    sv.push_back(avar[i]);
    ev.push_back(std::isfinite(edf_in[i]) && edf_in[i] > 0 ? edf_in[i] : 1.0);
  }
  if (terms.empty() || tv.size() < 2) {
    out.summary.termination =
        terms.empty() ? Termination::kSuccess : Termination::kInsufficientData;
    out.summary.message = terms.empty() ? "no stochastic term" : "fewer than 2 Allan points";
    return out;
  }
  const Eigen::VectorXd s2 = Eigen::Map<Eigen::VectorXd>(sv.data(), sv.size());
  const Eigen::VectorXd edf = Eigen::Map<Eigen::VectorXd>(ev.data(), ev.size());
  const double floor2 = o.relative_floor * o.relative_floor;
  const bool gm = std::find(terms.begin(), terms.end(), Term::kGaussMarkov) != terms.end();
  Fitted best;
  if (!gm) {
    best = FitAt(tv, s2, edf, terms, 0.0, floor2);
  } else {
    const double lo = std::log(o.min_tc_factor / fs), hi = std::log(record_s / o.max_tc_divisor);
    const int grid = 30;
    best.nnls.cost = std::numeric_limits<double>::infinity();
    int bi = 0;
    for (int i = 0; i < grid; ++i) {
      Fitted f = FitAt(tv, s2, edf, terms, std::exp(lo + (hi - lo) * i / (grid - 1)), floor2);
      if (f.nnls.cost < best.nnls.cost) {
        best = f;
        bi = i;
      }
    }
    const double step = (hi - lo) / (grid - 1);
    double a = lo + step * std::max(bi - 1, 0), b = lo + step * std::min(bi + 1, grid - 1);
    const double g = 0.6180339887498949;
    for (int it = 0; it < 30; ++it) {
      const double x1 = b - g * (b - a), x2 = a + g * (b - a);
      const Fitted f1 = FitAt(tv, s2, edf, terms, std::exp(x1), floor2);
      const Fitted f2 = FitAt(tv, s2, edf, terms, std::exp(x2), floor2);
      if (f1.nnls.cost < f2.nnls.cost) {
        b = x2;
        if (f1.nnls.cost < best.nnls.cost) best = f1;
      } else {
        a = x1;
        if (f2.nnls.cost < best.nnls.cost) best = f2;
      }
    }
    // Standard error of Tc from the curvature of the cost in log(Tc): a weighted LS cost is a
    // chi-square, so var(log Tc) ~ 2 / cost''.
    const double h = 0.05, l0 = std::log(best.tc);
    const double cm = FitAt(tv, s2, edf, terms, std::exp(l0 - h), floor2).nnls.cost;
    const double cp = FitAt(tv, s2, edf, terms, std::exp(l0 + h), floor2).nnls.cost;
    const double curv = (cp - 2 * best.nnls.cost + cm) / (h * h);
    out.model.gm_correlation_time_s = best.tc;
    out.model.gm_correlation_time_se = curv > 0 ? best.tc * std::sqrt(2.0 / curv) : best.tc;
  }
  auto root = [](double c, double se, double* p, double* pse) {
    *p = std::sqrt(std::max(c, 0.0));
    *pse = *p > 0 ? se / (2.0 * *p) : std::sqrt(std::max(se, 0.0));
  };
  for (size_t j = 0; j < terms.size(); ++j) {
    const double c = best.nnls.c[j], se = best.nnls.se[j];
    switch (terms[j]) {
      case Term::kQuantization:
        root(c, se, &out.model.q_rad, &out.model.q_se);
        break;
      case Term::kWhite:
        root(c, se, &out.model.n_rad_sqrt_s, &out.model.n_se);
        break;
      case Term::kBiasInstability:
        root(c, se, &out.model.b_rad_s, &out.model.b_se);
        break;
      case Term::kRateRandomWalk:
        root(c, se, &out.model.k_rad_s_sqrt_s, &out.model.k_se);
        break;
      case Term::kRateRamp:
        root(c, se, &out.model.r_rad_s2, &out.model.r_se);
        break;
      case Term::kGaussMarkov:
        root(c, se, &out.model.gm_sigma_rad_s, &out.model.gm_sigma_se);
        break;
      default:
        break;
    }
  }
  out.summary.num_parameters = static_cast<int>(terms.size()) + (gm ? 1 : 0);
  out.summary.weighted_rss = best.nnls.cost;
  out.summary.message = "weighted NNLS on " + std::to_string(tv.size()) + " Allan variances";
  return out;
}

}  // namespace fogpipe::model
