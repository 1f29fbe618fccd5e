#include "algorithms/allan/noise_fit.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <vector>

#include "algorithms/allan/avar_covariance.h"
#include "algorithms/allan/nnls.h"
#include "algorithms/allan/noise_model.h"
#include "algorithms/common/chi_square.h"
#include "algorithms/common/units.h"

namespace fogpipe::allan {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kTerms = 5;
constexpr Term kTermOrder[kTerms] = {Term::kQuantization, Term::kAngleRandomWalk,
                                     Term::kBiasInstability, Term::kRateRandomWalk,
                                     Term::kRateRamp};

// Basis function j at tau: the Allan variance of term j with unit amplitude.
double Basis(int j, double tau) {
  TermParams unit;
  unit.amplitude = 1.0;
  return TermAllanVariance(kTermOrder[j], unit, tau);
}

double* Amplitude(NoiseTerms* t, int j) {
  double* a[kTerms] = {&t->q_rad, &t->n_rad_sqrt_s, &t->b_rad_s, &t->k_rad_s_sqrt_s, &t->r_rad_s2};
  return a[j];
}
double* StandardError(NoiseTerms* t, int j) {
  double* a[kTerms] = {&t->q_se, &t->n_se, &t->b_se, &t->k_se, &t->r_se};
  return a[j];
}

}  // namespace

bool NoiseFitOptions::IsValid(std::string* error) const {
  if (!(fit_q || fit_n || fit_b || fit_k || fit_r)) {
    if (error) *error = "no term to fit";
    return false;
  }
  if (!(min_tau_s >= 0.0) || !(max_tau_s > min_tau_s)) {
    if (error) *error = "need 0 <= min_tau_s < max_tau_s";
    return false;
  }
  if (reweight_iterations < 0 || reweight_iterations > 100) {
    if (error) *error = "reweight_iterations must be in [0, 100]";
    return false;
  }
  if (gls_iterations < 1 || gls_iterations > 100) {
    if (error) *error = "gls_iterations must be in [1, 100]";
    return false;
  }
  if (!(significance_z > 0.0) || !(misfit_level > 0.0 && misfit_level < 1.0) ||
      !(discrepancy_below_p >= 0.0 && discrepancy_below_p < 1.0)) {
    if (error)
      *error = "need significance_z > 0, 0 < misfit_level < 1, 0 <= discrepancy_below_p < 1";
    return false;
  }
  if (!(readoff_slope_tolerance > 0.0)) {
    if (error) *error = "readoff_slope_tolerance must be positive";
    return false;
  }
  return true;
}

NoiseTermsEngineering ToEngineeringUnits(const NoiseTerms& t) {
  using namespace units;
  return {QuantizationToArcsec(t.q_rad),   ArwToDegPerSqrtHour(t.n_rad_sqrt_s),
          BiasToDegPerHour(t.b_rad_s),     RrwToDegPerHourSqrtHour(t.k_rad_s_sqrt_s),
          RampToDegPerHour2(t.r_rad_s2),   QuantizationToArcsec(t.q_se),
          ArwToDegPerSqrtHour(t.n_se),     BiasToDegPerHour(t.b_se),
          RrwToDegPerHourSqrtHour(t.k_se), RampToDegPerHour2(t.r_se)};
}

double NoiseModelVariance(const NoiseTerms& terms, double tau_s) {
  NoiseTerms t = terms;
  double v = 0.0;
  for (int j = 0; j < kTerms; ++j) {
    const double a = *Amplitude(&t, j);
    if (std::isfinite(a)) v += a * a * Basis(j, tau_s);
  }
  return v;
}

std::vector<int> ModelDominantAlpha(const NoiseTerms& terms, const std::vector<double>& tau_s) {
  constexpr int kAlpha[kTerms] = {2, 0, -1, -2, -2};  // Q, N, B, K, R
  NoiseTerms t = terms;
  std::vector<int> out;
  out.reserve(tau_s.size());
  for (double tau : tau_s) {
    int best = -1;
    double best_v = 0.0;
    for (int j = 0; j < kTerms; ++j) {
      const double a = *Amplitude(&t, j);
      const double v = std::isfinite(a) ? a * a * Basis(j, tau) : 0.0;
      if (v > best_v) best_v = v, best = j;
    }
    out.push_back(best < 0 ? kNoModelAlpha : kAlpha[best]);
  }
  return out;
}

