#include "pipeline/io/recording_check.h"

#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/results_layout.h"

namespace fogpipe::io {

// Generated at configure time from schemas/recording-v1.json (recording_schema_text.cpp.in).
extern const char* const kRecordingSchemaJson;

const Schema& RecordingSchema() {
  static const Schema schema =
      Schema::FromJsonText(kRecordingSchemaJson, "schemas/recording-v1.json (built in)");
  return schema;
}

RecordingError RecordingCheck::ToError() const {
  if (reader_error) return *reader_error;
  std::string list;
  for (const SchemaProblem& p : problems) {
    list += (list.empty() ? "" : "; ") + p.object + ": " + p.message;
  }
  return RecordingError(
      error_kind::kLayoutViolation, info.path,
      std::string("does not follow the ") + kRecordingSchemaName + " layout: " + list);
}

RecordingCheck CheckRecordingMetadata(const std::string& path, const hdf5::File& file,
                                      const Schema& schema) {
  RecordingCheck check;
  check.info.path = path;
  ValidationReport layout = schema.Validate(file);
  check.objects_checked = layout.objects_checked;
  check.problems = std::move(layout.problems);
  // A fogpipe output (results, sweep, campaign) names its format at the root; `validate` holds
  // it to that format's schema, so a reading command must not take it for a recording either.
  try {
    if (file.Root().HasAttribute(results::kFormatAttribute)) {
      check.problems.push_back(
          {"/", std::string("carries the attribute '") + results::kFormatAttribute +
                    "' of a fogpipe output file, so it is not read as a recording"});
    }
  } catch (const hdf5::Error&) {
    // An unreadable root is reported by the layout check and the reader.
  }
  // The reader also runs on a file the layout refuses: its refusal carries the specific kind
  // that status lines and scripts use. Listed only when the layout is clean, where it is the one
  // problem (otherwise it repeats one of the layout's in other words).
  try {
    check.info = RecordingReader(path).info();
  } catch (const RecordingError& e) {
    check.reader_error = e;
    if (check.problems.empty())
      check.problems.push_back({"/", e.problem() + " [" + e.kind() + "]"});
  }
  return check;
}

RecordingInfo AdmitRecording(const std::string& path) {
  const hdf5::File file = OpenHdf5ReadOnly(path);
  RecordingCheck check = CheckRecordingMetadata(path, file);
  if (!check.admitted()) throw check.ToError();
  return std::move(check.info);
}

RecordingInfo InspectRecording(const std::string& path) {
  auto lock = hdf5::LockHdf5();
  return AdmitRecording(path);
}

}  // namespace fogpipe::io
