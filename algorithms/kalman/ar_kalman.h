// The paper's Kalman filter on an AR(p) model (Liu, Liu & Shen 2018, eqs. 5-11; docs/method.md,
// "Step 3").
//
//   X(k) = A X(k-1) + W(k),  Z(k) = H X(k) + V(k),  X = [x(k) ... x(k-p+1)]',  A = companion(phi),
//   H = [1 0 ... 0],  Q = diag(q, 0, ..., 0),  R = r,  X(0|0) = 0,  P(0|0) = P0.
//
// The start P0 (ArKalmanOptions::initial_covariance):
//  - kSampleVariance, the paper's eq. 7: P0 = var(x0) I. var(x0), which the paper leaves undefined,
//    is the sample variance of the measured series z (after the mean is removed), a diffuse-enough
//    start on the scale of the signal, bounded at R / sqrt(eps) so that the covariance recursion
//    keeps its digits when the signal is far above the noise (the slowest IMFs: var(z) / R up to
//    1e20 and more); ArKalmanOptions::initial_variance overrides it. The filter
//    runs time-varying, in Joseph form (O(p^2) per step, see companion.h), until its gain G(k) is
//    within `gain_tolerance` (relative, max norm) of the steady-state gain from the DARE
//    (riccati.h), then switches to a constant-gain loop of O(p) per sample. The switch changes the
//    output by far less than 1e-9 relative (tested against the time-varying filter run to the end),
//    except where the gain stalls at the rounding floor of its recursion (stall_tolerance below).
//  - kSteadyState: P0 = the DARE's filtered covariance P(k|k). P0 is then the fixed point of the
//    Riccati recursion (eqs. 8-10), the gain is G_inf from the first sample, and the whole series
//    runs in the O(p) loop (the smoother needs no time-varying history either). This is the
//    time-invariant filter of Anderson & Moore 1979 ("Optimal Filtering", sec. 4.4): by their
//    exponential-stability result the two starts give outputs whose difference decays like the
//    closed-loop spectral radius^k of A (I - G_inf H) (DareSummary::closed_loop_spectral_radius):
//    both start from X(0|0) = 0, so the difference is driven only by G(k) - G_inf, which decays
//    like radius^(2k), and is then forgotten at radius^k (tested). What the steady-state start
//    gives up is the paper's diffuse prior: in the first ~1 / (1 - radius) samples it trusts its
//    start X(0|0) = 0 more than the paper's start does.
//    q = 0: a stable AR model gives P_inf = 0 and G_inf = 0 (no driving noise: x is known to stay
//    at 0), so the output is the model mean throughout; the paper's start gives the AR model
//    running free from its first estimates, which decays to the same at radius(A)^k. With a unit
//    or explosive root and q = 0 there is no stabilizing DARE solution: the filter then falls back
//    to the paper's start and time-varying path (ArKalmanSummary::initial_covariance says which
//    start was used, and the termination is kNoConvergence). The one exception is q = 0 from
//    P(0|0) = 0 (initial_variance = 0): P stays exactly 0 whatever the model, so the gain is 0
//    from the first sample and the output is the mean, without a time-varying phase.
//
// The time-varying phase is bounded in any case by max_time_varying_steps: when q/R is tiny the
// gain converges like radius^(2k) with radius close to 1, or (q = 0, unit root) like 1/k, and
// would otherwise cost O(p^2) per sample to the end of a 1e7-sample record. At the cap the filter
// switches to G_inf if the DARE converged (ArKalmanSummary::gain_distance_at_switch records how
// far the gain still was; the output difference this causes is driven by that distance and
// forgotten at radius^k, see the tests), and otherwise freezes the last time-varying gain if that
// gain gives a stable closed loop (an approximation, flagged as GainSwitch::kFrozen).
//
// Choice of the default: accuracy against the truth. The steady-state start trusts X(0|0) = 0
// for ~1 / (1 - radius) samples, which on slow IMFs (radii 0.999..0.99999 at small q/R) spans
// much of the record, while the paper's diffuse start locks on within a few hundred samples; so
// the paper's start is the default and the steady-state start the fast option (fogpipe sweep
// --kalman-start steady). Measurements: docs/filtering.md, "Per-component Kalman filters".
//
// Optionally the fixed-interval Rauch-Tung-Striebel smoother is run (rts_smoother.h). The sweep's
// bank of these filters over many option sets is ar_filter_bank.h.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/common/status.h"
#include "algorithms/kalman/riccati.h"

