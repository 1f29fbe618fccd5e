#include "algorithms/model/compensate.h"

#include <algorithm>

namespace fogpipe::model {

namespace {

const std::string kThermalUnits = "degC";

const AuxSeries* FindSeries(const std::vector<AuxSeries>& aux, const std::string& name) {
  for (const AuxSeries& series : aux)
    if (series.name == name) return &series;
  return nullptr;
}

// Why the model cannot be evaluated on these channels ("" when it can): every channel a term
// reads must be there with the rate's length, and in the units the term was fitted in (its
// coefficients are per unit of the channel, so a channel in other units would scale the effect
// silently).
std::string MissingChannel(const DeterministicModel& model, const std::vector<AuxSeries>& aux,
                           long n) {
  for (const auto& component : model.components) {
    const std::string channel = AuxChannelOf(component.term);
    if (channel.empty()) continue;
    const AuxSeries* series = FindSeries(aux, channel);
    const std::string term = "the model's '" + ToString(component.term) + "' term";
    if (series == nullptr || series->values == nullptr)
      return term + " needs the aux channel /aux/" + channel + ", which is not there";
    if (series->values->size() != n)
      return term + " needs the aux channel /aux/" + channel + " with the rate's " +
             std::to_string(n) + " samples; it has " + std::to_string(series->values->size());
    // The thermal catalog terms are in degC (their coefficients per degC, their reference
    // temperature in degC); an aux term in the units its channel had when it was fitted.
    const std::string& units = component.term.IsAux() ? component.units : kThermalUnits;
    if (!units.empty() && series->units != units)
      return term + " was fitted on /aux/" + channel + " in " + units +
             ", but the channel here is in " + (series->units.empty() ? "no units" : series->units);
  }
  return "";
}

}  // namespace

Compensation Compensate(const Eigen::VectorXd& rate, double fs, const std::vector<AuxSeries>& aux,
                        const DeterministicModel& model, const CompensateOptions& options) {
  Compensation compensation;
  if (!(fs > 0)) {
    compensation.summary.termination = Termination::kInvalidOptions;
    compensation.summary.message = "sample_rate_hz must be > 0";
    return compensation;
  }
  if (const std::string missing = MissingChannel(model, aux, rate.size()); !missing.empty()) {
    compensation.summary.termination = Termination::kInsufficientData;
    compensation.summary.message = missing;
    return compensation;
  }
  compensation.rate_rad_s =
      rate - EvaluateDeterministic(model, rate.size(), fs, aux, options.subtract_bias);
  compensation.summary.num_effects = static_cast<int>(model.components.size());
  compensation.summary.message =
      "subtracted " + std::to_string(compensation.summary.num_effects) + " effect(s)";
  return compensation;
}

Compensation Compensate(const Eigen::VectorXd& rate, double fs, const Eigen::VectorXd* temperature,
                        const DeterministicModel& model, const CompensateOptions& options) {
  return Compensate(rate, fs, TemperatureSeries(temperature), model, options);
}

}  // namespace fogpipe::model
