// One component (an IMF, the residue, or the raw signal for method 2): AR model + Kalman filter
// on it (Liu, Liu & Shen 2018, steps 2 and 3; method.md eqs. 2-11).
#pragma once

#include <Eigen/Core>
#include <string>

#include "algorithms/ar/fit_ar.h"
#include "algorithms/kalman/ar_kalman.h"

namespace fogpipe::method {

struct ComponentOptions {
  /// Order by BIC up to max_order, or fixed_order > 0 (ArOptions documents the estimator).
  ar::ArOptions ar;
  /// q, R, their scales, the steady-state switch and the optional RTS smoother.
  kalman::ArKalmanOptions kalman;
};

struct ComponentModel {
  /// The AR fit: model (order, phi in recursion convention, innovation variance), BIC for every
  /// order tried, one-step and simulation fit %, Ljung-Box.
  ar::ArFit fit;
  /// The Kalman filter on that model: q and R used, steady-state gain, filtered series.
  kalman::ArKalmanResult kalman;
  /// The white-noise variance handed to the filter (white_noise.h), units of x^2.
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

/// Fits the AR model to `x` and runs the Kalman filter on it with R from `white_noise_variance`.
ComponentModel ModelComponent(const Eigen::VectorXd& x, double white_noise_variance,
                              const ComponentOptions& options);

}  // namespace fogpipe::method
