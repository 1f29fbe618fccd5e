// What the importers of `fogpipe import` share: the options that describe a recording beyond its
// source's layout, the imported recording as data, and writing it as a contract-v1 recording
// (schemas/README.md, "Recording contract v1") that the shared recording checks admit.
//
// The importers (text_import.h, matlab_import.h) read a source into an ImportSource; FinishImport
// applies the options every source shares; WriteImportedRecording writes the result through the
// recording writer (recording_writer.h) and checks it with InspectRecording (recording_check.h),
// so that what `import` writes is what `run` and `validate` accept. Errors are data: every
// function here returns them, naming the file (and, for text, the line and the column).
#pragma once

#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/common/units.h"
#include "pipeline/io/recording_reader.h"
#include "pipeline/io/recording_writer.h"

namespace fogpipe::io {

/// Root attribute of an imported recording: JSON text saying where it came from (the source's
/// absolute path, SHA-256, size and format, the importer's options and what it found in the
/// source). Readers of contract v1 ignore it.
inline constexpr const char* kImportProvenanceAttribute = "import_provenance";

/// One aux channel to import, given as "NAME=SOURCE:UNITS", e.g. "temperature=T:degC".
struct AuxImportSpec {
  std::string name;    ///< written as /aux/<name>
  std::string source;  ///< a column (name or 0-based index) of a text file, a MATLAB variable
  std::string units;   ///< the channel's units as written, e.g. "degC"
};

/// Parses "NAME=SOURCE:UNITS": the first '=' ends the name, the last ':' starts the units, so a
/// column name may contain ':' and '='. Returns false with *error on a malformed spec.
bool ParseAuxImportSpec(const std::string& text, AuxImportSpec* spec, std::string* error);

/// What describes a recording beyond the source's layout.
struct ImportMetadataOptions {
  /// Unit of the rate after the scale factor: "deg/h", "deg/s" or "rad/s". No default: gyro
  /// files state their unit, if at all, in free text.
  std::string rate_units;
  /// rate = value x scale_factor (in rate_units), e.g. for integer counts of a gyro's output.
  /// 1 (default) keeps the source's values bit for bit.
  double scale_factor = 1.0;
  /// Samples per second, Hz. 0 (default): from the source (a time column, a sample-rate
  /// variable); given together with a time column, the two must agree.
  double sample_rate_hz = 0.0;
  /// Names of the rate columns, one per axis. Empty (default): a text header's names when they
  /// are valid axis names, otherwise none (readers then say axis0, axis1, ...).
  std::vector<std::string> axes;
  /// Aux channels to import (none by default).
  std::vector<AuxImportSpec> aux;
  std::string instrument;      ///< root attribute `instrument`; omitted when empty (default)
  std::string serial;          ///< root attribute `serial`; omitted when empty (default)
  std::string start_time_utc;  ///< root attribute `start_time_utc`, ISO 8601; omitted when empty
  std::optional<double> latitude_deg;  ///< root attribute `latitude_deg`, [-90, 90]; none default

  bool IsValid(std::string* error) const;
  nlohmann::json ToJson() const;
};

/// What an importer read from its source, before the shared options are applied.
struct ImportSource {
  std::string path;
  std::string format;    ///< "text", "matlab-v7.3" or "hdf5"
  Eigen::MatrixXd rate;  ///< [N, A] as read, before the scale factor; NaN marks a missing value
  /// Names the source gives the rate columns (a text header's); empty when it gives none.
  std::vector<std::string> axis_names;
  std::map<std::string, Eigen::VectorXd> aux;  ///< by aux name, in the spec's units, length N
  /// A sample rate found in the source (Hz; 0: none) and where it came from, for messages.
  double sample_rate_hz = 0.0;
  std::string sample_rate_from;
  std::string sha256;  ///< of the source file's bytes
  long long size_bytes = 0;
  nlohmann::json options;  ///< the importer's options, for the provenance
  nlohmann::json found;    ///< what the importer found (delimiter, header, shapes, ...)
};

/// An imported recording, ready to be written.
struct ImportedRecording {
  /// The recording; its rate is in data.rate_in_output_unit, in rate_unit.
  RecordingData data;
  units::RateUnit rate_unit = units::RateUnit::kDegPerHour;
  /// Written as the root attribute import_provenance; a caller may add to it (e.g. the program
  /// version) before writing.
  nlohmann::json provenance;
  /// What `run` and `validate` will refuse with their default options (a NaN run longer than
  /// they bridge, a constant axis, too few samples): the file is still written, as the source
  /// says, and these tell the user why a later `run` fails.
  std::vector<std::string> warnings;
  /// Things worth knowing that change nothing (short NaN runs, header names not usable as axes).
  std::vector<std::string> notes;
};

struct ImportResult {
  ImportedRecording recording;  ///< meaningful when ok()
  /// Why the import failed, naming the file (and the line and column for a text file).
  std::string error;
  bool ok() const { return error.empty(); }
};

/// Applies `options` to what an importer read: the scale factor, the axis names, the sample rate
/// (the option's, else the source's), the root attributes, and the provenance. Looks at the data
/// as `run` will with its defaults (NaN runs, constant axes, length) and fills the warnings.
ImportResult FinishImport(ImportSource source, const ImportMetadataOptions& options);

struct ImportWriteResult {
  RecordingInfo info;  ///< what the shared recording checks found in the written file
  std::string error;   ///< why writing or checking failed, naming the file
  bool ok() const { return error.empty(); }
};

/// Writes `recording` to `output_path`, float64, with its provenance. The file is written under
/// a temporary name in the same folder (hdf5::MakeAtomicTempPath), checked there with
/// InspectRecording and only then renamed to `output_path`: a file the checks refuse never
/// appears under the final name (and is removed). After a power cut a checked file may remain
/// under its temporary name, which hdf5::IsAtomicTempName recognises. Takes the HDF5 lock
/// itself. Takes the recording by value: move it in, a day of samples is large.
ImportWriteResult WriteImportedRecording(const std::string& output_path,
                                         ImportedRecording recording);

}  // namespace fogpipe::io
