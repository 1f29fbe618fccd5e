// The paper's Kalman filter on an AR(p) model (Liu, Liu & Shen 2018, method.md eqs. 5-11).
//
//   X(k) = A X(k-1) + W(k),  Z(k) = H X(k) + V(k),  X = [x(k) ... x(k-p+1)]',  A = companion(phi),
//   H = [1 0 ... 0],  Q = diag(q, 0, ..., 0),  R = r,  X(0|0) = 0,  P(0|0) = var(x0) I.
//
// var(x0), which the paper leaves undefined, is here the sample variance of the measured series z
// (after the mean is removed): a diffuse-enough start on the scale of the signal. It only shapes
// the first few gains; ArKalmanOptions::initial_variance overrides it.
//
// The filter runs time-varying, in Joseph form (O(p^2) per step, see companion.h), until its gain
// G(k) is within `gain_tolerance` (relative, max norm) of the steady-state gain from the DARE
// (riccati.h), then switches to a constant-gain loop of O(p) per sample. The switch changes the
// output by far less than 1e-9 relative (tested against the time-varying filter run to the end).
//
// Optionally the fixed-interval Rauch-Tung-Striebel smoother is run (rts_smoother.h).
#pragma once

#include <Eigen/Core>
#include <string>

#include "algorithms/common/status.h"
#include "algorithms/kalman/riccati.h"

namespace fogpipe::kalman {

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
  /// P(0|0) = initial_variance * I. < 0: the sample variance of z (see above).
  double initial_variance = -1.0;
  /// Switch to the steady-state gain once the time-varying gain has converged.
  bool steady_state_switch = true;
  /// Switch when max_i |G_i(k) - G_inf,i| <= gain_tolerance * max_i |G_inf,i|.
  double gain_tolerance = 1e-12;
  /// For ill-conditioned models (lightly damped poles, tiny q/R) the time-varying gain stalls at
  /// the rounding floor of its own recursion before reaching gain_tolerance. It then switches once
  /// the gain distance has not reached a new minimum for as many steps as it took to reach it, if
  /// that minimum is within stall_tolerance. 0 disables this. Measured on the paper's Table 2
  /// models with q/R down to 1e-10, the output changes by at most ~0.1 x the gain distance at the
  /// switch, so 1e-9 keeps the switch far inside the 1e-9 relative output budget; models whose
  /// gain stalls above it (imf6, imf7 at q/R = 1e-10) run time-varying to the end.
  double stall_tolerance = 1e-9;
  /// Also run the RTS smoother; ArKalmanResult::smoothed is filled. Memory: one more vector of n
  /// doubles (innovations, overwritten by the smoothed values) plus p + 1 doubles per
  /// time-varying step (all n steps if the filter never switches).
  bool smooth = false;
  /// Options of the DARE solver.
  DareOptions dare;

  bool IsValid(std::string* error) const;
};

struct ArKalmanSummary {
  Termination termination = Termination::kInvalidOptions;
  std::string message;
  /// First sample filtered with the steady-state gain; -1 if the filter never switched.
  long long switched_at_sample = -1;
  /// max_i |G_i(k) - G_inf,i| / max_i |G_inf,i| at the switch.
  double gain_distance_at_switch = 0.0;
  /// Doubling iterations of the DARE solver (riccati.h).
  int riccati_iterations = 0;
  double riccati_relative_residual = 0.0;
  long long samples = 0;
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
