// Writes one results file (fogpipe-results-v2, schemas/results-v2.md) per recording: provenance,
// then per axis preprocessing, decomposition, models, kalman, signals and allan groups.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "algorithms/allan/noise_fit.h"
#include "algorithms/method/method.h"
#include "pipeline/hdf5/group.h"
#include "pipeline/io/recording_reader.h"

namespace fogpipe::io {

/// How IMF-sized arrays (IMFs, residue, filtered components) are stored.
enum class ImfStorage { kFloat64, kFloat32, kNone };
/// "float64", "float32", "none".
const char* ToString(ImfStorage storage);
bool ParseImfStorage(const std::string& text, ImfStorage* storage);

struct ResultsOptions {
  /// IMFs and residue: float32 (default; relative rounding 6e-8, half the size of float64),
  /// float64 (exact) or none (per-IMF metadata, models and the reconstruction are still stored).
  /// Only the stored copy is rounded: the models, filters and Allan tables are computed from the
  /// doubles before storage.
  ImfStorage imf_storage = ImfStorage::kFloat32;
  /// Also store each component's Kalman output ([N, K+1], same storage as the IMFs).
  bool store_filtered_imfs = false;
  /// The large N-sample datasets (IMFs, residue, filtered components, method 1 and 2) are chunked
  /// one column per chunk, byte-shuffled and deflated at `deflate_level` (0: uncompressed), the
  /// chunks compressed in parallel (column_datasets.h, whose ColumnStorage defaults give the rest
  /// of the layout). Lossless whatever the level.
  int deflate_level = 1;
};

/// Where the numbers came from. Stored in /provenance.
struct Provenance {
  std::string fogpipe_version;
  std::string git_commit;
  std::string config_toml;    ///< The effective configuration, TOML.
  std::string config_sha256;  ///< SHA-256 of config_toml: the rerun key.
  std::string input_path;
  long long input_size_bytes = 0;
  std::string input_sha256;
  std::string start_time_utc;  ///< ISO 8601, e.g. 2026-11-21T06:30:00Z
  std::string end_time_utc;
  int threads = 0;
  std::vector<std::string> stage_names;  ///< e.g. read, preprocess_emd, models, allan, write
  std::vector<double> stage_seconds;     ///< Summed over the file's axes, s.
  /// `run --model FILE` (all empty without it): the model file (absolute path), the SHA-256 of
  /// its bytes, and the deterministic terms subtracted before the EMD, comma-separated.
  std::string model_path;
  std::string model_sha256;
  std::string model_compensated_terms;
};

/// One analysed axis.
struct AxisResults {
  std::string name;  ///< group name under /axes
  int index = 0;     ///< column in /rate
  double sample_rate_hz = 0.0;
  std::string input_units;  ///< units of /rate in the recording
  ReadReport read;          ///< what the reader found: NaN runs bridged, the longest repeated run
  const method::MethodResult* result = nullptr;
  /// Where the IMFs, the residue and the filtered components are when the method streamed them
  /// (method::StreamOptions::store); null: in *result. The writer releases each column once it
  /// has read it.
  method::ComponentStore* store = nullptr;
};

/// Writes `final_path` through a temporary file in the same folder renamed when complete
/// (hdf5::AtomicOutputFile). Takes the HDF5 lock itself. Throws hdf5::Error or
/// std::runtime_error; nothing is left under final_path on failure.
void WriteResultsFile(const std::filesystem::path& final_path, const Provenance& provenance,
                      const std::vector<AxisResults>& axes, const ResultsOptions& options);

/// The noise terms of a fit and their assessment in `noise` as the results file lays them out
/// (allan/<signal>/noise/ in schemas/results-v2.md): one table `terms`, a row per term Q ... R
/// with its value and standard error in engineer's units, z, significance, upper limit,
/// read-off, reliability, unit and reason; chi2, dof, p_value and misfit_tau_ranges as
/// attributes of `noise`.
void WriteNoiseTable(hdf5::Group& noise, const allan::NoiseFitResult& fit);

/// The same numbers as one scalar dataset each (Q, Q_std_error, ..., chi2, dof, p_value, per term
/// T_z, T_significant, T_upper_limit, T_readoff, T_reliable, attribute T_reason): the layout of
/// the model history's steps (compare/step_NNN/allan/noise, schemas/model-history.md).
void WriteNoiseTermDatasets(hdf5::Group& noise, const allan::NoiseFitResult& fit);

/// Current UTC time, ISO 8601 with seconds ("2026-11-21T06:30:00Z").
std::string UtcNowIso8601();

}  // namespace fogpipe::io
