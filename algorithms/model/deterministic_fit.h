// Joint least-squares fit of the bias and the deterministic effects of the gyro model:
//
//   rate(t) = bias + c_T (T - T_ref) + c_dT dTs/dt + sum_i [a_i cos(2 pi f_i t) + b_i sin(2 pi f_i
//   t)]
//             + D 1{t >= t_s} + A exp(-t / tau_w) + noise
//
// The model is linear in every amplitude; the nonlinear parameters (f_i, t_s, tau_w) are found by
// 1-D searches with all amplitudes profiled out (variable projection, Golub & Pereyra 1973):
//   - warm-up time constant: log-spaced grid then golden-section search on log(tau_w);
//   - step time: CUSUM scan of the residual (Page 1954; Hinkley 1970), then the exact profile RSS
//     in a neighbourhood;
//   - bias_levels (sum_j D_j 1{t >= t_j}, k >= 0 steps): the step times and their number by the
//     segmentation of the residual (SegmentLevels, bias_levels.h), one bias_step column each;
//   - sinusoid frequency: the largest peak of the zero-padded periodogram of the residual relative
//     to a band-median background, then golden-section refinement of the profile RSS (Rife &
//     Boorstyn 1974: this is the maximum-likelihood frequency in white noise).
// Coordinate-descent passes then re-optimise each nonlinear parameter with the others fixed (full
// searches for the warm-up and the step, a local golden-section search for the frequencies).
//
// Temperature: T_ref is the mean temperature of the record. dT/dt is the slope of a local
// least-squares line over a centred window of temperature_smoothing_s (Savitzky & Golay 1964),
// because differencing a sampled, noisy temperature amplifies its noise by fs.
//
// Aux terms (catalog.h) on any channel x: aux:<x> is sum_{k=1..p} c_k (x - x_ref)^k with x_ref
// the record's mean of x, aux_rate:<x> is c dx/dt with the same smoothed derivative as dT/dt.
// aux_hysteresis:<x> is c h(t) with h = +1 while x rises and -1 while it falls: a comparator with
// hysteresis (a Schmitt trigger, Schmitt 1938) on the smoothed derivative d = dx/dt, h switching
// to +1 when d > +w and to -1 when d < -w and holding its state inside the dead band [-w, w]; the
// state before the first exit from the band is that exit's (a record has no earlier state). The
// dead band's half-width w is sqrt(2 ln n) standard deviations of d under the channel's sensor
// noise alone (n samples): Donoho & Johnstone's (1994) universal threshold, which the largest of n
// Gaussian values exceeds with a probability that falls to 0 as n grows (~1 / sqrt(pi ln n) for
// independent ones; d is correlated over its window, which makes an exit rarer still), so that a
// flat channel's d rarely leaves the band and a switch back, an exit on the other side as well,
// is rarer again: noise does not chatter the switch, while a channel that moves changes state
// within the time d takes to exceed w (4.6-5.7 sd for 1 h at 10 Hz to 24 h at 100 Hz). The noise
// of d: the sensor noise sigma_x (the rms first difference over sqrt 2, white sensor noise; a slow
// channel's own change per sample is far below it) through the local-slope filter, whose noise
// gain at window W samples is fs sqrt(12 / (W (W^2 - 1))) (the variance of a least-squares
// slope). Zero crossings of d without a band would flip h with the noise wherever the channel is
// flat. Within h of the record's ends the window is clipped and the slope noisier (up to 2^1.5 at
// the first sample): the band widens by the same gain there. The fitted w is the component's
// reference (unit/s), so that a model evaluated on another record switches where the fit did.
// aux_am:<x> is a line whose amplitude follows x (amplitude modulation, e.g. a vibration or
// electronics line whose strength depends on the temperature): (a0 + a1 (x - x_ref)) sin(2 pi f t
// + phi), fitted as (c0 + c1 x~) cos(2 pi f t) + (s0 + s1 x~) sin(2 pi f t), x~ = x - x_ref, x_ref
// the record's mean: linear in (c0, s0, c1, s1) at a given f, and f searched as the sinusoid's (the
// carrier is the largest peak of the line, its sidebands at f +- the channel's frequencies), its
// refinement on the four-column profile. (c1, s1) not parallel to (c0, s0) is a modulation in
// quadrature (a phase modulation to first order); compare.h reports both parts.
// The order p of aux:<x> is chosen among 1..max_aux_order by the Gaussian BIC
// n_eff ln RSS_p + p ln n_eff (Schwarz 1978) with the other components in the design and
// n_eff = n / lambda, lambda the long-run variance ratio of the order-1 residual (below): the
// residual of a gyro is coloured, and with n in place of n_eff a slow wander of the bias that the
// channel happens to share would buy every extra power.
//
// Standard errors: the residual of a gyro is coloured (bias instability, rate random walk), so the
// ordinary least-squares covariance is too optimistic for slowly varying regressors. We use the
// batch-means sandwich covariance (X'X)^-1 [sum_b s_b s_b'] (X'X)^-1 with s_b = X_b' r_b over 32
// contiguous blocks (a cluster-robust estimator; cf. Newey & West 1987), never smaller than OLS.
// Nonlinear parameters get theirs from the linearised model (Jacobian column); the step time from
// Hinkley's (1970) scale sigma_lr^2 / D^2 with sigma_lr^2 the long-run variance.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/common/status.h"
#include "algorithms/model/catalog.h"