namespace {

// The read-offs with the pair of taus each was anchored at (B: the tau of the minimum).
struct AnchoredReadoffs {
  NoiseTerms value;
  std::array<TauRange, kTerms> taus{};
};

AnchoredReadoffs ReadOff(const AllanTable& table, double slope_tolerance) {
  AnchoredReadoffs out;
  NoiseTerms& value = out.value;
  value.q_rad = value.n_rad_sqrt_s = value.b_rad_s = value.k_rad_s_sqrt_s = value.r_rad_s2 = kNaN;
  std::vector<size_t> rows;
  for (size_t i = 0; i < table.size(); ++i)
    if (table.tau_s[i] > 0.0 && table.sigma[i] > 0.0 && std::isfinite(table.sigma[i]))
      rows.push_back(i);
  if (rows.empty()) return out;
  size_t min_row = rows[0];
  for (size_t i : rows)
    if (table.sigma[i] < table.sigma[min_row]) min_row = i;
  value.b_rad_s = table.sigma[min_row] / std::sqrt(2.0 * std::log(2.0) / units::kPi);
  out.taus[2] = {table.tau_s[min_row], table.tau_s[min_row]};
  // (slope, tau at which the line is read, factor turning the read value into the amplitude)
  struct Readoff {
    int term;         // index into kTermOrder
    double tau_read;  // where the line is read [s]
  };
  const Readoff readoffs[] = {{0, std::sqrt(3.0)}, {1, 1.0}, {3, 3.0}, {4, std::sqrt(2.0)}};
  for (const Readoff& r : readoffs) {
    const double target = TermSlope(kTermOrder[r.term]);
    double best = slope_tolerance;
    double read = kNaN;
    for (size_t k = 0; k + 1 < rows.size(); ++k) {
      const double lt0 = std::log(table.tau_s[rows[k]]), lt1 = std::log(table.tau_s[rows[k + 1]]);
      const double ls0 = std::log(table.sigma[rows[k]]), ls1 = std::log(table.sigma[rows[k + 1]]);
      const double slope = (ls1 - ls0) / (lt1 - lt0);
      // A slope known no better than the tolerance says nothing about which term made it: with
      // edf e, sd(ln sigma) ~ 1 / sqrt(2 e) (chi-square), so the pair's slope has standard error
      // sqrt(1 / (2 e0) + 1 / (2 e1)) / ln(tau1 / tau0) at most (neighbouring overlapping
      // estimates are positively correlated, which only lowers it). At 8-19 averages that is
      // ~0.4: a -1 slope there is as often white FM as quantization.
      const double e0 = rows[k] < table.edf.size() ? table.edf[rows[k]] : kNaN;
      const double e1 = rows[k + 1] < table.edf.size() ? table.edf[rows[k + 1]] : kNaN;
      if (e0 > 0.0 && e1 > 0.0 && std::sqrt(0.5 / e0 + 0.5 / e1) / (lt1 - lt0) > slope_tolerance)
        continue;
      if (std::abs(slope - target) <= best) {
        best = std::abs(slope - target);
        const double lt = 0.5 * (lt0 + lt1), ls = 0.5 * (ls0 + ls1);
        read = std::exp(ls + target * (std::log(r.tau_read) - lt));
        out.taus[r.term] = {table.tau_s[rows[k]], table.tau_s[rows[k + 1]]};
      }
    }
    *Amplitude(&value, r.term) = read;
  }
  return out;
}

}  // namespace

NoiseTerms SlopeReadoffs(const AllanTable& table, double slope_tolerance) {
  return ReadOff(table, slope_tolerance).value;
}

namespace {

// Table rows the fit uses, with what the covariance model needs.
struct Points {
  std::vector<double> tau, v, edf;
  std::vector<long long> m, count;
  bool have_edf = false;
  int size() const { return static_cast<int>(tau.size()); }
};

// Dense grids (every m) are thinned to at most this many rows per octave of tau: neighbouring
// taus of such a grid carry almost the same information (their estimates are correlated near 1,
// so their covariance matrix is numerically singular and the generalised fit cannot use it),
// while that matrix grows with the square of the rows (50 000 rows: 20 GB). Four per octave is
// about the density of the 100-tau log grid of a 1e7-sample record, where the generalised fit
// runs (allan_benchmark).
constexpr double kMaxRowsPerOctave = 4.0;

// Rows with an EDF are weighted by it; if no row has one, all get edf = 1 (relative least squares)
// and no standard errors are given. Rows without EDF in a table that has some are skipped (they
// are the ones whose noise type admits no EDF).
Points SelectRows(const AllanTable& table, const NoiseFitOptions& options) {
  Points p;
  for (size_t i = 0; i < table.size() && i < table.edf.size(); ++i)
    if (table.edf[i] > 0.0 && std::isfinite(table.edf[i])) p.have_edf = true;
  double last_log2_tau = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < table.size(); ++i) {
    const double t = table.tau_s[i], s = table.sigma[i];
    if (!(t >= options.min_tau_s && t <= options.max_tau_s) || !(s > 0.0) || !std::isfinite(s))
      continue;
    const bool last_row = i + 1 == table.size();
    if (!last_row && std::log2(t) - last_log2_tau < 1.0 / kMaxRowsPerOctave) continue;
    last_log2_tau = std::log2(t);
    const double e = i < table.edf.size() ? table.edf[i] : kNaN;
    if (p.have_edf && !(e > 0.0 && std::isfinite(e))) continue;
    p.tau.push_back(t);
    p.v.push_back(s * s);
    p.edf.push_back(p.have_edf ? e : 1.0);
    p.m.push_back(i < table.m.size() ? table.m[i] : 0);
    p.count.push_back(i < table.count.size() ? table.count[i] : 0);
  }
  return p;
}

// The covariance model needs m, the number of differences and one sample period for all rows.
bool CovarianceModelApplies(const AllanTable& table, const Points& p, double* sample_period_s) {
  if (table.deviation != Deviation::kOverlappingAllan || !p.have_edf || p.size() == 0) return false;
  *sample_period_s = p.tau[0] / static_cast<double>(p.m[0]);
  for (int i = 0; i < p.size(); ++i) {
    if (p.m[i] < 1 || p.count[i] < 1) return false;
    const double t0 = p.tau[i] / static_cast<double>(p.m[i]);
    if (std::abs(t0 / *sample_period_s - 1.0) > 1e-9) return false;
  }
  return true;
}

