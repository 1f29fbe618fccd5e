#include "pipeline/io/file_validation.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/recording_check.h"
#include "pipeline/io/recording_reader.h"
#include "pipeline/io/results_layout.h"

namespace fogpipe::io {
namespace {

/// The `fogpipe_format` tag of an open file's root ("" when absent or not a string).
std::string FormatTag(const hdf5::Group& root) {
  if (!root.HasAttribute(kFormatAttribute)) return "";
  const hdf5::AttributeInfo info = root.DescribeAttribute(kFormatAttribute);
  if (info.type.type_class != hdf5::TypeClass::kString || info.size() != 1) return "";
  return root.ReadStringAttribute(kFormatAttribute);
}

/// The reader's checks beyond the layout: every axis and aux channel readable, NaN runs short
/// enough, no infinity, no constant axis; a flagged run of one repeated value is a warning.
void CheckRecordingData(const FileValidationOptions& options, FileValidation* result) {
  RecordingReader reader(result->file);
  ReadOptions read;
  read.max_nan_gap_samples = options.max_nan_gap_samples;
  read.min_samples = options.min_samples;
  for (int axis = 0; axis < reader.info().axis_count; ++axis) {
    try {
      ReadReport report;
      result->samples_checked += reader.ReadAxisNative(axis, read, &report).size();
      const std::string repeats = DescribeRepeatedRun(report.repeats, reader.info().sample_rate_hz,
                                                      reader.info().rate_units);
      if (!repeats.empty()) {
        result->warnings.push_back({"/rate axis '" + reader.info().axis_names[axis] + "'",
                                    repeats + " (`run` flags it too)"});
      }
    } catch (const RecordingError& e) {
      result->problems.push_back({"/rate", e.problem() + " [" + e.kind() + "]"});
    }
  }
  // An aux channel is read by `run` only when --model needs it: its problems are warnings, so
  // that validate's verdict is run's.
  for (const AuxChannelInfo& aux : reader.info().aux) {
    try {
      result->samples_checked += reader.ReadAux(aux.name, read).size();
    } catch (const RecordingError& e) {
      result->warnings.push_back({"/aux/" + aux.name, e.problem() + " [" + e.kind() +
                                                          "]; `run --model` needing it fails"});
    }
  }
}

}  // namespace

std::string ReadFormatTag(const std::string& path) {
  auto lock = hdf5::LockHdf5();
  return FormatTag(OpenHdf5ReadOnly(path).Root());
}

std::string PreviousLayoutText() {
  return std::string(results::kPreviousFormat) +
         " is the previous results layout, which this fogpipe no longer reads; `fogpipe run` "
         "on its recording writes " +
         results::kFormat + " (a rerun replaces it)";
}

void RequireFormatTag(const hdf5::Group& root, const std::string& path, const std::string& format) {
  const std::string tag = FormatTag(root);
  if (tag == results::kPreviousFormat && format == results::kFormat) {
    throw std::runtime_error(path + ": " + PreviousLayoutText());
  }
  if (tag != format) {
    throw std::runtime_error(path + ": not a " + format +
                             " file (root attribute fogpipe_format missing or different)");
  }
}

std::string SchemaNameForFormat(const std::string& format_tag) {
  if (format_tag.empty()) return kRecordingSchemaName;
  const std::string prefix = "fogpipe-";
  return format_tag.rfind(prefix, 0) == 0 ? format_tag.substr(prefix.size()) : format_tag;
}

namespace {

/// The layouts of the files fogpipe writes, which ship with it (schemas/).
constexpr std::array<const char*, 4> kOutputSchemaNames = {"results-v2", "campaign-v1", "sweep-v1",
                                                           "compare-v1"};

/// A plain schema name ("results-v2"): what a file's own `fogpipe_format` may select. Anything
/// else (a path, "..") is the file's problem: a file never chooses what else is read.
bool IsPlainSchemaName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name) {
    if (!(std::islower(static_cast<unsigned char>(c)) ||
          std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '_')) {
      return false;
    }
  }
  return true;
}

