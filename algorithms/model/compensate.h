// Compensation of the deterministic effects of a fitted gyro model. `fogpipe run --model FILE`
// removes them before the EMD, AR and Kalman stages, so that an effect added to the model in
// `fogpipe compare` also improves the filtered output and its Allan tables.
//
// The effects are re-evaluated on the recording being compensated (deterministic_fit.h,
// EvaluateDeterministic): temperature and aux terms use that recording's aux channels (smoothed
// and differentiated exactly as in the fit), bias_step and warmup use time from its first sample.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/common/status.h"
#include "algorithms/model/deterministic_fit.h"

namespace fogpipe::model {

struct CompensateOptions {
  /// Also subtract the fitted constant bias (off by default: the bias is part of the gyro's
  /// output that the later stages and the Allan tables ignore anyway).
  bool subtract_bias = false;
  bool IsValid(std::string* error) const { return true; }
};

struct CompensationSummary {
  Termination termination = Termination::kSuccess;
  std::string message;
  int num_effects = 0;  ///< deterministic components subtracted
};

struct Compensation {
  Eigen::VectorXd rate_rad_s;  ///< input minus the effects, rad/s
  CompensationSummary summary;
};

/// rate - effects(model), the effects evaluated on the recording's aux channels. Every channel a
/// term reads (AuxChannelOf) must be in `aux` with the rate's length and, for aux terms, in the
/// units it was fitted in (DeterministicComponent::units); otherwise kInsufficientData, an empty
/// rate and a message naming the term and the channel.
Compensation Compensate(const Eigen::VectorXd& rate_rad_s, double sample_rate_hz,
                        const std::vector<AuxSeries>& aux, const DeterministicModel& model,
                        const CompensateOptions& options);
/// The same with at most the aux channel "temperature" (degC; may be null).
Compensation Compensate(const Eigen::VectorXd& rate_rad_s, double sample_rate_hz,
                        const Eigen::VectorXd* temperature_degc, const DeterministicModel& model,
                        const CompensateOptions& options);

}  // namespace fogpipe::model
