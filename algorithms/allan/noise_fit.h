// The five IEEE Std 952-1997 noise terms from an Allan table, fitted together, and the classic
// slope read-offs as a cross-check (IEEE 952 Annex C; docs/method.md, "Allan variance of the noise
// terms").
//
// Fit: sigma^2(tau) = 3Q^2/tau^2 + N^2/tau + (2 ln2/pi) B^2 + K^2 tau/3 + R^2 tau^2/2 is linear in
// theta = (Q^2, N^2, B^2, K^2, R^2) >= 0. It is solved by generalised non-negative least squares
// on the variances: the covariance matrix C of the overlapping Allan-variance estimates is computed
// from the current model (avar_covariance.h: exact for Gaussian noise, neighbouring taus share
// data and are strongly correlated), the system is whitened by C's Cholesky factor and solved by
// Lawson-Hanson NNLS (nnls.h); C is recomputed from the new model until theta settles. The start
// is the diagonal fit with weights edf / (2 v^2), v the model variance of the previous pass
// (weighting by the measured value favours points that fluctuated low and biases the fit down).
// Cov(theta) = (A_F^T C^-1 A_F)^-1 on the terms left positive; chi2 = r^T C^-1 r on
// points - positive terms degrees of freedom, with its chi-square p-value. Why GLS and not the
// diagonal weights: with independent-point weights the standard errors are too small and absent
// terms come out "significant" too often (measured in docs/allan-noise-fit.md, "Calibration").
//
// Significance is judged on the variance coefficient theta_j, which is linear in the data and
// nearly Gaussian: z = theta_j / se(theta_j) > 2. The amplitude's standard error se(a) = se(a^2) /
// (2a) (delta method) is only meaningful for significant terms.
//
// Honesty checks per term (TermAssessment): (1) the tau ranges where the measured variance leaves
// the model's 99.7 % chi-square interval (edf of each point from the model covariance, 2 v^2 /
// C_ii) are "misfit ranges"; a term carrying >= 25 % of the model there is marked unreliable;
// (2) no term may exceed the curve: a_j^2 b_j(tau) <= the upper 99.85 % bound of sigma^2(tau) at
// every tau (for B this is the Allan-minimum read-off min sigma / 0.664, for N the long-tau bound
// sigma(tau) sqrt(tau)); (3) a term with a slope read-off must be within a factor 2 of it (beyond
// 2 standard errors): the read-off extrapolates a local line with slope tolerance 0.15 over up to
// two decades, which moves it by up to ~2x. A term that is not significant is compared through its
// upper limit, and flagged when its read-off exceeds twice that limit at taus (readoff_taus) inside
// a misfit range: the curve has the term's slope where the data leave the model, so the limit does
// not hold there. Outside misfit ranges the model reproduces that slope with its neighbouring terms
// (Q into B passes N's -1/2), which a read-off cannot tell apart, and no flag is raised.
//
// When the model is rejected (p < 1e-3, usual on real gyros) the GLS weights trust the model's
// shape more than the data and the terms can leave the curve's level; a relative model
// discrepancy d, independent per point, is then added to C with d chosen so that chi2 / dof = 1
// (a standard "model error" inflation) and the terms refitted; their standard errors include it.
//
// Caveats: the bias-instability term is the flat floor of flicker noise; a real flicker region
// ends at a cut-off, and the floor is only visible between the ARW and RRW slopes. The model terms
// are the continuous-time IEEE forms; at tau of a few samples a sampled process deviates slightly
// from them. A non-overlapping ADEV table is fitted with the diagonal weights only (its
// covariance is not modelled): its standard errors are then optimistic, and the summary says so.
#pragma once

#include <array>
#include <functional>
#include <limits>
#include <string>
#include <vector>

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
  /// Generalised least squares with the model covariance of the Allan points (default true);
  /// false = the diagonal weights alone (points treated as independent).
  bool correlated = true;
  /// GLS passes (covariance recomputed from the previous model). Default 8.
  int gls_iterations = 8;
  /// A term is significant when theta / se(theta) exceeds this. Default 2.
  double significance_z = 2.0;
  /// Two-sided level of the per-point interval that defines the misfit ranges. Default 0.997.
  double misfit_level = 0.997;
  /// When the GLS fit's p-value is below this, a relative model discrepancy d (independent,
  /// d * model on each point's standard deviation) is added so that chi2 / dof = 1, and the terms
  /// are refitted with it (robust option for real gyros; 0 disables). Default 1e-3.
  double discrepancy_below_p = 1e-3;

  bool IsValid(std::string* error) const;
};

