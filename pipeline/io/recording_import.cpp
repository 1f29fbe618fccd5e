#include "pipeline/io/recording_import.h"

#include <cmath>
#include <filesystem>
#include <set>
#include <system_error>
#include <utility>

#include "pipeline/hdf5/atomic_output_file.h"
#include "pipeline/io/file_validation.h"
#include "pipeline/io/missing_samples.h"
#include "pipeline/io/recording_check.h"
#include "pipeline/io/recording_error.h"

namespace fogpipe::io {
namespace {

namespace fs = std::filesystem;

bool AreValidAxisNames(const std::vector<std::string>& names, std::string* bad) {
  std::set<std::string> seen;
  for (const std::string& name : names) {
    if (!IsValidAxisName(name) || !seen.insert(name).second) {
      if (bad) *bad = name;
      return false;
    }
  }
  return true;
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "'" : ", '") + name + "'";
  return text;
}

// What `run` will make of one column with its default read options (ReadOptions): its NaN runs
// bridged or refused, a constant column refused. Adds to `warnings` what makes `run` refuse the
// recording and to `notes` what it repairs.
void DescribeColumn(const std::string& what, const Eigen::VectorXd& column, bool reject_constant,
                    std::vector<std::string>* warnings, std::vector<std::string>* notes) {
  const ReadOptions defaults;
  Eigen::VectorXd bridged = column;
  BridgeReport report;
  const bool all_bridged = BridgeNanRuns(bridged, defaults.max_nan_gap_samples, &report);
  if (report.runs > 0) {
    const long long missing = column.array().isNaN().count();
    const std::string text = what + ": " + std::to_string(missing) + " missing sample" +
                             (missing == 1 ? "" : "s") + " in " + std::to_string(report.runs) +
                             " run" + (report.runs == 1 ? "" : "s") + ", the longest " +
                             std::to_string(report.longest_run) + " from sample " +
                             std::to_string(report.longest_run_start) + " (0-based)";
    if (all_bridged) {
      notes->push_back(text + "; the reader bridges runs of up to " +
                       std::to_string(defaults.max_nan_gap_samples) + " samples");
    } else {
      warnings->push_back(text + "; `run` and `validate` bridge runs of up to " +
                          std::to_string(defaults.max_nan_gap_samples) +
                          " samples and refuse this recording unless given --max-nan-gap " +
                          std::to_string(report.longest_run) + " or more");
    }
  }
  if (reject_constant && all_bridged && bridged.size() > 0 &&
      (bridged.array() == bridged[0]).all()) {
    warnings->push_back(what + ": every value is the same; `run` refuses a constant axis");
  }
}

// The sample rate: --sample-rate-hz when given, else what the source found. Sets *from to where
// it came from, for the provenance. False when there is none.
bool ResolveSampleRate(const ImportSource& source, const ImportMetadataOptions& options,
                       RecordingData* data, std::string* from) {
  const bool rate_given = options.sample_rate_hz > 0.0;
  data->sample_rate_hz = rate_given ? options.sample_rate_hz : source.sample_rate_hz;
  *from = rate_given ? "--sample-rate-hz" : source.sample_rate_from;
  return data->sample_rate_hz > 0.0 && std::isfinite(data->sample_rate_hz);
}

// Axis names from --axes, else from the source when they are valid (a note says why not).
bool NameAxes(const ImportSource& source, const ImportMetadataOptions& options,
              ImportedRecording* out, std::string* error) {
  const Eigen::Index axes = source.rate.cols();
  if (!options.axes.empty()) {
    if (static_cast<Eigen::Index>(options.axes.size()) != axes) {
      *error = "--axes names " + std::to_string(options.axes.size()) + " axes but the rate has " +
               std::to_string(axes) + " column" + (axes == 1 ? "" : "s");
      return false;
    }
    out->data.axes = options.axes;
  } else if (!source.axis_names.empty()) {
    if (AreValidAxisNames(source.axis_names, nullptr)) {
      out->data.axes = source.axis_names;
    } else {
      out->notes.push_back("the source's column names " + JoinNames(source.axis_names) +
                           " are not valid axis names (unique, non-empty, no '/'); the axes are "
                           "unnamed (axis0, axis1, ...): give --axes to name them");
    }
  }
  return true;
}

// Moves the rate (scaled) and the aux channels the options name from the source into `data`.
bool TakeSamples(const ImportMetadataOptions& options, ImportSource* source, RecordingData* data,
                 std::string* error) {
  const Eigen::Index samples = source->rate.rows();
  data->rate_in_output_unit = std::move(source->rate);
  if (options.scale_factor != 1.0) data->rate_in_output_unit *= options.scale_factor;
  for (const AuxImportSpec& spec : options.aux) {
    auto found = source->aux.find(spec.name);
    if (found == source->aux.end()) {
      *error = "aux '" + spec.name + "' was not read";
      return false;
    }
    if (found->second.size() != samples) {
      *error = "aux '" + spec.name + "' has " + std::to_string(found->second.size()) +
               " values, the rate " + std::to_string(samples) + " samples";
      return false;
    }
    data->aux[spec.name] = AuxChannel{std::move(found->second), spec.units};
  }
  return true;
}

// Warns of and notes what `run` will refuse or repair; returns the missing samples per axis.
nlohmann::json DescribeSamples(ImportedRecording* out) {
  const RecordingData& data = out->data;
  nlohmann::json missing = nlohmann::json::object();
  for (Eigen::Index a = 0; a < data.rate_in_output_unit.cols(); ++a) {
    const std::string name = data.axes.empty() ? "axis" + std::to_string(a) : data.axes[a];
    missing[name] = data.rate_in_output_unit.col(a).array().isNaN().count();
    DescribeColumn("axis '" + name + "'", data.rate_in_output_unit.col(a), true, &out->warnings,
                   &out->notes);
  }
  for (const auto& [name, channel] : data.aux) {
    DescribeColumn("aux '" + name + "'", channel.samples, false, &out->warnings, &out->notes);
  }
  const Eigen::Index samples = data.rate_in_output_unit.rows();
  const long long min_samples = ReadOptions().min_samples;
  if (samples < min_samples) {
    out->warnings.push_back("only " + std::to_string(samples) + " samples; `run` needs at least " +
                            std::to_string(min_samples));
  }
  return missing;
}

// The import_provenance attribute: the source file, every option, what was found.
nlohmann::json ImportProvenance(const ImportMetadataOptions& options, const RecordingData& data,
                                const std::string& rate_from, nlohmann::json missing,
                                ImportSource* source) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(source->path, ec);
  nlohmann::json found = std::move(source->found);
  found["samples"] = data.rate_in_output_unit.rows();
  found["axes"] = data.rate_in_output_unit.cols();
  found["sample_rate_hz"] = data.sample_rate_hz;
  found["sample_rate_from"] = rate_from;
  found["missing_samples"] = std::move(missing);
  nlohmann::json all_options = std::move(source->options);
  all_options["metadata"] = options.ToJson();
  return {{"source",
           {{"path", ec ? source->path : absolute.lexically_normal().string()},
            {"format", source->format},
            {"sha256", source->sha256},
            {"size_bytes", source->size_bytes}}},
          {"options", std::move(all_options)},
          {"found", std::move(found)}};
}

}  // namespace

