// The five IEEE Std 952-1997 noise terms from an Allan table, fitted together, and the classic
// slope read-offs as a cross-check (IEEE 952 Annex C; method.md's table).
//
// Fit: sigma^2(tau) = 3Q^2/tau^2 + N^2/tau + (2 ln2/pi) B^2 + K^2 tau/3 + R^2 tau^2/2 is linear in
// theta = (Q^2, N^2, B^2, K^2, R^2) >= 0, so it is solved by non-negative weighted least squares
// (Lawson-Hanson, nnls.h) on the variances. An Allan variance estimate with edf degrees of freedom
// has var(sigma^2_hat) ~ 2 sigma^4 / edf (chi-square), so point i gets weight edf_i / (2 v_i^2).
// v_i is the *model* variance from the previous pass (iteratively reweighted, starting from the
// measured one), because weighting by the measured value favours points that fluctuated low and
// biases the fit downwards. Standard errors come from the inverse of the weighted normal matrix on
// the free terms, carried to amplitudes by the delta method, se(a) = se(a^2) / (2 a).
//
// Caveats, stated rather than hidden: (1) Allan estimates at neighbouring taus share data and are
// correlated; the fit treats them as independent, so the standard errors are optimistic, the more
// so the denser the grid (use octave or ~5-per-decade grids for fitting). (2) The bias-instability
// term is the flat floor of flicker noise; a real flicker region ends at a cut-off, and the floor
// is only visible between the ARW and RRW slopes. (3) The model terms are the continuous-time
// IEEE forms; at tau of a few samples a sampled process deviates slightly from them.
#pragma once

#include <limits>
#include <string>

#include "algorithms/allan/allan.h"
#include "algorithms/common/status.h"

namespace fogpipe::allan {

/// Amplitudes in SI and their standard errors (same units). A term that the fit holds at zero has
/// amplitude 0 and as its "standard error" the one-sigma upper limit sqrt(se(a^2)). NaN means not
/// estimated (term switched off, or a slope read-off that found no matching slope).
struct NoiseTerms {
  double q_rad = 0.0;           ///< Quantization Q [rad].
  double n_rad_sqrt_s = 0.0;    ///< Angle random walk N [rad/sqrt(s)].
  double b_rad_s = 0.0;         ///< Bias instability B [rad/s].
  double k_rad_s_sqrt_s = 0.0;  ///< Rate random walk K [rad/s/sqrt(s)].
  double r_rad_s2 = 0.0;        ///< Rate ramp R [rad/s^2].
  double q_se = std::numeric_limits<double>::quiet_NaN();
  double n_se = std::numeric_limits<double>::quiet_NaN();
  double b_se = std::numeric_limits<double>::quiet_NaN();
  double k_se = std::numeric_limits<double>::quiet_NaN();
  double r_se = std::numeric_limits<double>::quiet_NaN();
};

/// The same terms in the units a gyro engineer reads (units.h): Q arcsec, N deg/sqrt(h),
/// B deg/h, K deg/h/sqrt(h), R deg/h^2; standard errors likewise.
struct NoiseTermsEngineering {
  double q_arcsec, n_deg_sqrt_h, b_deg_h, k_deg_h_sqrt_h, r_deg_h2;
  double q_se, n_se, b_se, k_se, r_se;
};
NoiseTermsEngineering ToEngineeringUnits(const NoiseTerms& terms);

struct NoiseFitOptions {
  bool fit_q = true, fit_n = true, fit_b = true, fit_k = true, fit_r = true;
  /// Only rows with min_tau_s <= tau_s <= max_tau_s are fitted.
  double min_tau_s = 0.0;
  double max_tau_s = std::numeric_limits<double>::infinity();
  /// Reweighting passes after the first (weights from the previous model). Default 3.
  int reweight_iterations = 3;
  /// Largest |local slope - term slope| accepted by a slope read-off. Default 0.15.
  double readoff_slope_tolerance = 0.15;

  bool IsValid(std::string* error) const;
};

struct NoiseFitSummary {
  Termination termination = Termination::kSuccess;
  std::string message;
  int points = 0;      ///< Table rows used.
  int free_terms = 0;  ///< Terms the fit left positive.
  int iterations = 0;  ///< Weighted NNLS solves.
};

struct NoiseFitResult {
  NoiseTerms terms;          ///< The joint NNLS fit.
  NoiseTerms slope_readoff;  ///< Read-offs: N = sigma(1 s) on the -1/2 line, etc. (no SEs).
  double chi2 = std::numeric_limits<double>::quiet_NaN();  ///< Weighted residual sum.
  int dof = 0;                                             ///< points - free terms.
  NoiseFitSummary summary;
};

/// Fits an OADEV or ADEV table (a Hadamard table gives kInvalidOptions: its term coefficients
/// differ). tau_s, sigma and edf are used; rows with non-finite or non-positive values are
/// skipped. If the table has no EDF at all (confidence intervals off), every point gets edf = 1
/// (relative least squares) and the standard errors are NaN; otherwise rows without EDF are
/// skipped.
NoiseFitResult FitNoiseTerms(const AllanTable& table, const NoiseFitOptions& options);

/// The model sigma^2(tau) [(rad/s)^2] of the five terms.
double NoiseModelVariance(const NoiseTerms& terms, double tau_s);

/// The read-offs alone: for each slope s in {-1, -1/2, +1/2, +1}, the adjacent pair of rows whose
/// local log-log slope is closest to s (within `slope_tolerance`) anchors a line of slope s, read
/// at tau = sqrt(3) (Q), 1 (N), 3 (K), sqrt(2) (R) s; B = min sigma / sqrt(2 ln2 / pi)
/// (= / 0.6643).
NoiseTerms SlopeReadoffs(const AllanTable& table, double slope_tolerance);

}  // namespace fogpipe::allan