namespace fogpipe::model {

struct DeterministicOptions {
  /// Window of the local least-squares slope that gives dT/dt, s.
  double temperature_smoothing_s = 120.0;
  /// A step is searched in [margin, 1 - margin] of the record (an edge step is a warm-up or bias).
  double step_margin_fraction = 0.02;
  /// Warm-up time constants searched, s: [max(min_warmup_tau_s, 3/fs), record / 3].
  double min_warmup_tau_s = 5.0;
  /// A sinusoid must complete at least this many cycles in the record (slower is drift).
  double min_sinusoid_cycles = 3.0;
  /// Coordinate-descent passes over the nonlinear parameters after initialisation.
  int refinement_passes = 2;
  /// Highest power of an aux:<channel> polynomial (its order is chosen by BIC in 1..this).
  int max_aux_order = 3;
  bool IsValid(std::string* error) const;
};

/// One fitted deterministic component. Values in SI: rate coefficients in rad/s per unit of the
/// regressor; the nonlinear parameter in Hz (sinusoid, aux_am) or s (bias_step time, warmup
/// constant).
struct DeterministicComponent {
  ModelTerm term = Term::kTemperature;
  double nonlinear = 0.0;     ///< frequency_hz | step_time_s | time_constant_s; 0 if none
  double nonlinear_se = 0.0;  ///< its standard error (same units)
  /// Linear coefficients: temperature rad/s/degC; temperature_rate rad/s/(degC/s); sinusoid
  /// (cosine, sine) rad/s; bias_step size rad/s; warmup amplitude rad/s at t = 0; aux c_1..c_p
  /// in rad/s per unit^k of the channel; aux_rate rad/s per (unit/s); aux_hysteresis rad/s (half
  /// the bias difference between rising and falling); aux_am (c0, s0, c1, s1): the line's
  /// cosine and sine amplitudes in rad/s, then their change in rad/s per unit of x - x_ref.
  std::vector<double> coefficients;
  std::vector<double> coefficients_se;
  /// Aux terms: the channel's mean over the fitted record (x_ref; aux_hysteresis: the dead band's
  /// half-width w, unit/s) and its units ("" if the recording gives none).
  double reference = 0.0;
  std::string units;
  /// aux_am: the covariance of its coefficients (row-major, 4 x 4; the sandwich's, with the
  /// frequency's uncertainty in it), for the parameters derived from several of them (compare.h);
  /// empty for the other terms.
  std::vector<double> coefficients_covariance;
  /// bias_levels: the step times, s (ascending; `coefficients` holds the step sizes in the same
  /// order) and their standard errors (Hinkley's scale, as the bias_step time).
  std::vector<double> step_times_s;
  std::vector<double> step_times_se_s;
  /// bias_levels: the segmentation's modified-BIC change of its steps, their penalty minus their
  /// -2 ln L drop (bias_levels.h; negative when it chose steps, 0 without).
  double levels_delta_bic = 0.0;
  /// bias_levels: the steps the segmentation found beyond what a dense fit of the record holds
  /// (LevelsSegmentation::too_many_steps; then no step is fitted), else 0, and that limit.
  int levels_too_many_steps = 0;
  long levels_max_design_steps = 0;
};

/// An aux channel as the deterministic fit reads it (non-owning; values of the rate's length).
struct AuxSeries {
  std::string name;
  std::string units;
  const Eigen::VectorXd* values = nullptr;
};

/// The aux channels of the overloads that take at most a temperature: {"temperature", "degC"},
/// or none for null.
std::vector<AuxSeries> TemperatureSeries(const Eigen::VectorXd* temperature_degc);

/// Everything needed to evaluate (and so compensate) the deterministic part on a recording.
struct DeterministicModel {
  double bias_rad_s = 0.0;
  double bias_se_rad_s = 0.0;
  double temperature_ref_degc = 0.0;
  double temperature_smoothing_s = 120.0;
  std::vector<DeterministicComponent> components;
};

struct DeterministicSummary {
  Termination termination = Termination::kSuccess;
  std::string message;
  int num_parameters = 0;  ///< linear + nonlinear parameters, bias included
  long num_samples = 0;
};

struct DeterministicFit {
  DeterministicModel model;
  Eigen::VectorXd residual;  ///< rate - bias - effects, rad/s
  double rss = 0.0;          ///< sum of squared residuals, (rad/s)^2
  /// Long-run to short-run variance ratio of the residual (batch means); >= 1 for coloured noise.
  double long_run_variance_ratio = 1.0;
  DeterministicSummary summary;
};

/// Fits bias + the rate-fitted terms of `terms` (others are ignored). A term whose aux channel
/// (AuxChannelOf; "temperature" for the thermal terms) is not in `aux` with the rate's length
/// makes the fit fail with kInsufficientData.
DeterministicFit FitDeterministic(const Eigen::VectorXd& rate_rad_s, double sample_rate_hz,
                                  const std::vector<AuxSeries>& aux,
                                  const std::vector<ModelTerm>& terms,
                                  const DeterministicOptions& options);
/// The same with at most the aux channel "temperature" (degC; may be null).
DeterministicFit FitDeterministic(const Eigen::VectorXd& rate_rad_s, double sample_rate_hz,
                                  const Eigen::VectorXd* temperature_degc,
                                  const std::vector<ModelTerm>& terms,
                                  const DeterministicOptions& options);

/// The smoothed temperature derivative used by temperature_rate, degC/s.
Eigen::VectorXd SmoothedDerivative(const Eigen::VectorXd& temperature_degc, double sample_rate_hz,
                                   double smoothing_s);

/// The dead band's half-width w of a channel's aux_hysteresis term, unit/s (above).
double HysteresisDeadBand(const Eigen::VectorXd& values, double sample_rate_hz, double smoothing_s);
/// The aux_hysteresis regressor: +1 rising, -1 falling, from the smoothed derivative (of window
/// smoothing_s at sample_rate_hz) and the dead band's half-width (above; where the window is
/// clipped at the record's ends, widened by its slope's larger noise gain); all 0 when the
/// derivative never leaves the band.
Eigen::VectorXd HysteresisState(const Eigen::VectorXd& derivative, double dead_band,
                                double sample_rate_hz, double smoothing_s);

/// Evaluates the effects (without the bias when include_bias is false), rad/s, on n samples.
/// Components whose channel is not in `aux` with n samples are left out.
Eigen::VectorXd EvaluateDeterministic(const DeterministicModel& model, long n,
                                      double sample_rate_hz, const std::vector<AuxSeries>& aux,
                                      bool include_bias);
/// The same with at most the aux channel "temperature" (degC; may be null).
Eigen::VectorXd EvaluateDeterministic(const DeterministicModel& model, long n,
                                      double sample_rate_hz,
                                      const Eigen::VectorXd* temperature_degc, bool include_bias);

}  // namespace fogpipe::model