struct NoiseFitSummary {
  Termination termination = Termination::kSuccess;
  std::string message;
  int points = 0;      ///< Table rows used.
  int free_terms = 0;  ///< Terms the fit left positive.
  int iterations = 0;  ///< Weighted NNLS solves.
};

/// Index of a term in NoiseFitResult::assessment and TermSymbol: Q, N, B, K, R.
constexpr int kNoiseTermCount = 5;
/// "Q", "N", "B", "K", "R".
const char* TermSymbol(int term);
/// Amplitude of term j of `terms` in its engineer's unit (ToEngineeringUnits), and that unit
/// (units.h: arcsec, deg/sqrt(h), deg/h, deg/h/sqrt(h), deg/h^2).
double EngineeringValue(const NoiseTerms& terms, int term);
/// The standard error of term j of `terms` in the term's engineer's unit.
double EngineeringStandardError(const NoiseTerms& terms, int term);
/// An amplitude of term j in its SI unit (a term's value or its upper limit) in the engineer's
/// unit.
double EngineeringAmplitude(int term, double amplitude_si);
const char* EngineeringUnit(int term);

/// Reliability of one fitted term.
struct TermAssessment {
  /// theta / se(theta) for the variance coefficient theta = a^2 [dimensionless]; 0 for a term held
  /// at zero, NaN when not fitted or without standard errors.
  double z = std::numeric_limits<double>::quiet_NaN();
  bool significant = false;  ///< z > NoiseFitOptions::significance_z.
  /// Upper limit of the amplitude, sqrt(theta + 2 se(theta)) [the term's SI unit]; NaN if unknown.
  double upper_limit = std::numeric_limits<double>::quiet_NaN();
  bool reliable = true;  ///< false when a check in the file comment failed; `reason` says which.
  std::string reason;    ///< "; "-joined reasons, empty when reliable.
};

/// A stretch of the tau axis [s].
struct TauRange {
  double low_s = 0.0, high_s = 0.0;
};

struct NoiseFitResult {
  NoiseTerms terms;          ///< The joint fit.
  NoiseTerms slope_readoff;  ///< Read-offs: N = sigma(1 s) on the -1/2 line, etc. (no SEs).
  /// Per term Q, N, B, K, R: the pair of taus each read-off's line was anchored at [s]
  /// (B: the tau of the Allan minimum; 0, 0 where there is no read-off).
  std::array<TauRange, kNoiseTermCount> readoff_taus{};
  /// Generalised residual sum r^T C^-1 r [dimensionless] (diagonal weights without GLS).
  double chi2 = std::numeric_limits<double>::quiet_NaN();
  int dof = 0;  ///< points - free terms.
  /// P(chi-square(dof) > chi2) [dimensionless]; NaN without standard errors or with dof = 0.
  double p_value = std::numeric_limits<double>::quiet_NaN();
  /// Tau ranges where the measured Allan variance leaves the model's interval (file comment).
  std::vector<TauRange> misfit_ranges;
  /// The shortest and longest tau of the rows fitted [s] (0, 0 when none was).
  TauRange fitted_range;
  /// Per term, in the order Q, N, B, K, R.
  std::array<TermAssessment, kNoiseTermCount> assessment;
  bool generalized = false;  ///< true when the GLS covariance was used.
  /// Relative model discrepancy d added because the model was rejected [1]; 0 when not needed.
  /// chi2 and p_value stay those of the sampling covariance alone.
  double model_discrepancy = 0.0;
  NoiseFitSummary summary;
};

/// "0.1-0.3 s, 200-800 s" (3 significant digits), or "" when there is no range.
std::string FormatTauRanges(const std::vector<TauRange>& ranges);

/// Number of fitted terms marked unreliable.
int UnreliableTermCount(const NoiseFitResult& fit);

