#include "algorithms/allan/noise_fit.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "algorithms/allan/nnls.h"
#include "algorithms/allan/noise_model.h"
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

NoiseTerms SlopeReadoffs(const AllanTable& table, double slope_tolerance) {
  NoiseTerms out;
  out.q_rad = out.n_rad_sqrt_s = out.b_rad_s = out.k_rad_s_sqrt_s = out.r_rad_s2 = kNaN;
  std::vector<size_t> rows;
  for (size_t i = 0; i < table.size(); ++i)
    if (table.tau_s[i] > 0.0 && table.sigma[i] > 0.0 && std::isfinite(table.sigma[i]))
      rows.push_back(i);
  if (rows.empty()) return out;
  double min_sigma = table.sigma[rows[0]];
  for (size_t i : rows) min_sigma = std::min(min_sigma, table.sigma[i]);
  out.b_rad_s = min_sigma / std::sqrt(2.0 * std::log(2.0) / units::kPi);
  // (slope, tau at which the line is read, factor turning the read value into the amplitude)
  struct Readoff {
    int term;         // index into kTermOrder
    double tau_read;  // where the line is read [s]
  };
  const Readoff readoffs[] = {{0, std::sqrt(3.0)}, {1, 1.0}, {3, 3.0}, {4, std::sqrt(2.0)}};
  for (const Readoff& r : readoffs) {
    const double target = TermSlope(kTermOrder[r.term]);
    double best = slope_tolerance;
    double value = kNaN;
    for (size_t k = 0; k + 1 < rows.size(); ++k) {
      const double lt0 = std::log(table.tau_s[rows[k]]), lt1 = std::log(table.tau_s[rows[k + 1]]);
      const double ls0 = std::log(table.sigma[rows[k]]), ls1 = std::log(table.sigma[rows[k + 1]]);
      const double slope = (ls1 - ls0) / (lt1 - lt0);
      if (std::abs(slope - target) <= best) {
        best = std::abs(slope - target);
        const double lt = 0.5 * (lt0 + lt1), ls = 0.5 * (ls0 + ls1);
        value = std::exp(ls + target * (std::log(r.tau_read) - lt));
      }
    }
    *Amplitude(&out, r.term) = value;
  }
  return out;
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
  if (table.deviation == Deviation::kOverlappingHadamard ||
      table.deviation == Deviation::kHadamard) {
    summary.termination = Termination::kInvalidOptions;
    summary.message =
        "the IEEE 952 model is that of the Allan variance; fit an OADEV or ADEV table";
    return result;
  }
  const bool enabled[kTerms] = {options.fit_q, options.fit_n, options.fit_b, options.fit_k,
                                options.fit_r};
  std::vector<int> cols;
  for (int j = 0; j < kTerms; ++j)
    if (enabled[j]) cols.push_back(j);
  // Rows with an EDF are weighted by it; if no row has one, all get edf = 1 (relative least
  // squares) and no standard errors are given. Rows without EDF in a table that has some are
  // skipped (they are the ones whose noise type admits no EDF).
  bool have_edf = false;
  for (size_t i = 0; i < table.size() && i < table.edf.size(); ++i)
    if (table.edf[i] > 0.0 && std::isfinite(table.edf[i])) have_edf = true;
  std::vector<double> tau, v, edf;
  for (size_t i = 0; i < table.size(); ++i) {
    const double t = table.tau_s[i], s = table.sigma[i];
    if (!(t >= options.min_tau_s && t <= options.max_tau_s) || !(s > 0.0) || !std::isfinite(s))
      continue;
    const double e = i < table.edf.size() ? table.edf[i] : kNaN;
    if (have_edf && !(e > 0.0 && std::isfinite(e))) continue;
    tau.push_back(t);
    v.push_back(s * s);
    edf.push_back(have_edf ? e : 1.0);
  }
  const int npts = static_cast<int>(tau.size());
  const int ncol = static_cast<int>(cols.size());
  summary.points = npts;
  if (npts < ncol) {
    summary.termination = Termination::kInsufficientData;
    summary.message = "fewer usable table rows than terms to fit";
    return result;
  }
  // Design matrix on unit amplitudes, then columns scaled to unit weighted norm for conditioning.
  Eigen::MatrixXd basis(npts, ncol);
  for (int i = 0; i < npts; ++i)
    for (int c = 0; c < ncol; ++c) basis(i, c) = Basis(cols[c], tau[i]);
  const Eigen::Map<const Eigen::VectorXd> measured(v.data(), npts);
  Eigen::VectorXd model_v = measured;
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(ncol);
  Eigen::VectorXd sqrt_w(npts);
  bool converged = true;
  for (int pass = 0; pass <= options.reweight_iterations; ++pass) {
    for (int i = 0; i < npts; ++i) {
      // var(sigma^2_hat) = 2 v^2 / edf; the model value once available, never below 1e-6 of the
      // measurement (a term the fit has not yet found must not get an infinite weight).
      const double vi = std::max(model_v[i], 1e-6 * measured[i]);
      sqrt_w[i] = std::sqrt(edf[i] / 2.0) / vi;
    }
    Eigen::MatrixXd a = sqrt_w.asDiagonal() * basis;
    const Eigen::VectorXd scale = a.colwise().norm().transpose();
    for (int c = 0; c < ncol; ++c) a.col(c) /= scale[c];
    const Eigen::VectorXd b = sqrt_w.cwiseProduct(measured);
    const NnlsResult nnls = SolveNnls(a, b);
    converged = converged && nnls.converged;
    theta = nnls.x.cwiseQuotient(scale);
    model_v = basis * theta;
    ++summary.iterations;
  }
  // Final weights (those the last solve used) for chi2 and the covariance.
  const Eigen::MatrixXd aw = sqrt_w.asDiagonal() * basis;
  const Eigen::VectorXd resid = sqrt_w.cwiseProduct(measured - model_v);
  result.chi2 = resid.squaredNorm();
  std::vector<int> free;
  for (int c = 0; c < ncol; ++c)
    if (theta[c] > 0.0) free.push_back(c);
  summary.free_terms = static_cast<int>(free.size());
  result.dof = npts - summary.free_terms;

  NoiseTerms& terms = result.terms;
  for (int j = 0; j < kTerms; ++j) *Amplitude(&terms, j) = enabled[j] ? 0.0 : kNaN;
  // Covariance of theta on the free set: (A_F^T W A_F)^-1; for held-at-zero terms, the variance
  // from the full normal matrix gives the one-sigma upper limit.
  auto covariance_diagonal = [&](const std::vector<int>& set) {
    Eigen::MatrixXd af(npts, static_cast<Eigen::Index>(set.size()));
    for (size_t k = 0; k < set.size(); ++k) af.col(static_cast<Eigen::Index>(k)) = aw.col(set[k]);
    const Eigen::VectorXd s = af.colwise().norm().transpose();
    for (Eigen::Index k = 0; k < af.cols(); ++k) af.col(k) /= s[k];
    const Eigen::MatrixXd normal = af.transpose() * af;
    const Eigen::MatrixXd inv =
        normal.ldlt().solve(Eigen::MatrixXd::Identity(normal.rows(), normal.cols()));
    Eigen::VectorXd diag(set.size());
    for (Eigen::Index k = 0; k < diag.size(); ++k) diag[k] = inv(k, k) / (s[k] * s[k]);
    return diag;
  };
  std::vector<int> all(static_cast<size_t>(ncol));
  for (int c = 0; c < ncol; ++c) all[c] = c;
  const Eigen::VectorXd var_free = free.empty() ? Eigen::VectorXd() : covariance_diagonal(free);
  const Eigen::VectorXd var_all = covariance_diagonal(all);
  for (size_t k = 0; k < free.size(); ++k) {
    const int c = free[k];
    const double amp = std::sqrt(theta[c]);
    *Amplitude(&terms, cols[c]) = amp;
    if (have_edf) *StandardError(&terms, cols[c]) = std::sqrt(var_free[k]) / (2.0 * amp);
  }
  for (int c = 0; c < ncol; ++c)
    if (theta[c] <= 0.0 && have_edf && var_all[c] > 0.0)
      *StandardError(&terms, cols[c]) = std::sqrt(std::sqrt(var_all[c]));

  result.slope_readoff = SlopeReadoffs(table, options.readoff_slope_tolerance);
  summary.termination = converged ? Termination::kSuccess : Termination::kNoConvergence;
  summary.message = "weighted NNLS on " + std::to_string(npts) + " points, " +
                    std::to_string(summary.free_terms) + " terms positive" +
                    (have_edf ? "" : " (no EDF: unit weights, no standard errors)");
  return result;
}

}  // namespace fogpipe::allan