namespace fogpipe::kalman {

/// P(0|0), the filter's start (see above).
enum class InitialCovariance {
  kSampleVariance,  ///< The paper's eq. 7: var(x0) I, var(x0) = sample variance of z.
  kSteadyState,     ///< The DARE's filtered covariance: steady-state gain from the first sample.
};
/// "sample_variance" or "steady_state".
const char* ToString(InitialCovariance initial_covariance);

/// How the filter reached its constant-gain loop.
enum class GainSwitch {
  kNever,      ///< Time-varying to the end (switch off, or no usable constant gain).
  kFromStart,  ///< G_inf from the first sample (steady-state start), or 0 when q = 0, P0 = 0.
  kConverged,  ///< |G(k) - G_inf| within gain_tolerance.
  kStalled,    ///< The gain distance stalled at the recursion's rounding floor (stall_tolerance).
  kCapped,     ///< max_time_varying_steps reached; switched to G_inf.
  kFrozen,     ///< max_time_varying_steps reached, no DARE solution: the last gain is kept.
};
/// "never", "from_start", "converged", "stalled", "capped", "frozen".
const char* ToString(GainSwitch gain_switch);

struct ArKalmanOptions {
  /// Process-noise variance q of the AR driving noise, units of x^2. < 0: DefaultNoise() rule
  /// (noise_defaults.h) from the AR innovation variance and the white-noise variance.
  double q = -1.0;
  /// Measurement-noise variance R, units of x^2. < 0: the white_noise_variance argument.
  double r = -1.0;
  /// Multipliers applied to the resolved q and R (explicit or default) for sweeps. The default q
  /// is computed from the unscaled R, so sweeping r_scale leaves q where the rule put it.
  double q_scale = 1.0;
  double r_scale = 1.0;
  /// The AR model's mean (ArModel::mean): removed from z before filtering, added back after.
  double mean = 0.0;
  /// P(0|0): the paper's sample-variance start (default) or the steady-state start. Why the
  /// default: see "Choice of the default" in the file comment.
  InitialCovariance initial_covariance = InitialCovariance::kSampleVariance;
  /// With kSampleVariance: P(0|0) = initial_variance * I. < 0: the sample variance of z, at most
  /// R / sqrt(eps) (a larger start leaves P(k|k) as rounding noise; ar_kalman.cpp,
  /// InitialVarianceBound).
  double initial_variance = -1.0;
  /// Use the constant-gain O(p) loop once the gain is (or starts) at the steady state. false runs
  /// the time-varying recursion to the end whatever the start (a reference for tests).
  bool steady_state_switch = true;
  /// Switch when max_i |G_i(k) - G_inf,i| <= gain_tolerance * max_i |G_inf,i|.
  double gain_tolerance = 1e-12;
  /// For ill-conditioned models (lightly damped poles, tiny q/R) the time-varying gain stalls at
  /// the rounding floor of its own recursion before reaching gain_tolerance. It then switches once
  /// the gain distance has not reached a new minimum for as many steps as it took to reach it, if
  /// that minimum and the current distance are both within stall_tolerance. 0 disables this.
  /// Such a switch moved the output by at most 3.5e-9 relative on the paper's Table 2 models, the
  /// time-varying reference's own rounding noise (docs/filtering.md, "Per-component Kalman
  /// filters").
  double stall_tolerance = 1e-9;
  /// At most this many time-varying steps (O(p^2) each) before the switch (see above); 0: no cap.
  /// 2^16 steps bound the time-varying cost to ~1 % of a 24 h record at 100 Hz and to a few ms per
  /// filter at p <= 12, while the well-conditioned models (closed-loop radius < 0.9997) converge to
  /// gain_tolerance before it: radius^(2k) <= 1e-12 needs k >= ln(1e12) / (2 (1 - radius)).
  long long max_time_varying_steps = 1LL << 16;
  /// Also run the RTS smoother; ArKalmanResult::smoothed is filled. Memory: one more vector of n
  /// doubles (innovations, overwritten by the smoothed values) plus p + 1 doubles per
  /// time-varying step (none for the steady-state start, at most max_time_varying_steps unless
  /// the filter finds no usable constant gain).
  bool smooth = false;
  /// With smooth: when the record contradicts the model in the smoother's direction
  /// (SmootherContradictsModel, rts_smoother.h: the smoothed residuals' mean square below the
  /// filtered ones', which a correctly specified model never gives in expectation), the smoothed
  /// series is replaced by the filtered one and ArKalmanSummary::smoother_replaced says so. Off by
  /// default: the residuals also hold the signal a misspecified filter lags behind, which the
  /// smoother follows, so the check can fire where the smoother is better (measured on the raw
  /// signal and at other q than method 1's rule: docs/filtering.md, "S5"). Method 1's components
  /// under their rule's own q and R turn it on (ComponentFilterOptions, component.h).
  bool smoother_model_check = false;
  /// Options of the DARE solver.
  DareOptions dare;

