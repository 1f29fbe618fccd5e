#include "algorithms/method/component.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace fogpipe::method {

bool ComponentModel::ok() const {
  return HasResult(fit.summary.termination) && HasResult(kalman.summary.termination);
}

std::string ComponentModel::message() const {
  if (!HasResult(fit.summary.termination)) return "AR fit: " + fit.summary.message;
  if (!HasResult(kalman.summary.termination)) return "Kalman filter: " + kalman.summary.message;
  return "";
}

bool IsConstantComponent(const Eigen::VectorXd& x) {
  return x.size() > 0 && (x.array() == x[0]).all();
}

kalman::ArKalmanOptions ComponentFilterOptions(const ComponentOptions& options, double white_share,
                                               double variance, const ar::ArModel& model,
                                               double* r) {
  kalman::ArKalmanOptions kalman = options.kalman;
  kalman.mean = model.mean;
  const FilterNoise noise =
      ComponentFilterNoise(options.noise_rule, white_share, variance, model.innovation_variance);
  *r = noise.r;
  if (kalman.q >= 0.0 || kalman.r >= 0.0) return kalman;
  kalman.q = noise.q;
  if (noise.pure_noise) kalman.initial_variance = 0.0;
  // The share rule's own q and R on an EMD component: where the smoother's model check was
  // measured to remove every loss of the smoother to its filter and no gain (kalman.h,
  // smoother_model_check; docs/filtering.md, "S5").
  kalman.smoother_model_check = options.noise_rule == ComponentNoiseRule::kShareOfInnovation &&
                                kalman.q_scale == 1.0 && kalman.r_scale == 1.0;
  return kalman;
}

ComponentModel ModelComponent(const Eigen::VectorXd& x, double white_noise_variance,
                              const ComponentOptions& options, ar::ArFit* prefit) {
  ComponentModel out;
  out.white_noise_variance = white_noise_variance;
  if (IsConstantComponent(x)) {
    out.fit.model.mean = x[0];
    out.fit.summary.termination = Termination::kSuccess;
    out.fit.summary.message = "constant component: passed through without a model";
    out.kalman.filtered = x;
    out.kalman.summary.termination = Termination::kSuccess;
    out.kalman.summary.message = out.fit.summary.message;
    return out;
  }
  out.fit = prefit != nullptr ? std::move(*prefit) : ar::FitAr(x, options.ar);
  if (!HasResult(out.fit.summary.termination)) return out;
  const double variance = (x.array() - x.mean()).square().mean();
  // The Kalman filter on out.fit's model, q and R by the noise rule (ComponentFilterOptions).
  const auto filter = [&] {
    double r = 0.0;
    const kalman::ArKalmanOptions kalman_options =
        ComponentFilterOptions(options, white_noise_variance, variance, out.fit.model, &r);
    out.kalman = kalman::FilterAr(x, out.fit.model.phi, out.fit.model.innovation_variance, r,
                                  kalman_options);
  };
  filter();
  std::string diverged;
  const auto diverges = [&](std::string* message) {
    return FilterBrokeDown(out.kalman, out.fit.model.mean, variance, message,
                           options.diverged_rms_ratio);
  };
  // A filter on an ill-conditioned high-order model of a slow IMF can diverge in floating point
  // (README, Known limitations; keeping the time-varying gain to the end does not help: measured
  // 33x on a 30 min 100 Hz recording's imf10 AR(13), built without fused multiply-adds). BIC's
  // next best orders below are then tried, best first (order_note names the rejected ones).
  bool bad = diverges(&diverged);
  std::string rejected;
  while (bad && options.ar.fixed_order == 0 && out.fit.model.order > 1) {
    rejected += (rejected.empty() ? "AR(" : ", AR(") + std::to_string(out.fit.model.order) + ") " +
                diverged;
    ar::ArOptions lower = options.ar;
    lower.max_order = out.fit.model.order - 1;
    ar::ArFit fit = ar::FitAr(x, lower);
    if (!HasResult(fit.summary.termination)) break;
    out.fit = std::move(fit);
    filter();
    bad = diverges(&diverged);
  }
  out.order_note = out.fit.summary.order_note;
  if (!rejected.empty()) out.order_note += (out.order_note.empty() ? "" : "; ") + rejected;
  if (bad) {
    // As every failed filter (ar_kalman.h): no output.
    out.kalman.summary.termination = Termination::kNumericalFailure;
    out.kalman.summary.message = diverged +
                                 (rejected.empty() ? "" : " (and before it " + rejected + ")") +
                                 "; " + out.kalman.summary.message;
    out.kalman.filtered.resize(0);
    out.kalman.smoothed.resize(0);
  }
  return out;
}

bool FilterBrokeDown(const kalman::ArKalmanResult& result, double model_mean,
                     double component_variance, std::string* message, double rms_ratio) {
  if (result.summary.loop_unstable) {
    *message = result.summary.message;
    return true;
  }
  if (!HasResult(result.summary.termination)) return false;
  // A smoother replaced by its filter (ArKalmanSummary::smoother_replaced) is judged as a filter.
  if (result.smoothed.size() == 0 || result.summary.smoother_replaced) {
    return FilterDiverged((result.filtered.array() - model_mean).square().mean(),
                          component_variance, message, rms_ratio);
  }
  if (!FilterDiverged((result.smoothed.array() - model_mean).square().mean(), component_variance,
                      message, std::min(rms_ratio, kSmoothedRmsBound)))
    return false;
  *message = "smoother " + *message;
  return true;
}

bool FilterDiverged(double estimate_mean_square, double component_variance, std::string* message,
                    double rms_ratio) {
  if (!(component_variance > 0.0)) return false;  // nothing to compare with
  const double ratio = std::sqrt(estimate_mean_square / component_variance);
  if (!(ratio > rms_ratio)) return false;
  char text[96];
  std::snprintf(text, sizeof(text), "diverged (estimate RMS %.3g x the component's)", ratio);
  *message = text;
  return true;
}

}  // namespace fogpipe::method
