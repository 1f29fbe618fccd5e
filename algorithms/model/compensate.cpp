#include "algorithms/model/compensate.h"

namespace fogpipe::model {

Compensation Compensate(const Eigen::VectorXd& rate, double fs, const Eigen::VectorXd* temp,
                        const DeterministicModel& model, const CompensateOptions& options) {
  Compensation out;
  if (!(fs > 0)) {
    out.summary.termination = Termination::kInvalidOptions;
    out.summary.message = "sample_rate_hz must be > 0";
    return out;
  }
  for (const auto& c : model.components) {
    if (NeedsTemperature(c.term) && (temp == nullptr || temp->size() != rate.size())) {
      out.summary.termination = Termination::kInsufficientData;
      out.summary.message = std::string("the model's '") + ToString(c.term) +
                            "' term needs an aux temperature channel of the rate's length";
      return out;
    }
  }
  out.rate_rad_s =
      rate - EvaluateDeterministic(model, rate.size(), fs, temp, options.subtract_bias);
  out.summary.num_effects = static_cast<int>(model.components.size());
  out.summary.message = "subtracted " + std::to_string(out.summary.num_effects) + " effect(s)";
  return out;
}

}  // namespace fogpipe::model
