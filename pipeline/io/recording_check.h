// Whether a file is a recording fogpipe can analyse: one set of checks for `validate` and for
// every command that reads recordings (`run`, `sweep`, `allan`, `compare`, `merge`), so that a
// file `validate` calls valid is one they accept and the other way round.
//
// The metadata checks are the recording-v1 layout (schemas/recording-v1.json, compiled into the
// binary so that no command depends on finding schema files at run time) and the reader's
// (recording_reader.h: shapes, types, units, sample rate, external data, declared sizes). The
// samples are checked by the reader as they are read, with the caller's ReadOptions.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/hdf5/file.h"
#include "pipeline/io/recording_error.h"
#include "pipeline/io/recording_reader.h"
#include "pipeline/io/schema_validator.h"

namespace fogpipe::io {

inline constexpr const char* kRecordingSchemaName = "recording-v1";

/// The recording-v1 schema as built into this binary (from schemas/recording-v1.json).
const Schema& RecordingSchema();

/// What the metadata checks found.
struct RecordingCheck {
  RecordingInfo info;  ///< what the reader found; meaningful when admitted()
  /// The reader's refusal, when it refused (its kind is the most specific one).
  std::optional<RecordingError> reader_error;
  /// Every problem of the layout; when there is none, the reader's refusal, tagged "[kind]".
  std::vector<SchemaProblem> problems;
  long long objects_checked = 0;
  bool admitted() const { return problems.empty(); }
  /// The refusal as the RecordingError a reading command reports: the reader's own, or one of
  /// kind layout_violation listing the layout's problems.
  RecordingError ToError() const;
};

/// Checks `file` against `schema` and runs the reader's metadata checks on `path` (the same
/// file, already opened read-only). Never throws for problems of the file. Caller holds
/// LockHdf5().
RecordingCheck CheckRecordingMetadata(const std::string& path, const hdf5::File& file,
                                      const Schema& schema = RecordingSchema());

/// The metadata of an admitted recording. Throws the RecordingError of RecordingCheck::ToError
/// for any other file. Caller holds LockHdf5().
RecordingInfo AdmitRecording(const std::string& path);

/// AdmitRecording under the HDF5 lock (takes it).
RecordingInfo InspectRecording(const std::string& path);

}  // namespace fogpipe::io
