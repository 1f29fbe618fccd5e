#include "pipeline/io/recording_writer.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "algorithms/simulation/navigation_grade.h"
#include "pipeline/hdf5/atomic_output_file.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/text_output_file.h"

namespace fogpipe::io {
namespace {

namespace fs = std::filesystem;
namespace sim = fogpipe::simulation;

bool InOutputUnit(const RecordingData& data) { return data.rate_in_output_unit.size() > 0; }

const Eigen::MatrixXd& RateMatrix(const RecordingData& data) {
  return InOutputUnit(data) ? data.rate_in_output_unit : data.rate_rad_s;
}

void Validate(const RecordingData& data, const RecordingWriterOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  if (!(data.sample_rate_hz > 0.0) || !std::isfinite(data.sample_rate_hz)) {
    throw std::invalid_argument("sample_rate_hz must be finite and > 0");
  }
  if (InOutputUnit(data) && data.rate_rad_s.size() > 0) {
    throw std::invalid_argument("give the rate either in rad/s or in the output unit, not both");
  }
  const Eigen::MatrixXd& rate = RateMatrix(data);
  if (rate.rows() < 1 || rate.cols() < 1) {
    throw std::invalid_argument("the rate needs at least one sample and one axis");
  }
  if (!data.axes.empty() && data.axes.size() != static_cast<size_t>(rate.cols())) {
    throw std::invalid_argument("one axis name per rate column is needed");
  }
  static const char* const kReserved[] = {"sample_rate_hz", "start_time_utc", "instrument",
                                          "serial",         "latitude_deg",   "fogpipe_format"};
  for (const auto& [name, value] : data.extra_root_attributes) {
    if (name.empty() ||
        std::find(std::begin(kReserved), std::end(kReserved), name) != std::end(kReserved)) {
      throw std::invalid_argument("root attribute '" + name + "' cannot be set as an extra");
    }
  }
  for (const auto& [name, channel] : data.aux) {
    if (channel.samples.size() != rate.rows()) {
      throw std::invalid_argument("aux channel '" + name + "' must have as many samples as /rate");
    }
    if (name.empty() || name.find('/') != std::string::npos || channel.units.empty()) {
      throw std::invalid_argument("aux channel '" + name + "' needs a plain name and units");
    }
  }
}

hdf5::DatasetOptions Layout(const RecordingWriterOptions& options, SampleType type) {
  hdf5::DatasetOptions layout;
  layout.storage =
      type == SampleType::kFloat32 ? hdf5::StorageType::kFloat32 : hdf5::StorageType::kFloat64;
  layout.chunk_rows = options.chunk_samples;
  layout.deflate_level = options.deflate_level;
  layout.shuffle = options.deflate_level > 0;
  layout.min_chunked_elements = 0;  // always chunked, whatever the length
  return layout;
}

}  // namespace

const char* ToString(SampleType type) {
  return type == SampleType::kFloat32 ? "float32" : "float64";
}

bool RecordingWriterOptions::IsValid(std::string* error) const {
  if (chunk_samples < 1) {
    if (error) *error = "chunk_samples must be >= 1";
    return false;
  }
  if (deflate_level < 0 || deflate_level > 9) {
    if (error) *error = "deflate_level must be in 0..9";
    return false;
  }
  return true;
}

void WriteRecording(const std::string& path, const RecordingData& data,
                    const RecordingWriterOptions& options) {
  Validate(data, options);
  const Eigen::Index n = RateMatrix(data).rows();
  const Eigen::Index axes = RateMatrix(data).cols();
  // Row-major [N, A] in the declared unit (HDF5 converts to float32 on writing when asked).
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMajor rate = InOutputUnit(data)
                            ? RowMajor(data.rate_in_output_unit)
                            : RowMajor(data.rate_rad_s / units::ToRadPerSecond(options.rate_unit));
  const bool one_d = axes == 1 && options.squeeze_single_axis;
  std::vector<hsize_t> dims = {static_cast<hsize_t>(n)};
  if (!one_d) dims.push_back(static_cast<hsize_t>(axes));

  hdf5::SilenceHdf5ErrorPrinter();
  auto lock = hdf5::LockHdf5();  // declared first, released last (pipeline/hdf5/hdf5_lock.h)
  try {
    hdf5::AtomicOutputFile output(path);
    {
      hdf5::Group root = output.Root();
      root.WriteDoubleAttribute("sample_rate_hz", data.sample_rate_hz);
      if (!data.start_time_utc.empty()) {
        root.WriteStringAttribute("start_time_utc", data.start_time_utc);
      }
      if (!data.instrument.empty()) root.WriteStringAttribute("instrument", data.instrument);
      if (!data.serial.empty()) root.WriteStringAttribute("serial", data.serial);
      if (data.latitude_deg) root.WriteDoubleAttribute("latitude_deg", *data.latitude_deg);
      for (const auto& [name, value] : data.extra_root_attributes) {
        root.WriteStringAttribute(name, value);
      }
      hdf5::Dataset dataset =
          root.WriteDataset("rate", rate.data(), dims, units::ToString(options.rate_unit),
                            Layout(options, options.sample_type));
      if (!data.axes.empty()) dataset.WriteStringArrayAttribute("axes", data.axes);
      if (!data.aux.empty()) {
        hdf5::Group aux = root.CreateGroup("aux");
        for (const auto& [name, channel] : data.aux) {
          aux.WriteDataset(name, channel.samples, channel.units,
                           Layout(options, SampleType::kFloat64));
        }
      }
    }  // every wrapper is released before the commit closes the file
    output.Commit();
  } catch (const hdf5::Error& e) {
    throw std::runtime_error(path + ": " + e.what());
  } catch (const fs::filesystem_error& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

std::string TruthSidecarPath(const std::string& recording_path) {
  return recording_path + ".truth.json";
}

void WriteJsonFile(const std::string& path, const nlohmann::json& json) {
  WriteTextFileAtomically(path, json.dump(2) + "\n");
}

namespace {

using nlohmann::json;

json RateComponentToJson(const sim::RateComponent& c) {
  using units::RadPerSecondToDegPerHour;
  json item{{"kind", sim::ToString(c.kind)}};
  switch (c.kind) {
    case sim::RateComponent::Kind::kConstant:
      item["value_deg_h"] = RadPerSecondToDegPerHour(c.value_rad_s);
      break;
    case sim::RateComponent::Kind::kStep:
      item["start_s"] = c.start_s;
      item["value_deg_h"] = RadPerSecondToDegPerHour(c.value_rad_s);
      break;
    case sim::RateComponent::Kind::kRamp:
      item["start_s"] = c.start_s;
      item["end_s"] = c.end_s;
      item["slope_deg_h_per_s"] = RadPerSecondToDegPerHour(c.slope_rad_s2);
      break;
    case sim::RateComponent::Kind::kSine:
      item["frequency_hz"] = c.frequency_hz;
      item["amplitude_deg_h"] = RadPerSecondToDegPerHour(c.value_rad_s);
      item["phase_rad"] = c.phase_rad;
      break;
  }
  return item;
}

json AuxTemperatureToJson(const std::optional<sim::TemperatureProfile>& temperature) {
  if (!temperature) return nullptr;
  const sim::TemperatureProfile& t = *temperature;
  return {{"mean_degC", t.mean_degC},
          {"peak_to_peak_degC", t.peak_to_peak_degC},
          {"period_s", t.period_s},
          {"sharpness", t.sharpness},
          {"phase_rad", t.phase_rad},
          {"noise_std_degC", t.noise_std_degC},
          {"max_abs_rate_degC_per_s", sim::MaxAbsTemperatureRate(t)}};
}

// The stochastic terms of the catalog; an absent term (zero) writes no key.
void AddNoiseTerms(const sim::GyroErrorModel& e, json* axis) {
  using namespace fogpipe::units;
  json& a = *axis;
  if (e.n_rad_sqrt_s > 0.0) {
    a["white"] = {{"n_deg_sqrt_h", ArwToDegPerSqrtHour(e.n_rad_sqrt_s)},
                  {"n_rad_sqrt_s", e.n_rad_sqrt_s}};
  }
  if (e.q_rad > 0.0) {
    a["quantization"] = {{"q_arcsec", QuantizationToArcsec(e.q_rad)},
                         {"q_rad", e.q_rad},
                         {"model", sim::ToString(e.quantization_model)}};
  }
  if (e.b_rad_s > 0.0) {
    a["bias_instability"] = {
        {"b_deg_h", BiasToDegPerHour(e.b_rad_s)},
        {"b_rad_s", e.b_rad_s},
        {"allan_floor_deg_h", BiasToDegPerHour(sim::BiasInstabilityFloor(e.b_rad_s))}};
  }
  if (e.k_rad_s_sqrt_s > 0.0) {
    a["rate_random_walk"] = {{"k_deg_h_sqrt_h", RrwToDegPerHourSqrtHour(e.k_rad_s_sqrt_s)},
                             {"k_rad_s_sqrt_s", e.k_rad_s_sqrt_s}};
  }
  if (e.r_rad_s2 != 0.0) {
    a["rate_ramp"] = {{"r_deg_h2", RampToDegPerHour2(e.r_rad_s2)}, {"r_rad_s2", e.r_rad_s2}};
  }
  if (!e.gauss_markov.empty()) {
    json list = json::array();
    for (const sim::GaussMarkovTerm& g : e.gauss_markov) {
      list.push_back({{"sigma_deg_h", RadPerSecondToDegPerHour(g.sigma_rad_s)},
                      {"sigma_rad_s", g.sigma_rad_s},
                      {"correlation_time_s", g.correlation_time_s}});
    }
    a["gauss_markov"] = list;
  }
}

// The deterministic and environmental terms; an absent term writes no key.
void AddSystematicTerms(const sim::GyroErrorModel& e, json* axis) {
  using units::RadPerSecondToDegPerHour;
  json& a = *axis;
  if (!e.sinusoids.empty()) {
    json list = json::array();
    for (const sim::SinusoidTerm& s : e.sinusoids) {
      list.push_back({{"frequency_hz", s.frequency_hz},
                      {"amplitude_deg_h", RadPerSecondToDegPerHour(s.amplitude_rad_s)},
                      {"amplitude_rad_s", s.amplitude_rad_s},
                      {"phase_rad", s.phase_rad}});
    }
    a["sinusoid"] = list;
  }
  if (e.temperature) {
    a["temperature"] = {{"coefficient_deg_h_per_degC",
                         RadPerSecondToDegPerHour(e.temperature->coefficient_rad_s_per_degC)},
                        {"coefficient_rad_s_per_degC", e.temperature->coefficient_rad_s_per_degC},
                        {"reference_degC", e.temperature->reference_degC}};
  }
  if (e.temperature_rate) {
    a["temperature_rate"] = {
        {"coefficient_deg_h_per_degC_per_s",
         RadPerSecondToDegPerHour(e.temperature_rate->coefficient_rad_s_per_degC_per_s)},
        {"coefficient_rad_s_per_degC_per_s", e.temperature_rate->coefficient_rad_s_per_degC_per_s}};
  }
  if (!e.bias_steps.empty()) {
    json list = json::array();
    for (const sim::BiasStep& s : e.bias_steps) {
      list.push_back({{"time_s", s.time_s},
                      {"size_deg_h", RadPerSecondToDegPerHour(s.size_rad_s)},
                      {"size_rad_s", s.size_rad_s}});
    }
    a["bias_step"] = list;
  }
  if (e.warmup) {
    a["warmup"] = {{"amplitude_deg_h", RadPerSecondToDegPerHour(e.warmup->amplitude_rad_s)},
                   {"amplitude_rad_s", e.warmup->amplitude_rad_s},
                   {"time_constant_s", e.warmup->time_constant_s}};
  }
}

json AxisTruthToJson(const sim::SimulationTruth& truth, const std::string& name) {
  const sim::GyroErrorModel& e = truth.options.errors;
  json a;
  a["name"] = name;
  a["stream_axis"] = truth.options.axis;
  json terms = json::array();
  for (sim::Term term : truth.terms) terms.push_back(sim::ToString(term));
  a["terms"] = terms;
  a["bias_deg_h"] = units::RadPerSecondToDegPerHour(e.bias_rad_s);
  a["bias_rad_s"] = e.bias_rad_s;
  AddNoiseTerms(e, &a);
  AddSystematicTerms(e, &a);
  return a;
}

}  // namespace

nlohmann::json SimulationTruthToJson(const std::vector<sim::SimulationTruth>& axes,
                                     const std::vector<std::string>& axis_names) {
  if (axes.empty()) throw std::invalid_argument("the truth needs at least one axis");
  const sim::GyroSimulatorOptions& first = axes.front().options;
  json j;
  j["format"] = "fogpipe-simulation-truth";
  j["format_version"] = 1;
  j["note"] = "ground truth of a simulated recording; the analysis never reads this file";
  j["seed"] = first.seed;
  j["sample_rate_hz"] = first.sample_rate_hz;
  j["duration_s"] = first.duration_s;
  j["num_samples"] = axes.front().num_samples;
  j["latitude_deg"] = first.latitude_deg ? json(*first.latitude_deg) : json(nullptr);
  j["earth_rate_deg_h"] = units::RadPerSecondToDegPerHour(axes.front().earth_rate_rad_s);
  j["earth_rate_rad_s"] = axes.front().earth_rate_rad_s;

  json input = json::array();
  for (const sim::RateComponent& c : first.input_rate.components) {
    input.push_back(RateComponentToJson(c));
  }
  j["input_rate"] = input;
  j["input_rate_text"] = sim::FormatRateProfile(first.input_rate);
  j["aux_temperature"] = AuxTemperatureToJson(first.temperature);

  json axis_list = json::array();
  for (size_t i = 0; i < axes.size(); ++i) {
    axis_list.push_back(
        AxisTruthToJson(axes[i], i < axis_names.size() ? axis_names[i] : std::to_string(i)));
  }
  j["axes"] = axis_list;
  return j;
}

Eigen::VectorXd TrueRateFromTruth(const nlohmann::json& truth) {
  try {
    sim::RateProfile profile;
    std::string error;
    if (!sim::ParseRateProfile(truth.at("input_rate_text").get<std::string>(), &profile, &error)) {
      throw std::runtime_error("truth: input_rate_text: " + error);
    }
    const double sample_rate_hz = truth.at("sample_rate_hz").get<double>();
    const auto n = truth.at("num_samples").get<Eigen::Index>();
    return sim::SampleRateProfile(profile, n, sample_rate_hz).array() +
           truth.at("earth_rate_rad_s").get<double>();
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("truth JSON: ") + e.what());
  }
}

}  // namespace fogpipe::io