// NNLS on a (whitened) system with columns scaled to unit norm for conditioning.
Eigen::VectorXd SolveScaled(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, bool* converged) {
  Eigen::MatrixXd as = a;
  const Eigen::VectorXd scale = a.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < as.cols(); ++c) as.col(c) /= scale[c] > 0.0 ? scale[c] : 1.0;
  const NnlsResult nnls = SolveNnls(as, b);
  *converged = *converged && nnls.converged;
  Eigen::VectorXd theta = nnls.x;
  for (Eigen::Index c = 0; c < theta.size(); ++c) theta[c] /= scale[c] > 0.0 ? scale[c] : 1.0;
  return theta;
}

// Diagonal weights sqrt(edf / 2) / v, v the previous model (the measurement at first), never below
// 1e-6 of the measurement (a term not yet found must not get an infinite weight).
Eigen::VectorXd DiagonalSqrtWeights(const Points& p, const Eigen::VectorXd& model_v) {
  Eigen::VectorXd w(p.size());
  for (int i = 0; i < p.size(); ++i)
    w[i] = std::sqrt(p.edf[i] / 2.0) / std::max(model_v[i], 1e-6 * p.v[i]);
  return w;
}

// Sampling covariance of the Allan variances under theta, plus an independent model discrepancy
// (discrepancy * model_i)^2 on the diagonal (0 unless the model is rejected, see FitNoiseTerms).
Eigen::MatrixXd ModelCovariance(const AvarCovarianceModel& cov, const std::vector<int>& cols,
                                const Eigen::VectorXd& theta, const Eigen::MatrixXd& basis,
                                double discrepancy) {
  std::array<double, 4> t{};
  double r2 = 0.0;
  for (size_t c = 0; c < cols.size(); ++c) {
    if (cols[c] < 4)
      t[static_cast<size_t>(cols[c])] = theta[static_cast<Eigen::Index>(c)];
    else
      r2 = theta[static_cast<Eigen::Index>(c)];
  }
  Eigen::MatrixXd c = cov.Covariance(t, r2);
  // Dense grids make neighbouring rows nearly collinear; a relative 1e-9 on the diagonal keeps the
  // Cholesky factor finite without changing any fitted digit that matters.
  c.diagonal() *= 1.0 + 1e-9;
  if (discrepancy > 0.0) c.diagonal() += (discrepancy * (basis * theta)).array().square().matrix();
  return c;
}

// The whitened system of the final model: aw = W A, rw = W (v - A theta), W^T W = C^-1.
struct Whitened {
  Eigen::MatrixXd aw;
  Eigen::VectorXd rw;
  Eigen::VectorXd point_variance;  // var(v_i) under the model [(rad/s)^4]
};

// Generalised NNLS iterated on the model covariance. Returns false if C is not positive definite.
bool GeneralizedFit(const Points& p, const Eigen::MatrixXd& basis, const std::vector<int>& cols,
                    const AvarCovarianceModel& cov, double discrepancy, int iterations,
                    Eigen::VectorXd* theta, bool* converged, int* solves, Whitened* out) {
  const Eigen::Map<const Eigen::VectorXd> v(p.v.data(), p.size());
  for (int pass = 0; pass < iterations; ++pass) {
    const Eigen::LLT<Eigen::MatrixXd> llt(ModelCovariance(cov, cols, *theta, basis, discrepancy));
    if (llt.info() != Eigen::Success) return false;
    const Eigen::MatrixXd a = llt.matrixL().solve(basis);
    const Eigen::VectorXd b = llt.matrixL().solve(v);
    const Eigen::VectorXd previous = basis * *theta;
    *theta = SolveScaled(a, b, converged);
    ++*solves;
    const Eigen::VectorXd model = basis * *theta;
    if (((model - previous).cwiseAbs().array() / v.array()).maxCoeff() < 1e-7) break;
  }
  const Eigen::MatrixXd c = ModelCovariance(cov, cols, *theta, basis, discrepancy);
  const Eigen::LLT<Eigen::MatrixXd> llt(c);
  if (llt.info() != Eigen::Success) return false;
  out->aw = llt.matrixL().solve(basis);
  out->rw = llt.matrixL().solve(v - basis * *theta);
  out->point_variance = c.diagonal();
  return true;
}

int PositiveCount(const Eigen::VectorXd& theta) {
  return static_cast<int>((theta.array() > 0.0).count());
}

// The relative model discrepancy d that brings the generalised chi2 / dof to 1 (bisection on
// log d in [1e-3, 10]), with theta refitted at it. A rejected model (real gyros: filter roll-off,
// vibration, temperature) otherwise gets weights that trust its shape more than the data; d adds
// the model error as independent per-point noise, which widens the standard errors honestly and
// lets the terms follow the curve's level (docs/allan-noise-fit.md).
double FitWithDiscrepancy(const Points& p, const Eigen::MatrixXd& basis,
                          const std::vector<int>& cols, const AvarCovarianceModel& cov,
                          const NoiseFitOptions& options, Eigen::VectorXd* theta, bool* converged,
                          int* solves, Whitened* out) {
  double lo = std::log(1e-3), hi = std::log(10.0);
  const Eigen::VectorXd start = *theta;
  for (int step = 0; step < 14; ++step) {
    const double mid = 0.5 * (lo + hi);
    Eigen::VectorXd t = start;
    Whitened w;
    if (!GeneralizedFit(p, basis, cols, cov, std::exp(mid), options.gls_iterations, &t, converged,
                        solves, &w))
      break;
    const int dof = std::max(1, p.size() - PositiveCount(t));
    (w.rw.squaredNorm() / dof > 1.0 ? lo : hi) = mid;
  }
  const double d = std::exp(hi);
  *theta = start;
  GeneralizedFit(p, basis, cols, cov, d, options.gls_iterations, theta, converged, solves, out);
  return d;
}