  bool IsValid(std::string* error) const;
};

struct ArKalmanSummary {
  Termination termination = Termination::kInvalidOptions;
  std::string message;
  /// The start actually used: kSampleVariance when kSteadyState was asked but the DARE has no
  /// stabilizing solution.
  InitialCovariance initial_covariance = InitialCovariance::kSampleVariance;
  /// The sample-variance start was bounded at R / sqrt(eps) (ArKalmanOptions::initial_variance).
  bool initial_variance_bounded = false;
  /// Why and whether the filter reached its constant-gain loop.
  GainSwitch gain_switch = GainSwitch::kNever;
  /// First sample filtered with the constant gain (0 for the steady-state start); -1 if never.
  long long switched_at_sample = -1;
  /// max_i |G_i(k) - G_inf,i| / max_i |G_inf,i| (absolute if G_inf = 0) at the switch; for the
  /// steady-state start, that of one Riccati step from P0 (how exactly P0 is a fixed point of the
  /// filter's arithmetic). kFrozen: the same distance between the frozen gain and the gain at half
  /// the cap (how far from converged the time-varying gain still was).
  double gain_distance_at_switch = 0.0;
  /// Doubling iterations of the DARE solver (riccati.h).
  int riccati_iterations = 0;
  double riccati_relative_residual = 0.0;
  long long samples = 0;
  /// The constant-gain loop would not be stable as it runs (steady_state_filter.h,
  /// ConstantGainLoopStable): the filter failed without output; a lower AR order may work.
  bool loop_unstable = false;
  /// The smoothed series is the filtered one: the record contradicted the model in the
  /// smoother's direction (ArKalmanOptions::smoother_model_check); smoother_note says by how much.
  bool smoother_replaced = false;
  /// Empty, or why the smoother's output was replaced by the filter's.
  std::string smoother_note;
};

struct ArKalmanResult {
  /// Estimate of x(k) given z(1..k), units of z. Empty if the summary has no result.
  Eigen::VectorXd filtered;
  /// Estimate of x(k) given z(1..N) (RTS); empty unless options.smooth.
  Eigen::VectorXd smoothed;
  double q = 0.0;  ///< The process-noise variance used (after default rule and scale).
  double r = 0.0;  ///< The measurement-noise variance used (after scale).
  Eigen::VectorXd steady_state_gain;            ///< G_inf, dimensionless.
  double steady_state_error_variance = 0.0;     ///< H P(k|k) H' in steady state, units of x^2.
  double steady_state_innovation_variance = 0;  ///< H P(k|k-1) H' + R, units of x^2.
  /// H P(k|N) H' of the smoother far from both ends; 0 unless options.smooth.
  double steady_state_smoothed_error_variance = 0.0;
  ArKalmanSummary summary;
};

/// Filters z (one IMF or the raw series) with the AR(p) model x(k) = sum_i phi_i x(k-i) + w(k).
/// innovation_variance: the AR fit's one-step prediction-error variance of z (used by the default
/// q rule only); white_noise_variance: the per-sample white measurement-noise variance (default R).
/// Either may be given as a negative number if the matching explicit option is set.
///
/// reuse (optional): storage for ArKalmanResult::filtered, taken over (moved from) when its size
/// is z's; move the previous result's vector back in to filter many equal-length series without
/// allocating. A fresh 1e7-sample output costs ~4 ns/sample of page faults on the reference
/// machine, more than the filtering itself.
ArKalmanResult FilterAr(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
                        double innovation_variance, double white_noise_variance,
                        const ArKalmanOptions& options = ArKalmanOptions(),
                        Eigen::VectorXd* reuse = nullptr);

}  // namespace fogpipe::kalman