/// The schema the user asked for (--schema NAME or PATH, or NAME in --schemas DIR); nullopt with
/// result->usage_error when it cannot be found or read.
std::optional<Schema> UserSchema(const std::string& name, const FileValidationOptions& options,
                                 FileValidation* result) {
  const bool is_path =
      name.find('/') != std::string::npos || name.find(".json") != std::string::npos;
  result->schema_path = is_path ? name : FindSchemaFile(name, options.schemas_dir);
  if (result->schema_path.empty()) {
    std::string folders;
    for (const std::string& f : SchemaSearchPath(options.schemas_dir)) folders += "\n  " + f;
    result->usage_error = "schema '" + name + ".json' not found; looked in:" + folders;
    return std::nullopt;
  }
  return Schema::FromFile(result->schema_path);
}

/// The schema named by a fogpipe output's `fogpipe_format` tag, from the schema search path;
/// nullopt with a problem of the file when the tag names no schema.
std::optional<Schema> TaggedSchema(const std::string& tag, const FileValidationOptions& options,
                                   FileValidation* result) {
  const std::string name = SchemaNameForFormat(tag);
  if (tag == results::kPreviousFormat) {
    result->problems.push_back({"/", PreviousLayoutText()});
    return std::nullopt;
  }
  // The layouts of fogpipe's own outputs ship with it: not finding one is an installation
  // problem, not the file's.
  if (std::find(kOutputSchemaNames.begin(), kOutputSchemaNames.end(), name) !=
      kOutputSchemaNames.end()) {
    return UserSchema(name, options, result);
  }
  if (IsPlainSchemaName(name)) result->schema_path = FindSchemaFile(name, options.schemas_dir);
  if (result->schema_path.empty()) {
    std::string known;
    for (const char* n : kOutputSchemaNames) known += (known.empty() ? "" : ", ") + std::string(n);
    result->problems.push_back({"/", "attribute 'fogpipe_format' is '" + tag +
                                         "', which names no fogpipe file format with a schema "
                                         "here (known: " +
                                         known + ")"});
    return std::nullopt;
  }
  return Schema::FromFile(result->schema_path);
}

}  // namespace

FileValidation ValidateFile(const std::string& path, const FileValidationOptions& options) {
  FileValidation result;
  result.file = path;
  auto lock = hdf5::LockHdf5();
  try {
    const hdf5::File file = OpenHdf5ReadOnly(path);
    std::string tag;
    try {
      tag = FormatTag(file.Root());
    } catch (const hdf5::Error& e) {
      result.problems.push_back({"/", std::string("cannot read the root attributes: ") + e.what()});
      return result;
    }
    result.detected = tag.empty() ? "recording" : tag;
    // A recording is held to the layout built into the binary, the one every reading command
    // uses, unless the user names another (--schema, or a --schemas folder).
    const bool built_in = tag.empty() && options.schema.empty() && options.schemas_dir.empty();
    std::optional<Schema> chosen;
    if (!built_in) {
      chosen = !options.schema.empty() ? UserSchema(options.schema, options, &result)
               : tag.empty()           ? UserSchema(kRecordingSchemaName, options, &result)
                                       : TaggedSchema(tag, options, &result);
      if (!chosen) return result;
    } else {
      result.schema_path = "(built in)";
    }
    const Schema& schema = chosen ? *chosen : RecordingSchema();
    result.schema = schema.name();
    if (tag.empty()) {
      // A recording: the checks every reading command makes (recording_check.h).
      RecordingCheck check = CheckRecordingMetadata(path, file, schema);
      result.problems = std::move(check.problems);
      result.objects_checked = check.objects_checked;
      if (check.admitted()) result.samples_per_column = check.info.samples;
      if (result.problems.empty() && options.check_data) CheckRecordingData(options, &result);
    } else {
      ValidationReport report = schema.Validate(file);
      result.problems = std::move(report.problems);
      result.objects_checked = report.objects_checked;
    }
  } catch (const RecordingError& e) {
    result.problems.push_back({"/", e.problem() + " [" + e.kind() + "]"});
  } catch (const SchemaError& e) {
    result.usage_error = e.what();
  }
  return result;
}