bool ParseAuxImportSpec(const std::string& text, AuxImportSpec* spec, std::string* error) {
  const size_t equals = text.find('=');
  const size_t colon = text.rfind(':');
  if (equals == std::string::npos || colon == std::string::npos || colon < equals || equals == 0 ||
      colon == equals + 1 || colon + 1 == text.size()) {
    if (error) *error = "aux '" + text + "': expected NAME=SOURCE:UNITS, e.g. temperature=T:degC";
    return false;
  }
  AuxImportSpec parsed{text.substr(0, equals), text.substr(equals + 1, colon - equals - 1),
                       text.substr(colon + 1)};
  if (parsed.name.find('/') != std::string::npos || parsed.name == "." || parsed.name == "..") {
    if (error) *error = "aux '" + text + "': the name '" + parsed.name + "' cannot hold a '/'";
    return false;
  }
  *spec = std::move(parsed);
  return true;
}

bool ImportMetadataOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!units::ParseRateUnit(rate_units)) {
    return fail("the rate units must be deg/h, deg/s or rad/s (given: '" + rate_units + "')");
  }
  if (!std::isfinite(scale_factor) || scale_factor == 0.0) {
    return fail("the scale factor must be finite and not 0");
  }
  if (!std::isfinite(sample_rate_hz) || sample_rate_hz < 0.0) {
    return fail("the sample rate must be finite and > 0 (0: from the source)");
  }
  std::string bad;
  if (!AreValidAxisNames(axes, &bad)) {
    return fail("axis name '" + bad + "' is empty, repeated or holds a '/'");
  }
  std::set<std::string> aux_names;
  for (const AuxImportSpec& spec : aux) {
    if (spec.name.empty() || spec.source.empty() || spec.units.empty()) {
      return fail("every aux channel needs a name, a source and units");
    }
    if (!aux_names.insert(spec.name).second) return fail("aux '" + spec.name + "' given twice");
  }
  if (latitude_deg && !(std::abs(*latitude_deg) <= 90.0)) {
    return fail("the latitude must be in [-90, 90] deg");
  }
  return true;
}