// Diagonal of (A_S^T W^T W A_S)^-1 for the column subset S.
Eigen::VectorXd ThetaVariances(const Eigen::MatrixXd& aw, const std::vector<int>& set) {
  Eigen::MatrixXd af(aw.rows(), static_cast<Eigen::Index>(set.size()));
  for (size_t k = 0; k < set.size(); ++k) af.col(static_cast<Eigen::Index>(k)) = aw.col(set[k]);
  const Eigen::VectorXd s = af.colwise().norm().transpose();
  for (Eigen::Index k = 0; k < af.cols(); ++k) af.col(k) /= s[k];
  const Eigen::MatrixXd normal = af.transpose() * af;
  const Eigen::MatrixXd inv =
      normal.ldlt().solve(Eigen::MatrixXd::Identity(normal.rows(), normal.cols()));
  Eigen::VectorXd diag(static_cast<Eigen::Index>(set.size()));
  for (Eigen::Index k = 0; k < diag.size(); ++k) diag[k] = inv(k, k) / (s[k] * s[k]);
  return diag;
}

// One-sided tail of the upper limits: theta_hat + 2 sigma of a Gaussian estimate.
constexpr double kUpperLimitTail = 0.02275;

// The one-sided upper limit of theta_c (97.7 % for a Gaussian estimate): the largest U with
// theta_hat_c >= U - 2 se(U), where se(U) is the standard error the same fit would have if theta_c
// were U, the other terms as fitted. This inverts the 2-sigma test instead of adding 2 se at the
// estimate (Wald): the Allan variances' sampling variance grows with the model, so a term
// estimated low (or held at 0) has a small se at its estimate, and theta_hat + 2 se(theta_hat)
// then covers the truth far less often than it claims (the five-term scenario's R: 81 % of
// records instead of 97.7 %; docs/allan-noise-fit.md). se(U) rises with U, so U = theta_hat + 2
// se(U) is iterated from the Wald limit. `whiten` returns the whitened design of the fit at a given
// theta. The iteration stops once it passes `cap` (the caller takes the smaller of the two).
double UpperLimitByInversion(const Eigen::VectorXd& theta, int c, const std::vector<int>& positive,
                             double wald_se, double cap,
                             const std::function<Eigen::MatrixXd(const Eigen::VectorXd&)>& whiten) {
  std::vector<int> set = positive;
  if (std::find(set.begin(), set.end(), c) == set.end()) set.push_back(c);
  std::sort(set.begin(), set.end());
  const int at = static_cast<int>(std::find(set.begin(), set.end(), c) - set.begin());
  const double estimate = std::max(theta[c], 0.0);
  double limit = estimate + 2.0 * wald_se;
  for (int pass = 0; pass < 12 && limit < cap && limit > 0.0; ++pass) {
    Eigen::VectorXd alternative = theta.cwiseMax(0.0);
    alternative[c] = limit;
    const Eigen::MatrixXd aw = whiten(alternative);
    if (aw.size() == 0) return limit;
    const double var = ThetaVariances(aw, set)[at];
    if (!(var > 0.0)) return limit;
    const double next = estimate + 2.0 * std::sqrt(var);
    if (std::abs(next - limit) <= 1e-4 * limit) return std::max(limit, next);
    limit = std::max(limit, next);
  }
  if (!(limit < cap)) return limit;
  // Still rising: where the term dominates its points, se(U) grows in proportion to U, and when
  // it does so with a slope of 1/2 or more the record sets no 2-sigma limit on its own.
  return std::numeric_limits<double>::infinity();
}

// A term's value in the engineer's unit, for reasons: "0.12 deg/h".
std::string Engineering(int term, double si) {
  NoiseTerms t;
  *Amplitude(&t, term) = si;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g %s", EngineeringValue(t, term), EngineeringUnit(term));
  return buf;
}

void AddReason(TermAssessment* a, const std::string& reason) {
  a->reliable = false;
  a->reason += (a->reason.empty() ? "" : "; ") + reason;
}

// Per-point model edf 2 v^2 / var(v) and the two-sided interval of v_measured / v_model.
struct PointInterval {
  double low, high;
};
PointInterval ModelInterval(double model_v, double variance, double level) {
  const double edf = 2.0 * model_v * model_v / variance;
  const double tail = 0.5 * (1.0 - level);
  return {stats::ChiSquareQuantile(tail, edf) / edf,
          stats::ChiSquareQuantile(1.0 - tail, edf) / edf};
}

