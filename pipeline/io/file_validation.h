// What `fogpipe validate FILE` does, as a library function: recognise the kind of fogpipe file,
// check it against its layout schema (schemas/), and for recordings also run the reader's
// semantic checks (NaN gaps, infinities, constant axes, readable data).
#pragma once

#include <string>
#include <vector>

#include "pipeline/io/isolated_call.h"
#include "pipeline/io/recording_reader.h"
#include "pipeline/io/schema_validator.h"

namespace fogpipe::io {

/// Root attribute that marks fogpipe output files, e.g. "fogpipe-results-v2". A file without it
/// is treated as a recording (contract v1).
inline constexpr const char* kFormatAttribute = "fogpipe_format";

struct FileValidationOptions {
  /// Folder with the schema files ("" = the default search path, see SchemaSearchPath()). A
  /// recording is held to the built-in recording-v1 layout (recording_check.h) unless this or
  /// `schema` is given.
  std::string schemas_dir;
  /// Force a schema by name ("recording-v1") or path ("x/y.json"); "" = detect from the file
  /// (a fogpipe output's `fogpipe_format` tag may name a schema, never a path).
  std::string schema;
  /// Read every axis and aux channel of a recording and run the reader's checks.
  bool check_data = true;
  /// Reader options for those checks, those of `run` (ReadOptions), so that a recording
  /// `validate` calls valid is one `run` can analyse: the contract sets no minimum length, the
  /// analysis does.
  long long max_nan_gap_samples = ReadOptions{}.max_nan_gap_samples;
  long long min_samples = ReadOptions{}.min_samples;
};

struct FileValidation {
  std::string file;
  std::string detected;  ///< "recording" or "results" (or the format tag found)
  std::string schema;    ///< schema name used, e.g. "recording-v1"
  std::string schema_path;
  std::vector<SchemaProblem> problems;  ///< empty when valid
  /// Found but not making the file invalid: an aux channel `run` reads only for --model.
  std::vector<SchemaProblem> warnings;
  long long objects_checked = 0;
  long long samples_checked = 0;     ///< values read by the semantic checks
  long long samples_per_column = 0;  ///< N of a recording whose metadata were admitted
  /// Not empty when the file could not be validated for reasons outside the file (schema not
  /// found or broken): a usage error, exit code 2.
  std::string usage_error;
  bool valid() const { return usage_error.empty() && problems.empty(); }
};

/// Validates one file; never throws for problems of the file itself. Takes the HDF5 lock.
FileValidation ValidateFile(const std::string& path, const FileValidationOptions& options);

/// ValidateFile in a child process (isolated_call.h): a file that crashes or hangs the HDF5
/// library, or needs more memory than `limits` allow, is reported as one problem of that file
/// ("[reader_crashed]", "[reader_timeout]", "[reader_out_of_memory]"). Take no lock around it.
FileValidation ValidateFileIsolated(const std::string& path, const FileValidationOptions& options,
                                    const IsolationLimits& limits);

/// The `fogpipe_format` tag of a file ("" when absent or not a string: a recording). Takes the
/// HDF5 lock. Throws RecordingError when the file cannot be opened as HDF5.
std::string ReadFormatTag(const std::string& path);

/// Throws std::runtime_error naming `path` unless `root` (of that file) carries the
/// `fogpipe_format` tag `format`: what every reader of a fogpipe output checks first. Caller
/// holds LockHdf5().
void RequireFormatTag(const hdf5::Group& root, const std::string& path, const std::string& format);

/// What a reader says of a file in the previous results layout (results::kPreviousFormat): which
/// layout it is and that a rerun rewrites it (without the file's path).
std::string PreviousLayoutText();

/// The schema name for a `fogpipe_format` tag: "fogpipe-results-v2" -> "results-v2"; "" (no
/// tag) -> "recording-v1".
std::string SchemaNameForFormat(const std::string& format_tag);

}  // namespace fogpipe::io