nlohmann::json ImportMetadataOptions::ToJson() const {
  nlohmann::json j;
  j["rate_units"] = rate_units;
  j["scale_factor"] = scale_factor;
  j["sample_rate_hz"] = sample_rate_hz > 0.0 ? nlohmann::json(sample_rate_hz) : nullptr;
  j["axes"] = axes;
  nlohmann::json aux_list = nlohmann::json::array();
  for (const AuxImportSpec& spec : aux) {
    aux_list.push_back({{"name", spec.name}, {"source", spec.source}, {"units", spec.units}});
  }
  j["aux"] = aux_list;
  j["instrument"] = instrument;
  j["serial"] = serial;
  j["start_time_utc"] = start_time_utc;
  j["latitude_deg"] = latitude_deg ? nlohmann::json(*latitude_deg) : nullptr;
  return j;
}

ImportResult FinishImport(ImportSource source, const ImportMetadataOptions& options) {
  ImportResult result;
  auto fail = [&](const std::string& message) {
    result.error = source.path + ": " + message;
    return result;
  };
  std::string error;
  if (!options.IsValid(&error)) return fail(error);
  if (source.rate.rows() < 1 || source.rate.cols() < 1) return fail("no samples to import");

  ImportedRecording& out = result.recording;
  RecordingData& data = out.data;
  out.rate_unit = *units::ParseRateUnit(options.rate_units);
  std::string rate_from;
  if (!ResolveSampleRate(source, options, &data, &rate_from)) {
    return fail(
        "no sample rate: give --sample-rate-hz, a time column (text) or a sample-rate "
        "variable (MATLAB)");
  }
  if (!NameAxes(source, options, &out, &error)) return fail(error);
  if (!TakeSamples(options, &source, &data, &error)) return fail(error);
  data.instrument = options.instrument;
  data.serial = options.serial;
  data.start_time_utc = options.start_time_utc;
  data.latitude_deg = options.latitude_deg;
  nlohmann::json missing = DescribeSamples(&out);
  out.provenance = ImportProvenance(options, data, rate_from, std::move(missing), &source);
  return result;
}

ImportWriteResult WriteImportedRecording(const std::string& output_path,
                                         ImportedRecording recording) {
  ImportWriteResult result;
  RecordingWriterOptions writer;
  writer.rate_unit = recording.rate_unit;
  writer.sample_type = SampleType::kFloat64;
  RecordingData& data = recording.data;
  // Header names from Windows tools are often Latin-1, not UTF-8: replaced, not an exception.
  data.extra_root_attributes[kImportProvenanceAttribute] =
      recording.provenance.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  const fs::path final_path(output_path);
  const fs::path staged = hdf5::MakeAtomicTempPath(final_path);
  std::error_code ec;
  try {
    WriteRecording(staged.string(), data, writer);
  } catch (const std::exception& e) {
    result.error = output_path + ": cannot write: " + e.what();
    return result;
  }
  try {
    result.info = InspectRecording(staged.string());
  } catch (const RecordingError& e) {
    fs::remove(staged, ec);
    result.error = output_path + ": not written: the recording checks refuse it: " + e.problem() +
                   " [" + e.kind() + "]";
    return result;
  } catch (const std::exception& e) {
    fs::remove(staged, ec);
    result.error = output_path + ": not written: checking it failed: " + e.what();
    return result;
  }
  // What `import` writes is what `validate` calls valid and `run` analyses: the samples are
  // checked as `validate` checks them, with `run`'s reader limits, before the file gets its name.
  const FileValidation validation = ValidateFile(staged.string(), FileValidationOptions());
  if (!validation.valid()) {
    fs::remove(staged, ec);
    result.error = output_path + ": not written: `run` would refuse it (fix the source or the " +
                   "import options):";
    for (const SchemaProblem& p : validation.problems)
      result.error += "\n  " + p.object + ": " + p.message;
    return result;
  }
  fs::rename(staged, final_path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(staged, ignored);
    result.error = output_path + ": cannot rename the checked file into place: " + ec.message();
    return result;
  }
  result.info.path = output_path;
  return result;
}

}  // namespace fogpipe::io