// Misfit ranges, and the terms that carry >= 25 % of the model inside them.
void AssessMisfit(const Points& p, const Eigen::VectorXd& model, const Eigen::VectorXd& variance,
                  const Eigen::MatrixXd& basis, const std::vector<int>& cols,
                  const Eigen::VectorXd& theta, double level, NoiseFitResult* result) {
  std::vector<bool> out(static_cast<size_t>(p.size()), false);
  for (int i = 0; i < p.size(); ++i) {
    if (!(model[i] > 0.0) || !(variance[i] > 0.0)) {
      out[static_cast<size_t>(i)] = true;
      continue;
    }
    const PointInterval iv = ModelInterval(model[i], variance[i], level);
    const double ratio = p.v[i] / model[i];
    out[static_cast<size_t>(i)] = ratio < iv.low || ratio > iv.high;
  }
  // Rows are in tau order in every table fogpipe makes; a range is a run of rows outside.
  std::vector<std::vector<TauRange>> carried(cols.size());
  for (int i = 0; i < p.size(); ++i) {
    if (!out[static_cast<size_t>(i)]) continue;
    int j = i;
    while (j + 1 < p.size() && out[static_cast<size_t>(j + 1)]) ++j;
    const TauRange range{p.tau[i], p.tau[j]};
    result->misfit_ranges.push_back(range);
    for (size_t c = 0; c < cols.size(); ++c) {
      double share = 0.0;
      for (int k = i; k <= j; ++k)
        if (model[k] > 0.0) share = std::max(share, theta[c] * basis(k, c) / model[k]);
      if (share >= 0.25) carried[c].push_back(range);
    }
    i = j;
  }
  for (size_t c = 0; c < cols.size(); ++c)
    if (!carried[c].empty())
      AddReason(&result->assessment[cols[c]],
                "model does not describe the curve at " + FormatTauRanges(carried[c]));
}

// The largest amplitude of term c that no point of the curve contradicts: min over tau of
// sqrt(v_high / b_c(tau)), v_high the upper `tail` chi-square bound of the measured Allan variance
// with the table's own EDF (the bound should not rest on the fit). `at`, if given, receives that
// tau.
double CurveBound(const Points& p, double tail, int c, double* at = nullptr) {
  double bound = std::numeric_limits<double>::infinity();
  if (at) *at = kNaN;
  for (int i = 0; i < p.size(); ++i) {
    const double edf = p.edf[i];
    if (!(edf > 0.0) || !std::isfinite(edf)) continue;
    const double v_high = p.v[i] * edf / stats::ChiSquareQuantile(tail, edf);
    const double b = std::sqrt(v_high / Basis(c, p.tau[i]));
    if (b < bound) {
      bound = b;
      if (at) *at = p.tau[i];
    }
  }
  return bound;
}

// The reported upper limit of the term in column c (IEEE term `term`) of a fit with estimate
// `theta` (amplitudes squared), `positive` its positive columns, and se_theta the standard error
// of theta[c] at the estimate: the inverted 2-sigma test (UpperLimitByInversion, `whiten` the fit's
// whitened design at another theta) capped by what the curve itself allows, which is finite where
// the inversion is not: at every point at once, so each point's bound takes the tail / points
// share (Bonferroni; the minimum over points of 97.7 % bounds covered white noise's N in 61 of 80
// records). FitNoiseTerms and AssessNoiseTerms both report this limit.
double TermUpperLimit(const Points& p, const Eigen::VectorXd& theta, int c, int term,
                      const std::vector<int>& positive, double se_theta,
                      const std::function<Eigen::MatrixXd(const Eigen::VectorXd&)>& whiten) {
  const double curve = CurveBound(p, kUpperLimitTail / p.size(), term);
  return std::min(
      std::sqrt(UpperLimitByInversion(theta, c, positive, se_theta, curve * curve, whiten)), curve);
}

void AssessBound(const Points& p, double level, int c, NoiseFitResult* result) {
  NoiseTerms copy = result->terms;
  const double amp = *Amplitude(&copy, c), se = *StandardError(&copy, c);
  const double margin = std::isfinite(se) ? 2.0 * se : 0.0;
  double at = kNaN;
  const double bound = CurveBound(p, 0.5 * (1.0 - level), c, &at);
  if (amp - margin > bound) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.3g", at);
    AddReason(&result->assessment[c],
              std::string("exceeds the bound the Allan curve sets at tau = ") + buf + " s (" +
                  Engineering(c, bound) + ")");
  }
}

bool Overlaps(const TauRange& a, const std::vector<TauRange>& ranges) {
  for (const TauRange& r : ranges)
    if (a.low_s <= r.high_s && r.low_s <= a.high_s) return true;
  return false;
}

// Agreement of a term with its slope read-off (IEEE 952 Annex C reads each term off the curve where
// the curve has the term's slope), check (3) of noise_fit.h: a significant term's range is
// [a - 2 SE, a + 2 SE], a term not significant has [0, upper limit] and is flagged only where the
// read-off lies in a misfit range. B's read-off is an upper bound (min sigma / 0.664), checked by
// AssessBound instead.
void AssessReadoff(int c, NoiseFitResult* result) {
  TermAssessment& a = result->assessment[c];
  NoiseTerms terms = result->terms, readoff = result->slope_readoff;
  const double ro = *Amplitude(&readoff, c);
  if (c == 2 || !std::isfinite(ro) || !(ro > 0.0)) return;
  const double amp = *Amplitude(&terms, c), se = *StandardError(&terms, c);
  const TauRange& at = result->readoff_taus[c];
  if (a.significant && amp > 0.0) {
    const double margin = std::isfinite(se) ? 2.0 * se : 0.0;
    if (amp - margin > 2.0 * ro || amp + margin < 0.5 * ro)
      AddReason(&a, "differs from its slope read-off " + Engineering(c, ro) + " by more than 2x");
  } else if (std::isfinite(a.upper_limit) && a.upper_limit < 0.5 * ro &&
             Overlaps(at, result->misfit_ranges)) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.3g x its upper limit %s, read at %s", ro / a.upper_limit,
                  Engineering(c, a.upper_limit).c_str(), FormatTauRanges({at}).c_str());
    AddReason(&a, "not significant, but its slope read-off " + Engineering(c, ro) + " is " + buf +
                      " where the model misses the curve");
  }
}

