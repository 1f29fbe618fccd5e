// Writes gyro recordings in the input contract v1 (schemas/README.md, "Recording contract v1") and
// the simulator's truth sidecar. Used by `fogpipe simulate`; any tool that produces recordings may
// use it.
//
// Files are written atomically through pipeline/hdf5 (AtomicOutputFile: "<name>.tmp-<pid>-<n>" in
// the target folder, then renamed), so a reader never sees a partial recording. HDF5 errors become
// std::runtime_error naming the file. WriteRecording takes the process-wide HDF5 lock itself: do
// not call it while holding hdf5::LockHdf5().
#pragma once

#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/common/units.h"
#include "algorithms/simulation/gyro_simulator.h"

namespace fogpipe::io {

enum class SampleType { kFloat64, kFloat32 };
const char* ToString(SampleType type);

/// An aux channel, e.g. {"temperature", samples, "degC"}.
struct AuxChannel {
  Eigen::VectorXd samples;
  std::string units;
};

/// One recording in memory, SI inside.
struct RecordingData {
  double sample_rate_hz = 0.0;
  /// [N, A]: one column per axis, rad/s. Converted to `rate_unit` on writing.
  Eigen::MatrixXd rate_rad_s;
  /// Axis names (length A); written as the `axes` attribute when A > 1 or when not empty.
  std::vector<std::string> axes;
  std::string start_time_utc;  ///< ISO 8601; omitted when empty
  std::string instrument;      ///< omitted when empty
  std::string serial;          ///< omitted when empty
  std::optional<double> latitude_deg;
  std::map<std::string, AuxChannel> aux;  ///< written as /aux/<name>, float64
  /// [N, A] already in RecordingWriterOptions::rate_unit, written as it is; used instead of
  /// rate_rad_s when not empty. An importer keeps the source's numbers to the last bit this way,
  /// where a round trip through rad/s would change the last bit of some of them.
  Eigen::MatrixXd rate_in_output_unit;
  /// Further string attributes of the root group (e.g. where an imported recording came from).
  /// The contract's own root attributes and `fogpipe_format` cannot be set here.
  std::map<std::string, std::string> extra_root_attributes;
};

struct RecordingWriterOptions {
  units::RateUnit rate_unit = units::RateUnit::kDegPerHour;
  SampleType sample_type = SampleType::kFloat64;
  /// A single axis is written as a 1-D [N] dataset (the common case); false writes [N, 1].
  bool squeeze_single_axis = true;
  /// Chunk length in samples (clamped to N); recordings are always chunked.
  /// 65536 x 8 B = 512 KiB per chunk for one axis.
  std::size_t chunk_samples = 65536;
  /// gzip level 0-9 (0: no compression); the byte shuffle filter is applied before it.
  int deflate_level = 4;

  bool IsValid(std::string* error) const;
};

/// Writes `data` to `path` atomically. Throws std::invalid_argument for inconsistent data and
/// std::runtime_error (naming the file and the HDF5 message) when writing fails; a failed write
/// leaves no file behind, neither the target nor the temporary.
void WriteRecording(const std::string& path, const RecordingData& data,
                    const RecordingWriterOptions& options = {});

/// The truth of one simulated recording as JSON, in engineer's units with the unit in every key
/// name (e.g. "n_deg_sqrt_h") and the SI values alongside ("n_rad_sqrt_s"). One entry per axis.
nlohmann::json SimulationTruthToJson(const std::vector<simulation::SimulationTruth>& axes,
                                     const std::vector<std::string>& axis_names);

/// The true rate (rad/s) of a simulated recording rebuilt from its truth JSON: the rate-table input
/// ("input_rate_text", parsed by simulation::ParseRateProfile) plus the Earth-rate projection,
/// sampled at t_k = k / sample_rate_hz for num_samples samples. For metrics against the truth
/// (sweeps); the analysis proper never reads the truth. Throws std::runtime_error when a field is
/// missing or malformed.
Eigen::VectorXd TrueRateFromTruth(const nlohmann::json& truth);

/// Writes `json` (indented) to `path` atomically; throws std::runtime_error on failure.
void WriteJsonFile(const std::string& path, const nlohmann::json& json);

/// "<recording>.truth.json": where the sidecar of a recording goes.
std::string TruthSidecarPath(const std::string& recording_path);

}  // namespace fogpipe::io
