// One component (an IMF, the residue, or the raw signal for method 2): AR model + Kalman filter
// on it (Liu, Liu & Shen 2018, steps 2 and 3; method.md eqs. 2-11).
#pragma once

#include <Eigen/Core>
#include <string>

#include "algorithms/ar/fit_ar.h"
#include "algorithms/kalman/ar_kalman.h"
#include "algorithms/method/white_noise.h"

namespace fogpipe::method {

struct ComponentOptions {
  /// Order by BIC up to max_order, or fixed_order > 0 (ArOptions documents the estimator).
  ar::ArOptions ar;
  /// q, R, their scales, the steady-state switch and the optional RTS smoother. Explicit q or R
  /// (>= 0) override the rule below.
  kalman::ArKalmanOptions kalman;
  /// How q and R follow from the component's white-noise share (white_noise.h).
  ComponentNoiseRule noise_rule = ComponentNoiseRule::kShareOfInnovation;
};

struct ComponentModel {
  /// The AR fit: model (order, phi in recursion convention, innovation variance), BIC for every
  /// order tried, one-step and simulation fit %, Ljung-Box.
  ar::ArFit fit;
  /// The Kalman filter on that model: q and R used, steady-state gain, filtered series.
  kalman::ArKalmanResult kalman;
  /// The component's share of the white-noise variance (white_noise.h), units of x^2; the R
  /// actually used is kalman.r.
  double white_noise_variance = 0.0;
  /// The filter output used downstream: RTS-smoothed when kalman.smooth, filtered otherwise.
  const Eigen::VectorXd& Output() const {
    return kalman.smoothed.size() > 0 ? kalman.smoothed : kalman.filtered;
  }
  /// True when both the fit and the filter produced a result.
  bool ok() const;
  /// Why not, when !ok().
  std::string message() const;
};

/// Fits the AR model to `x` and runs the Kalman filter on it, q and R from `white_noise_variance`
/// (the component's white share, units of x^2) by options.noise_rule unless given explicitly.
ComponentModel ModelComponent(const Eigen::VectorXd& x, double white_noise_variance,
                              const ComponentOptions& options);

/// The filter of a component judged pure white noise (white_noise.h, step 3): with q = 0 and
/// P(0|0) = 0 the gain is 0 from the first sample, so the estimate is the AR model's mean at
/// every sample (q = 0, R = r, gain 0). Written out directly in O(n): the DARE at q = 0 is
/// ill-posed on the near-unit-root models of slow IMFs (measured: it made the filter run
/// time-varying, O(p^2) per sample, over 8 IMFs of a 24 h record).
kalman::ArKalmanResult PureNoiseFilter(Eigen::Index n, Eigen::Index order, double mean, double r,
                                       bool smooth);

}  // namespace fogpipe::method