// Checks (2) and (3) of noise_fit.h for the terms in `cols`: a significant term's bound from the
// curve, and every term's agreement with its slope read-off.
void AssessAgainstTheCurve(const Points& p, double level, const std::vector<int>& cols,
                           NoiseFitResult* result) {
  NoiseTerms terms = result->terms;
  for (int c : cols) {
    if (result->assessment[c].significant && *Amplitude(&terms, c) > 0.0)
      AssessBound(p, level, c, result);
    AssessReadoff(c, result);
  }
}

}  // namespace

void MarkTermsAboveUnfiltered(const NoiseFitResult& unfiltered, NoiseFitResult* filtered) {
  NoiseTerms terms = filtered->terms;
  for (int j = 0; j < kTerms; ++j) {
    const double limit = unfiltered.assessment[j].upper_limit;
    const double amplitude = *Amplitude(&terms, j);
    if (!std::isfinite(limit) || !(amplitude > limit)) continue;
    TermAssessment& a = filtered->assessment[j];
    a.reliable = false;
    char text[200];
    std::snprintf(text, sizeof(text),
                  "above the unfiltered signal's upper limit (%.3g x): a filter removes noise, "
                  "this reads the filter's Allan shape",
                  amplitude / limit);
    a.reason += (a.reason.empty() ? "" : "; ") + std::string(text);
  }
}

NoiseFitResult AssessNoiseTerms(const AllanTable& table, const NoiseTerms& terms,
                                const std::function<double(double)>& other_variance,
                                double relative_tolerance, const NoiseFitOptions& options) {
  NoiseFitResult result;
  result.terms = terms;
  std::string error = "the IEEE 952 model is that of the Allan variance";
  if (!options.IsValid(&error) || !IeeeModelApplies(table.deviation)) {
    result.summary = {Termination::kInvalidOptions, error};
    return result;
  }
  NoiseFitSummary& summary = result.summary;
  NoiseTerms given = terms;
  std::vector<int> cols;
  for (int j = 0; j < kTerms; ++j)
    if (std::isfinite(*Amplitude(&given, j))) cols.push_back(j);
  const Points p = SelectRows(table, options);
  const int npts = p.size(), ncol = static_cast<int>(cols.size());
  summary.points = npts;
  if (npts > 0) result.fitted_range = {p.tau.front(), p.tau.back()};
  const AnchoredReadoffs readoffs = ReadOff(table, options.readoff_slope_tolerance);
  result.slope_readoff = readoffs.value;
  result.readoff_taus = readoffs.taus;
  if (npts == 0 || ncol == 0 || !p.have_edf) {
    summary.termination = Termination::kInsufficientData;
    summary.message = "no term, or no table row with an EDF, to check";
    return result;
  }
  Eigen::MatrixXd basis(npts, ncol);
  Eigen::VectorXd theta(ncol), model(npts), variance(npts);
  std::vector<int> positive;
  for (int c = 0; c < ncol; ++c) {
    const double a = *Amplitude(&given, cols[c]);
    theta[c] = a * a;
    if (a > 0.0) positive.push_back(c);
    for (int i = 0; i < npts; ++i) basis(i, c) = Basis(cols[c], p.tau[i]);
  }
  // Each point's Allan variance v under a model theta_alt, and the variance of its estimate: the
  // sampling variance 2 v^2 / edf and the claimed relative shape tolerance.
  const auto model_at = [&](const Eigen::VectorXd& theta_alt, int i) {
    return basis.row(i).dot(theta_alt) + (other_variance ? other_variance(p.tau[i]) : 0.0);
  };
  const auto variance_of = [&](double v, int i) {
    return (2.0 / p.edf[i] + relative_tolerance * relative_tolerance) * v * v;
  };
  for (int i = 0; i < npts; ++i) {
    model[i] = model_at(theta, i);
    variance[i] = variance_of(model[i], i);
  }
  const auto whiten_at = [&](const Eigen::VectorXd& alternative) {
    Eigen::MatrixXd aw = basis;
    for (int i = 0; i < npts; ++i) aw.row(i) /= std::sqrt(variance_of(model_at(alternative, i), i));
    return aw;
  };
  for (int c = 0; c < ncol; ++c) {
    const double a = *Amplitude(&given, cols[c]), se = *StandardError(&given, cols[c]);
    const double se_theta = a > 0.0 ? 2.0 * a * se : se * se;
    TermAssessment& t = result.assessment[cols[c]];
    // A term held at zero without an upper limit (se 0) has no z and no limit: unknown, not 0.
    const bool known = a > 0.0 || se_theta > 0.0;
    t.z = !known ? kNaN : a > 0.0 ? theta[c] / se_theta : 0.0;
    t.significant = t.z > options.significance_z;
    // As FitNoiseTerms: the shared rule wherever there is a standard error to start from.
    t.upper_limit = !known ? kNaN
                    : se_theta > 0.0
                        ? TermUpperLimit(p, theta, c, cols[c], positive, se_theta, whiten_at)
                        : std::sqrt(theta[c]);
  }
  AssessMisfit(p, model, variance, basis, cols, theta, options.misfit_level, &result);
  AssessAgainstTheCurve(p, options.misfit_level, cols, &result);
  summary.message = "checked on " + std::to_string(npts) + " points";
  return result;
}

