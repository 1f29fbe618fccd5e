#include "algorithms/model/compensate.h"

namespace fogpipe::model {

Compensation Compensate(const Eigen::VectorXd& rate, double fs, const Eigen::VectorXd* temperature,
                        const DeterministicModel& model, const CompensateOptions& options) {
  Compensation compensation;
  if (!(fs > 0)) {
    compensation.summary.termination = Termination::kInvalidOptions;
    compensation.summary.message = "sample_rate_hz must be > 0";
    return compensation;
  }
  for (const auto& component : model.components) {
    if (!AuxChannelOf(component.term).empty() && AuxChannelOf(component.term) != "temperature") {
      compensation.summary.termination = Termination::kInsufficientData;
      compensation.summary.message = "the model's '" + ToString(component.term) +
                                     "' term needs its aux channel, and only the temperature "
                                     "is passed here";
      return compensation;
    }
    if (AuxChannelOf(component.term) == "temperature" &&
        (temperature == nullptr || temperature->size() != rate.size())) {
      compensation.summary.termination = Termination::kInsufficientData;
      compensation.summary.message = std::string("the model's '") + ToString(component.term) +
                                     "' term needs an aux temperature channel of the rate's length";
      return compensation;
    }
  }
  compensation.rate_rad_s =
      rate - EvaluateDeterministic(model, rate.size(), fs, temperature, options.subtract_bias);
  compensation.summary.num_effects = static_cast<int>(model.components.size());
  compensation.summary.message =
      "subtracted " + std::to_string(compensation.summary.num_effects) + " effect(s)";
  return compensation;
}

}  // namespace fogpipe::model
