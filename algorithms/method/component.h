// One component (an IMF, the residue, or the raw signal for method 2): AR model + Kalman filter
// on it (Liu, Liu & Shen 2018, steps 2 and 3, eqs. 2-11; docs/method.md).
#pragma once

#include <Eigen/Core>
#include <string>

#include "algorithms/ar/fit_ar.h"
#include "algorithms/kalman/ar_kalman.h"
#include "algorithms/method/white_noise.h"

namespace fogpipe::method {

/// The RMS ratio above which a filter's estimate has diverged (FilterDiverged documents it).
constexpr double kDivergedRmsRatio = 10.0;

/// The RMS ratio above which an RTS-smoothed estimate has diverged. The fixed-interval smoother is
/// E[x | z] of the state-space model, x^ - mean = Sx (Sx + R I)^-1 (z - mean) with Sx the model's
/// covariance of the n samples of x, a symmetric matrix with eigenvalues lambda / (lambda + R) in
/// [0, 1): the smoothed estimate is never larger than the mean-removed component, whatever the
/// model, q, R or start (Anderson & Moore 1979, "Optimal Filtering", ch. 7; Durbin & Koopman
/// 2012, sec. 4.4). An estimate above it is rounding that has taken over the recursion. The slack
/// covers the steady-state switch, which moves the output by at most 3.5e-9 relative
/// (ar_kalman.h, stall_tolerance), with a margin of about 300.
constexpr double kSmoothedRmsBound = 1.0 + 1e-6;

struct ComponentOptions {
  /// Order by BIC up to max_order, or fixed_order > 0 (ArOptions documents the estimator).
  ar::ArOptions ar;
  /// q, R, their scales, the steady-state switch and the optional RTS smoother. Explicit q or R
  /// (>= 0) override the rule below.
  kalman::ArKalmanOptions kalman;
  /// How q and R follow from the component's white-noise share (white_noise.h).
  ComponentNoiseRule noise_rule = ComponentNoiseRule::kShareOfInnovation;
  /// A filter whose estimate's RMS exceeds this many times the component's has diverged
  /// (FilterDiverged); ModelComponent then tries BIC's next orders below.
  double diverged_rms_ratio = kDivergedRmsRatio;
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
  /// Empty, or why fit.model is not BIC's own order: the fit's ar::ArSummary::order_note (that
  /// order is not stationary in double precision), then the higher orders whose filters diverged
  /// ("AR(13) diverged (estimate RMS 11.1 x the component's)"), highest first.
  std::string order_note;
  /// The filter output used downstream: RTS-smoothed when kalman.smooth, filtered otherwise.
  const Eigen::VectorXd& Output() const {
    return kalman.smoothed.size() > 0 ? kalman.smoothed : kalman.filtered;
  }
  /// True when both the fit and the filter produced a result.
  bool ok() const;
  /// Why not, when !ok().
  std::string message() const;
};

/// Whether every sample of x equals the first. Such a component (e.g. a residue that is exactly
/// flat) has no dynamics to model and nothing to filter: ModelComponent and the sweep pass it
/// through unchanged, recorded as order 0.
bool IsConstantComponent(const Eigen::VectorXd& x);

/// The Kalman options of a filter on a component with `model` (an AR model fitted to it):
/// options.kalman with the model's mean and, unless q or R is given explicitly (>= 0), the noise
/// rule's q (white_noise.h), and for a pure-noise component P(0|0) = 0 (step 3: q = 0 from
/// P(0|0) = 0 gives gain 0, the output is the mean; ar_kalman.h); with the share rule at q and R
/// scales 1 also the smoother's model check (kalman::ArKalmanOptions::smoother_model_check, set
/// whatever options.kalman says; off otherwise). `white_share` and `variance` are
/// the component's white-noise share and variance, units of x^2. *r receives the rule's R, the
/// white-noise variance to give kalman::FilterAr (an explicit options.kalman.r overrides it
/// there). ModelComponent and the sweep's default-rule setting configure their filters with it, so
/// the sweep's default row is what `run` does.
kalman::ArKalmanOptions ComponentFilterOptions(const ComponentOptions& options, double white_share,
                                               double variance, const ar::ArModel& model,
                                               double* r);

/// Whether a Kalman filter on a component has diverged: a filter on a stationary model fitted to a
/// component estimates it with a variance below the component's own (var(x^) = var(x) - P <=
/// var(z)), so an estimate whose mean square about the model mean exceeds kDivergedRmsRatio^2
/// times the component's variance (units of x^2 both) is numerical breakdown, not filtering.
/// A working filter stays at or below 1x (component_test.cpp), broken-down ones were measured far
/// above 10x (docs/filtering.md, "Models that can run"). Fills *message.
bool FilterDiverged(double estimate_mean_square, double component_variance, std::string* message,
                    double rms_ratio = kDivergedRmsRatio);

/// Whether a filter on a component broke down, so that a lower AR order should be tried: its
/// constant-gain loop would not be stable as it runs (kalman::ArKalmanSummary::loop_unstable; the
/// filter then has no output), or its estimate diverged about `model_mean` (FilterDiverged
/// against `component_variance`, units of x^2): the filtered one above rms_ratio, the smoothed one
/// (if there is one and was not replaced by the filtered one, ArKalmanSummary::smoother_replaced)
/// above the smaller of rms_ratio and kSmoothedRmsBound. Fills *message.
/// ModelComponent and the sweep's fallback judge their filters with it.
bool FilterBrokeDown(const kalman::ArKalmanResult& result, double model_mean,
                     double component_variance, std::string* message,
                     double rms_ratio = kDivergedRmsRatio);

/// Fits the AR model to `x` and runs the Kalman filter on it, q and R from `white_noise_variance`
/// (the component's white share, units of x^2) by options.noise_rule unless given explicitly. A
/// diverged filter (FilterDiverged) is reported as a numerical failure of the filter.
/// `prefit`, when given, is ar::FitAr(x, options.ar) computed beforehand (the streamed method fits
/// each IMF while the next is sifted); it is moved from.
ComponentModel ModelComponent(const Eigen::VectorXd& x, double white_noise_variance,
                              const ComponentOptions& options, ar::ArFit* prefit = nullptr);

}  // namespace fogpipe::method