const char* TermSymbol(int term) {
  static const char* kSymbols[kTerms] = {"Q", "N", "B", "K", "R"};
  return term >= 0 && term < kTerms ? kSymbols[term] : "?";
}

double EngineeringValue(const NoiseTerms& terms, int term) {
  const NoiseTermsEngineering e = ToEngineeringUnits(terms);
  const double v[kTerms] = {e.q_arcsec, e.n_deg_sqrt_h, e.b_deg_h, e.k_deg_h_sqrt_h, e.r_deg_h2};
  return v[term];
}

double EngineeringStandardError(const NoiseTerms& terms, int term) {
  const NoiseTermsEngineering e = ToEngineeringUnits(terms);
  const double se[kTerms] = {e.q_se, e.n_se, e.b_se, e.k_se, e.r_se};
  return se[term];
}

double EngineeringAmplitude(int term, double amplitude_si) {
  NoiseTerms t;
  *Amplitude(&t, term) = amplitude_si;
  return EngineeringValue(t, term);
}

const char* EngineeringUnit(int term) {
  static const char* kUnits[kTerms] = {units::kQuantizationUnit, units::kArwUnit, units::kBiasUnit,
                                       units::kRrwUnit, units::kRampUnit};
  return kUnits[term];
}

std::string FormatTauRanges(const std::vector<TauRange>& ranges) {
  std::string s;
  for (const TauRange& r : ranges) {
    char buf[64];
    if (r.low_s == r.high_s)
      std::snprintf(buf, sizeof buf, "%.3g s", r.low_s);
    else
      std::snprintf(buf, sizeof buf, "%.3g-%.3g s", r.low_s, r.high_s);
    s += (s.empty() ? "" : ", ") + std::string(buf);
  }
  return s;
}

int UnreliableTermCount(const NoiseFitResult& fit) {
  int n = 0;
  for (const TermAssessment& a : fit.assessment) n += a.reliable ? 0 : 1;
  return n;
}

