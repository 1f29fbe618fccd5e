#include "pipeline/io/file_validation.h"

#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/recording_reader.h"

namespace fogpipe::io {
namespace {

constexpr const char* kRecordingSchema = "recording-v1";

/// The `fogpipe_format` tag of an open file ("" when absent or not a string).
std::string FormatTag(const hdf5::File& file) {
  const hdf5::Group root = file.Root();
  if (!root.HasAttribute(kFormatAttribute)) return "";
  const hdf5::AttributeInfo info = root.DescribeAttribute(kFormatAttribute);
  if (info.type.type_class != hdf5::TypeClass::kString || info.size() != 1) return "";
  return root.ReadStringAttribute(kFormatAttribute);
}

/// The reader's checks beyond the layout: every axis and aux channel readable, NaN runs short
/// enough, no infinity, no constant axis.
void CheckRecordingData(const FileValidationOptions& options, FileValidation* result) {
  RecordingReader reader(result->file);
  ReadOptions read;
  read.max_nan_gap_samples = options.max_nan_gap_samples;
  read.min_samples = options.min_samples;
  for (int axis = 0; axis < reader.info().axis_count; ++axis) {
    try {
      result->samples_checked += reader.ReadAxisNative(axis, read).size();
    } catch (const RecordingError& e) {
      result->problems.push_back({"/rate", e.problem() + " [" + e.kind() + "]"});
    }
  }
  for (const AuxChannelInfo& aux : reader.info().aux) {
    try {
      result->samples_checked += reader.ReadAux(aux.name, read).size();
    } catch (const RecordingError& e) {
      result->problems.push_back({"/aux/" + aux.name, e.problem() + " [" + e.kind() + "]"});
    }
  }
}

}  // namespace

std::string SchemaNameForFormat(const std::string& format_tag) {
  if (format_tag.empty()) return kRecordingSchema;
  const std::string prefix = "fogpipe-";
  return format_tag.rfind(prefix, 0) == 0 ? format_tag.substr(prefix.size()) : format_tag;
}

FileValidation ValidateFile(const std::string& path, const FileValidationOptions& options) {
  FileValidation result;
  result.file = path;
  auto lock = hdf5::LockHdf5();
  try {
    const hdf5::File file = OpenHdf5ReadOnly(path);
    std::string tag;
    try {
      tag = FormatTag(file);
    } catch (const hdf5::Error& e) {
      result.problems.push_back({"/", std::string("cannot read the root attributes: ") + e.what()});
      return result;
    }
    result.detected = tag.empty() ? "recording" : tag;
    result.schema = options.schema.empty() ? SchemaNameForFormat(tag) : options.schema;
    const bool is_path = result.schema.find('/') != std::string::npos ||
                         result.schema.find(".json") != std::string::npos;
    result.schema_path =
        is_path ? result.schema : FindSchemaFile(result.schema, options.schemas_dir);
    if (result.schema_path.empty()) {
      std::string folders;
      for (const std::string& f : SchemaSearchPath(options.schemas_dir)) folders += "\n  " + f;
      result.usage_error = "schema '" + result.schema + ".json' not found; looked in:" + folders;
      return result;
    }
    const Schema schema = Schema::FromFile(result.schema_path);
    result.schema = schema.name();
    ValidationReport report = schema.Validate(file);
    result.problems = std::move(report.problems);
    result.objects_checked = report.objects_checked;
    if (result.problems.empty() && tag.empty() && options.check_data) {
      CheckRecordingData(options, &result);
    } else if (result.problems.empty() && tag.empty()) {
      RecordingReader reader(path);  // metadata checks only
    }
  } catch (const RecordingError& e) {
    result.problems.push_back({"/", e.problem() + " [" + e.kind() + "]"});
  } catch (const SchemaError& e) {
    result.usage_error = e.what();
  }
  return result;
}

}  // namespace fogpipe::io