/// Fits an OADEV or ADEV table (any other kind gives kInvalidOptions: its term coefficients
/// differ). tau_s, sigma and edf are used; rows with non-finite or non-positive values are
/// skipped. Grids denser than 4 taus per octave (`--taus all`) are thinned to 4 per octave for the
/// fit. If the table has no EDF at all (confidence intervals off), every point gets edf = 1
/// (relative least squares) and the standard errors are NaN; otherwise rows without EDF are
/// skipped.
NoiseFitResult FitNoiseTerms(const AllanTable& table, const NoiseFitOptions& options);

/// The honesty checks of FitNoiseTerms (file comment, checks 1-3) on terms another estimator
/// fitted to `table`: `fogpipe compare` fits them jointly with a deterministic part on the Allan
/// variance of its residual, and one rule must judge every command's terms. `terms` as that fit
/// gives them (SI; NaN amplitude = not in its model; a term held at zero carries the one-sigma
/// upper limit sqrt(se(a^2)) as its SE, as here); `other_variance(tau)` [(rad/s)^2] is the Allan
/// variance of the rest of that model (e.g. a Gauss-Markov term; null: none), part of the model
/// each term's share is judged against. z = a / (2 se(a)) (the delta method, as here). Each
/// point's variance is (2 / edf + relative_tolerance^2) v^2 with the table's EDF: the other fit's
/// own covariance is not known here, and a fit that claims its model only to a relative shape
/// tolerance c (compare: the closed forms are idealised at tau of a few samples, where the EDF
/// is in the 1e5) is judged on that claim; 0 = sampling error alone. Each term's upper limit is
/// FitNoiseTerms' rule (the inverted 2-sigma test, capped by what the curve allows), with the
/// standard error at the limit from these point variances. Fills terms, slope_readoff,
/// assessment, misfit_ranges, fitted_range and summary.points; chi2, dof and p_value stay unset
/// (the other fit has its own goodness of fit).
NoiseFitResult AssessNoiseTerms(const AllanTable& table, const NoiseTerms& terms,
                                const std::function<double(double)>& other_variance,
                                double relative_tolerance, const NoiseFitOptions& options);

/// For the fit of a filtered signal (a Kalman or low-pass output of the signal `unfiltered` was
/// fitted to): marks unreliable every term whose amplitude exceeds the unfiltered fit's upper
/// limit for it (TermAssessment::upper_limit). A filter removes noise, it cannot add a gyro's;
/// such a term reads the filter's Allan shape (suppressed at short tau, rising back to the
/// unfiltered curve) as noise, typically rate random walk. Terms of an unfiltered fit without
/// standard errors are not compared.
void MarkTermsAboveUnfiltered(const NoiseFitResult& unfiltered, NoiseFitResult* filtered);

/// The model sigma^2(tau) [(rad/s)^2] of the five terms.
double NoiseModelVariance(const NoiseTerms& terms, double tau_s);

/// ModelDominantAlpha's value where no term is positive.
inline constexpr int kNoModelAlpha = 99;

/// The power-law exponent of the term that contributes most to the model variance at each tau,
/// the cross-check of the identified noise types (noise_id.h): Q 2 (white PM), N 0 (white FM),
/// B -1 (flicker FM), K -2 (random-walk FM); the ramp R, not a noise, counts as -2 (its Allan
/// deviation rises faster still). kNoModelAlpha where every term is zero.
std::vector<int> ModelDominantAlpha(const NoiseTerms& terms, const std::vector<double>& tau_s);

/// The read-offs alone: for each slope s in {-1, -1/2, +1/2, +1}, the adjacent pair of rows whose
/// local log-log slope is closest to s (within `slope_tolerance`) anchors a line of slope s, read
/// at tau = sqrt(3) (Q), 1 (N), 3 (K), sqrt(2) (R) s; B = min sigma / sqrt(2 ln2 / pi)
/// (= / 0.6643). Where the table has EDFs, a pair whose slope standard error (from the EDFs)
/// exceeds `slope_tolerance` is not used: its slope cannot tell the terms apart.
NoiseTerms SlopeReadoffs(const AllanTable& table, double slope_tolerance);

}  // namespace fogpipe::allan
