#include "algorithms/method/method.h"

#include <sstream>

#include "algorithms/allan/model_edf.h"
#include "algorithms/method/white_noise.h"

namespace fogpipe::method {
namespace {

void Fail(MethodResult* result, Termination termination, const std::string& message) {
  result->summary.termination = termination;
  result->summary.message = message;
}

}  // namespace

bool MethodOptions::IsValid(std::string* error) const {
  std::string detail;
  auto fail = [&](const std::string& what) {
    if (error) *error = what + (detail.empty() ? "" : ": " + detail);
    return false;
  };
  if (!preprocess.IsValid(&detail)) return fail("preprocess");
  if (!emd.IsValid(&detail)) return fail("emd");
  if (!band_limit.IsValid(&detail)) return fail("band_limit");
  if (!component.ar.IsValid(&detail)) return fail("ar");
  if (!component.kalman.IsValid(&detail)) return fail("kalman");
  if (direct_ar_order < 0) return fail("direct_ar_order must be >= 0 (0 = by BIC)");
  if (!allan.IsValid(&detail)) return fail("allan");
  if (!noise_fit.IsValid(&detail)) return fail("noise_fit");
  if (!reference.IsValid(&detail)) return fail("reference");
  return true;
}

void SerialForEach(int n, const std::function<void(int)>& body) {
  for (int i = 0; i < n; ++i) body(i);
}

std::string ComponentName(int index, int num_imfs) {
  return index < num_imfs ? "imf" + std::to_string(index + 1) : "residue";
}

void PreprocessAndDecompose(const Eigen::VectorXd& x, double sample_rate_hz,
                            const MethodOptions& options, MethodResult* result) {
  std::string error;
  if (!options.IsValid(&error)) return Fail(result, Termination::kInvalidOptions, error);
  result->preprocessed = Preprocess(x, sample_rate_hz, options.preprocess);
  const PreprocessSummary& pre = result->preprocessed.summary;
  if (!HasResult(pre.termination)) {
    return Fail(result, pre.termination, "preprocessing: " + pre.message);
  }
  result->decomposition = emd::Decompose(result->preprocessed.signal, options.emd);
  const auto& emd_summary = result->decomposition.summary;
  if (!HasResult(emd_summary.termination)) {
    return Fail(result, emd_summary.termination, "EMD: " + emd_summary.message);
  }
  BandLimitImfs(options.band_limit, &result->decomposition);
  result->band_limit_ratio = options.band_limit.cutoff_ratio;
  result->summary.num_imfs = static_cast<int>(result->decomposition.imfs.size());
  result->summary.termination = Termination::kSuccess;
}

void ModelComponents(const MethodOptions& options, const ForEach& for_each, MethodResult* result) {
  if (!HasResult(result->summary.termination)) return;
  const emd::EmdResult& emd_result = result->decomposition;
  const int num_imfs = static_cast<int>(emd_result.imfs.size());
  const Eigen::VectorXd& signal = result->preprocessed.signal;

  // R per component (white_noise.h): the raw white-noise variance shared by mean period.
  const WhiteNoiseLevels levels = EstimateWhiteNoiseLevels(signal);
  const double white = levels.Total();
  const std::vector<double> r = ShareWhiteNoise(levels, emd_result, signal.size());

  // Slots 0..num_imfs-1: IMFs, num_imfs: residue, num_imfs + 1: method 2 on the whole signal.
  result->components.assign(num_imfs + 1, ComponentModel());
  ComponentOptions direct_options = options.component;
  direct_options.ar.fixed_order = options.direct_ar_order;
  // The raw signal's white noise is white: innovation matching is the consistent rule there.
  direct_options.noise_rule = ComponentNoiseRule::kInnovationMatch;
  for_each(num_imfs + 2, [&](int k) {
    if (k < num_imfs) {
      result->components[k] = ModelComponent(emd_result.imfs[k], r[k], options.component);
    } else if (k == num_imfs) {
      result->components[k] = ModelComponent(emd_result.residue, r[k], options.component);
    } else {
      result->direct = ModelComponent(signal, white, direct_options);
    }
  });

  for (int k = 0; k <= num_imfs; ++k) {
    const ComponentModel& c = result->components[k];
    if (!c.ok()) {
      return Fail(result, Termination::kNumericalFailure,
                  ComponentName(k, num_imfs) + ": " + c.message());
    }
  }
  if (!result->direct.ok()) {
    return Fail(result, Termination::kNumericalFailure, "method 2: " + result->direct.message());
  }
  // Eq. 12, summed in component order (fixed, whatever the schedule).
  result->method1 = Eigen::VectorXd::Zero(signal.size());
  for (int k = 0; k <= num_imfs; ++k) result->method1 += result->components[k].Output();
}

void RunReferenceFilters(double sample_rate_hz, const MethodOptions& options,
                         const ForEach& for_each, MethodResult* result) {
  if (!HasResult(result->summary.termination)) return;
  std::vector<filters::ReferenceOutput> outputs = filters::RunReferenceFilters(
      result->preprocessed.signal, sample_rate_hz, options.reference, for_each);
  result->reference.assign(outputs.size(), ReferenceEvaluation());
  for (std::size_t i = 0; i < outputs.size(); ++i)
    result->reference[i].output = std::move(outputs[i]);
}

void EvaluateAllan(double sample_rate_hz, const MethodOptions& options, const ForEach& for_each,
                   MethodResult* result) {
  if (!HasResult(result->summary.termination)) return;
  std::vector<const Eigen::VectorXd*> signals = {&result->preprocessed.signal, &result->method1,
                                                 &result->direct.Output()};
  std::vector<AllanEvaluation*> outputs = {&result->raw_allan, &result->method1_allan,
                                           &result->method2_allan};
  for (ReferenceEvaluation& r : result->reference) {
    if (!HasResult(r.output.termination)) continue;
    signals.push_back(&r.output.signal);
    outputs.push_back(&r.allan);
  }
  for_each(static_cast<int>(signals.size()), [&](int i) {
    outputs[i]->allan = allan::ComputeAllan(*signals[i], sample_rate_hz, options.allan);
    if (HasResult(outputs[i]->allan.summary.termination)) {
      outputs[i]->noise = allan::FitNoiseTermsAndModelEdf(
          options.noise_fit, options.allan.confidence, &outputs[i]->allan.table);
    }
  });
  // Terms of the filtered outputs above the raw fit's upper limits describe the filter.
  if (HasResult(result->raw_allan.allan.summary.termination)) {
    for (std::size_t i = 1; i < outputs.size(); ++i) {
      if (HasResult(outputs[i]->allan.summary.termination))
        allan::MarkTermsAboveUnfiltered(result->raw_allan.noise, &outputs[i]->noise);
    }
  }
  const char* names[3] = {"raw", "method 1", "method 2"};
  for (int i = 0; i < 3; ++i) {
    if (!HasResult(outputs[i]->allan.summary.termination)) {
      return Fail(
          result, outputs[i]->allan.summary.termination,
          std::string("Allan variance of ") + names[i] + ": " + outputs[i]->allan.summary.message);
    }
  }
}

MethodResult RunMethod(const Eigen::VectorXd& x, double sample_rate_hz,
                       const MethodOptions& options, const ForEach& for_each) {
  MethodResult result;
  PreprocessAndDecompose(x, sample_rate_hz, options, &result);
  ModelComponents(options, for_each, &result);
  RunReferenceFilters(sample_rate_hz, options, for_each, &result);
  EvaluateAllan(sample_rate_hz, options, for_each, &result);
  return result;
}

}  // namespace fogpipe::method