namespace {

// FileValidation across the pipe (the child is this same binary; JSON keeps strings exact).
std::string ToWire(const FileValidation& v) {
  nlohmann::json j;
  j["detected"] = v.detected;
  j["schema"] = v.schema;
  j["schema_path"] = v.schema_path;
  j["objects_checked"] = v.objects_checked;
  j["samples_checked"] = v.samples_checked;
  j["samples_per_column"] = v.samples_per_column;
  j["usage_error"] = v.usage_error;
  for (const SchemaProblem& p : v.problems) j["problems"].push_back({p.object, p.message});
  for (const SchemaProblem& p : v.warnings) j["warnings"].push_back({p.object, p.message});
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

FileValidation FromWire(const std::string& path, const std::string& wire) {
  const nlohmann::json j = nlohmann::json::parse(wire);
  FileValidation v;
  v.file = path;
  v.detected = j.at("detected").get<std::string>();
  v.schema = j.at("schema").get<std::string>();
  v.schema_path = j.at("schema_path").get<std::string>();
  v.objects_checked = j.at("objects_checked").get<long long>();
  v.samples_checked = j.at("samples_checked").get<long long>();
  v.samples_per_column = j.at("samples_per_column").get<long long>();
  v.usage_error = j.at("usage_error").get<std::string>();
  if (j.contains("problems")) {
    for (const auto& p : j["problems"]) v.problems.push_back({p[0], p[1]});
  }
  if (j.contains("warnings")) {
    for (const auto& p : j["warnings"]) v.warnings.push_back({p[0], p[1]});
  }
  return v;
}

FileValidation ValidateInChild(const std::string& path, const FileValidationOptions& options,
                               const IsolationLimits& limits) {
  constexpr int kOutOfMemory = 3;
  auto child = [&](std::string* out) {
    try {
      *out = ToWire(ValidateFile(path, options));
      return 0;
    } catch (const std::bad_alloc&) {
      return kOutOfMemory;
    }
  };
  IsolatedOutcome outcome = RunIsolatedLockingHdf5(child, limits);
  if (outcome.end == IsolatedOutcome::End::kExited && outcome.exit_code == 0) {
    try {
      return FromWire(path, outcome.output);
    } catch (const std::exception& e) {
      outcome.error = e.what();
    }
  }
  FileValidation v;
  v.file = path;
  if (outcome.Interrupted()) {
    v.problems.push_back({"/", "validation interrupted (" + outcome.Describe(limits) + ") [" +
                                   std::string(error_kind::kInterrupted) + "]"});
    return v;
  }
  const char* kind =
      outcome.end == IsolatedOutcome::End::kSignalled  ? error_kind::kReaderCrashed
      : outcome.end == IsolatedOutcome::End::kTimedOut ? error_kind::kReaderTimeout
      : outcome.end == IsolatedOutcome::End::kExited && outcome.exit_code == kOutOfMemory
          ? error_kind::kReaderOutOfMemory
          : error_kind::kUnreadableFile;
  v.problems.push_back({"/", "validating it in a child process: the HDF5 library " +
                                 outcome.Describe(limits) +
                                 " (damaged HDF5 metadata, a file that blocks, or an allocation "
                                 "beyond the memory limit); the file is not usable [" +
                                 std::string(kind) + "]"});
  return v;
}

}  // namespace

FileValidation ValidateFileIsolated(const std::string& path, const FileValidationOptions& options,
                                    const IsolationLimits& limits) {
  // Metadata first, under the short limit that suits it (a loop in damaged metadata is found in
  // seconds), then the samples under the caller's limit.
  if (options.check_data) {
    FileValidationOptions metadata = options;
    metadata.check_data = false;
    IsolationLimits short_limits = limits;
    short_limits.seconds = std::min(limits.seconds, IsolationLimits().seconds);
    FileValidation first = ValidateInChild(path, metadata, short_limits);
    if (!first.valid()) return first;
    // One column at a time is in memory, as in the reading commands: the allowance grows by
    // what they allow for it (isolated_reader.h), so that both accept the same lengths.
    IsolationLimits data_limits = limits;
    data_limits.extra_memory_bytes +=
        2 * static_cast<std::uint64_t>(std::max(first.samples_per_column, 0ll)) * sizeof(double);
    return ValidateInChild(path, options, data_limits);
  }
  return ValidateInChild(path, options, limits);
}

}  // namespace fogpipe::io