NoiseFitResult FitNoiseTerms(const AllanTable& table, const NoiseFitOptions& options) {
  NoiseFitResult result;
  NoiseFitSummary& summary = result.summary;
  std::string error;
  if (!options.IsValid(&error)) {
    summary.termination = Termination::kInvalidOptions;
    summary.message = error;
    return result;
  }
  if (!IeeeModelApplies(table.deviation)) {
    summary.termination = Termination::kInvalidOptions;
    summary.message = std::string(
                          "the IEEE 952 model is that of the Allan variance; fit an OADEV "
                          "or ADEV table, not ") +
                      ToString(table.deviation);
    return result;
  }
  const bool enabled[kTerms] = {options.fit_q, options.fit_n, options.fit_b, options.fit_k,
                                options.fit_r};
  std::vector<int> cols;
  for (int j = 0; j < kTerms; ++j)
    if (enabled[j]) cols.push_back(j);
  const Points p = SelectRows(table, options);
  const int npts = p.size();
  const int ncol = static_cast<int>(cols.size());
  summary.points = npts;
  if (npts > 0) result.fitted_range = {p.tau.front(), p.tau.back()};
  if (npts < ncol) {
    summary.termination = Termination::kInsufficientData;
    summary.message = "fewer usable table rows than terms to fit";
    return result;
  }
  Eigen::MatrixXd basis(npts, ncol);
  for (int i = 0; i < npts; ++i)
    for (int c = 0; c < ncol; ++c) basis(i, c) = Basis(cols[c], p.tau[i]);
  const Eigen::Map<const Eigen::VectorXd> measured(p.v.data(), npts);

  // Step 1: the diagonal fit (the start of GLS, and the fit itself when GLS does not apply).
  bool converged = true;
  Eigen::VectorXd model_v = measured, theta = Eigen::VectorXd::Zero(ncol), sqrt_w;
  for (int pass = 0; pass <= options.reweight_iterations; ++pass) {
    sqrt_w = DiagonalSqrtWeights(p, model_v);
    theta = SolveScaled(sqrt_w.asDiagonal() * basis, sqrt_w.cwiseProduct(measured), &converged);
    model_v = basis * theta;
    ++summary.iterations;
  }
  Whitened w{sqrt_w.asDiagonal() * basis, sqrt_w.cwiseProduct(measured - model_v),
             Eigen::VectorXd()};

  // Step 2: GLS on the model covariance of the overlapping Allan variances (kept for the upper
  // limits of step 3).
  double t0 = 0.0;
  std::shared_ptr<const AvarCovarianceModel> gls_cov;
  if (options.correlated && CovarianceModelApplies(table, p, &t0)) {
    gls_cov = SharedAvarCovarianceModel(p.m, p.count, t0);
    const AvarCovarianceModel& cov = *gls_cov;
    Eigen::VectorXd theta_gls = theta;
    Whitened wg;
    if (GeneralizedFit(p, basis, cols, cov, 0.0, options.gls_iterations, &theta_gls, &converged,
                       &summary.iterations, &wg)) {
      theta = theta_gls, w = wg, model_v = basis * theta;
      result.generalized = true;
      const int dof = npts - PositiveCount(theta);
      const double p_value = dof > 0 ? stats::ChiSquareSurvival(w.rw.squaredNorm(), dof) : 1.0;
      if (options.discrepancy_below_p > 0.0 && p_value < options.discrepancy_below_p) {
        Whitened wd;
        result.model_discrepancy = FitWithDiscrepancy(p, basis, cols, cov, options, &theta,
                                                      &converged, &summary.iterations, &wd);
        // Sampling-only residuals and point variances of the final model (the goodness of fit
        // and the misfit ranges), the inflated covariance for the standard errors.
        Whitened w0;
        Eigen::VectorXd t = theta;
        GeneralizedFit(p, basis, cols, cov, 0.0, 0, &t, &converged, &summary.iterations, &w0);
        w = wd;
        model_v = basis * theta;
        result.chi2 = w0.rw.squaredNorm();
        w.point_variance = w0.point_variance;
      }
    }
  }
  if (!w.point_variance.size() && p.have_edf)
    w.point_variance = (2.0 * model_v.array().square() /
                        Eigen::Map<const Eigen::VectorXd>(p.edf.data(), npts).array())
                           .matrix();

  // Step 3: chi2, standard errors, significance and upper limits.
  if (!(result.model_discrepancy > 0.0)) result.chi2 = w.rw.squaredNorm();
  std::vector<int> free;
  for (int c = 0; c < ncol; ++c)
    if (theta[c] > 0.0) free.push_back(c);
  summary.free_terms = static_cast<int>(free.size());
  result.dof = npts - summary.free_terms;
  if (p.have_edf && result.dof > 0)
    result.p_value = stats::ChiSquareSurvival(result.chi2, result.dof);

  // The whitened design at another theta, as the fit whitened it at its estimate.
  const auto whiten_at = [&](const Eigen::VectorXd& alternative) -> Eigen::MatrixXd {
    if (!result.generalized)
      return DiagonalSqrtWeights(p, basis * alternative).asDiagonal() * basis;
    Eigen::VectorXd t = alternative;
    Whitened out;
    bool ok = true;
    int solves = 0;
    if (!GeneralizedFit(p, basis, cols, *gls_cov, result.model_discrepancy, 0, &t, &ok, &solves,
                        &out))
      return Eigen::MatrixXd();
    return out.aw;
  };
  NoiseTerms& terms = result.terms;
  for (int j = 0; j < kTerms; ++j) *Amplitude(&terms, j) = enabled[j] ? 0.0 : kNaN;
  std::vector<int> all(static_cast<size_t>(ncol));
  for (int c = 0; c < ncol; ++c) all[c] = c;
  const Eigen::VectorXd var_free = free.empty() ? Eigen::VectorXd() : ThetaVariances(w.aw, free);
  const Eigen::VectorXd var_all = ThetaVariances(w.aw, all);
  for (int c = 0; c < ncol; ++c) {
    TermAssessment& a = result.assessment[cols[c]];
    const auto k = std::find(free.begin(), free.end(), c);
    const double var = k != free.end() ? var_free[k - free.begin()] : var_all[c];
    const double se_theta = p.have_edf && var > 0.0 ? std::sqrt(var) : kNaN;
    if (k != free.end()) {
      const double amp = std::sqrt(theta[c]);
      *Amplitude(&terms, cols[c]) = amp;
      *StandardError(&terms, cols[c]) = se_theta / (2.0 * amp);
      a.z = theta[c] / se_theta;
    } else {
      // Held at zero: the "standard error" is the one-sigma upper limit sqrt(se(a^2)).
      *StandardError(&terms, cols[c]) = std::sqrt(se_theta);
      a.z = p.have_edf ? 0.0 : kNaN;
    }
    a.significant = a.z > options.significance_z;
    a.upper_limit = std::sqrt(std::max(theta[c], 0.0) + 2.0 * se_theta);
    if (p.have_edf && se_theta > 0.0)
      a.upper_limit = TermUpperLimit(p, theta, c, cols[c], free, se_theta, whiten_at);
  }

  // Step 4: read-offs and the honesty checks.
  const AnchoredReadoffs readoffs = ReadOff(table, options.readoff_slope_tolerance);
  result.slope_readoff = readoffs.value;
  result.readoff_taus = readoffs.taus;
  if (p.have_edf) {
    AssessMisfit(p, model_v, w.point_variance, basis, cols, theta, options.misfit_level, &result);
    AssessAgainstTheCurve(p, options.misfit_level, cols, &result);
  }
  summary.termination = converged ? Termination::kSuccess : Termination::kNoConvergence;
  summary.message =
      std::string(result.generalized ? "generalised" : "weighted") + " NNLS on " +
      std::to_string(npts) + " points, " + std::to_string(summary.free_terms) + " terms positive" +
      (result.model_discrepancy > 0.0
           ? " (model rejected: relative discrepancy " +
                 std::to_string(result.model_discrepancy).substr(0, 6) + " added to each point)"
           : "") +
      (!p.have_edf          ? " (no EDF: unit weights, no standard errors)"
       : result.generalized ? ""
                            : " (points treated as independent: optimistic "
                              "standard errors)");
  return result;
}

}  // namespace fogpipe::allan
