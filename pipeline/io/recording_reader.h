// Reader of gyro recordings, input contract v1.1 (schemas/README.md, "Recording contract v1.1";
// schemas/recording-v1.json).
//
// Accepts every file that follows the contract: /rate [N] or [N, A], float32 or float64 (or, v1.1,
// integer counts with a `scale_factor`, returned as counts times the factor), any
// chunking or compression HDF5 can decode, `units` deg/h, deg/s or rad/s, optional `axes`,
// optional /aux/<name> [N] channels with `units`, optional root attributes. Anything else in the
// file is ignored. Reads one column at a time by hyperslabs of a bounded number of rows (aligned
// to the chunk rows so that each chunk is inflated once per column), never the [N, A] matrix.
//
// Every problem is a RecordingError whose message names the file and the problem and whose
// kind() is one of error_kind::* (recording_error.h).
//
// Threads: see pipeline/hdf5/hdf5_lock.h. The free functions taking a path lock the HDF5 mutex
// themselves; RecordingReader holds an open file and requires the caller to hold LockHdf5() for
// its whole lifetime.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/common/units.h"
#include "pipeline/hdf5/file.h"
#include "pipeline/io/missing_samples.h"
#include "pipeline/io/recording_error.h"
#include "pipeline/io/repeated_samples.h"

namespace fogpipe::io {

struct AuxChannelInfo {
  std::string name;           ///< "temperature" for /aux/temperature
  std::string units;          ///< as written, e.g. "degC"
  std::string dtype;          ///< "float32", "float64", or an integer type ("int16", "uint32", ...)
  double scale_factor = 1.0;  ///< units per count of an integer channel (contract v1.1); 1 else
};

/// Metadata of one recording (nothing but attributes and shapes is read).
struct RecordingInfo {
  std::string path;
  long long samples = 0;         ///< N
  int axis_count = 0;            ///< A (1 for a [N] dataset)
  bool two_dimensional = false;  ///< /rate is [N, A] (also when A == 1)
  /// From the `axes` attribute; without it "axis0", "axis1", ... (valid HDF5 group names).
  std::vector<std::string> axis_names;
  bool axis_names_from_file = false;
  std::string rate_units;  ///< as written: "deg/h", "deg/s" or "rad/s"
  units::RateUnit rate_unit = units::RateUnit::kRadPerSecond;
  std::string rate_dtype;  ///< "float32", "float64", or an integer type ("int16", "uint32", ...)
  /// Units per count of an integer /rate (its `scale_factor`, contract v1.1); 1 for floats. The
  /// reader returns counts times this factor.
  double rate_scale_factor = 1.0;
  std::vector<unsigned long long> rate_chunk;  ///< chunk shape; empty when contiguous
  double sample_rate_hz = 0.0;                 ///< > 0 and finite
  std::optional<std::string> start_time_utc;
  std::optional<std::string> instrument;
  std::optional<std::string> serial;
  std::optional<double> latitude_deg;
  std::vector<AuxChannelInfo> aux;  ///< sorted by name
  long long file_size_bytes = 0;

  double duration_s() const { return static_cast<double>(samples) / sample_rate_hz; }
};

/// What a read accepts. Defaults suit a quick look; the pipeline passes what its analysis needs.
struct ReadOptions {
  /// Longest run of NaN samples bridged by linear interpolation (missing_samples.h); a longer
  /// run is an error (kind nan_gap_too_long). 0 refuses every NaN.
  long long max_nan_gap_samples = 10;
  /// Fewer samples than this is an error (kind too_few_samples). The default 64 still gives an
  /// octave Allan grid of 6 points (m = 1..32, m <= N/2); the pipeline asks for what it needs.
  long long min_samples = 64;
  /// A column whose (bridged) values are all equal is an error (kind constant_signal): its Allan
  /// variance is zero at every tau and no noise term exists. Not applied to aux channels.
  bool reject_constant = true;
  /// Rows per hyperslab read (rounded to a multiple of the chunk rows): bounds the buffer that
  /// HDF5 fills per call; the returned vector still holds the whole column.
  long long block_rows = 1 << 16;

  bool IsValid(std::string* error) const;
};

/// What a read found and repaired.
struct ReadReport {
  BridgeReport nan;
  RepeatedRunReport repeats;  ///< the longest run of one value, in the column's own units
  long long blocks_read = 0;  ///< hyperslab reads issued
};

/// The column of `axis` in `info`, given by name (an entry of axis_names) or by decimal index.
/// Throws RecordingError (unknown_axis) naming the axes there are.
int AxisIndex(const RecordingInfo& info, const std::string& axis);
/// The value of --axis that selects every axis of a recording (allan, compare).
inline constexpr const char* kAllAxes = "all";
/// The columns `axis` selects: every one for kAllAxes (unless the file names an axis "all"),
/// otherwise AxisIndex's one. Throws RecordingError as AxisIndex.
std::vector<int> SelectAxes(const RecordingInfo& info, const std::string& axis);

/// An open recording whose metadata passed every contract check. Caller holds LockHdf5().
class RecordingReader {
 public:
  /// Opens read-only and checks the metadata (throws RecordingError).
  explicit RecordingReader(const std::string& path);

  const RecordingInfo& info() const { return info_; }
  /// The column of `axis`, given by name (an entry of axis_names) or by decimal index.
  int AxisIndex(const std::string& axis) const;
  /// One axis converted to rad/s, NaN runs bridged, checked for length and constancy.
  Eigen::VectorXd ReadAxisRadPerSecond(int axis, const ReadOptions& options = {},
                                       ReadReport* report = nullptr) const;
  Eigen::VectorXd ReadAxisRadPerSecond(const std::string& axis, const ReadOptions& options = {},
                                       ReadReport* report = nullptr) const;
  /// One axis in the file's own unit (info().rate_units), NaN runs bridged.
  Eigen::VectorXd ReadAxisNative(int axis, const ReadOptions& options = {},
                                 ReadReport* report = nullptr) const;
  /// The aux channel /aux/<name> in its own units (info().aux[i].units), NaN runs bridged.
  Eigen::VectorXd ReadAux(const std::string& name, const ReadOptions& options = {},
                          ReadReport* report = nullptr) const;

 private:
  /// Reads column `column` of `dataset` block by block, multiplies it by `scale` (the units per
  /// count found when the recording was inspected; 1 for floats) and bridges NaNs.
  Eigen::VectorXd ReadColumn(const hdf5::Dataset& dataset, int column, double scale,
                             const std::string& what, const ReadOptions& options,
                             bool reject_constant, ReadReport* report) const;

  hdf5::File file_;
  RecordingInfo info_;
};

/// A valid axis name (of the `axes` attribute) is usable as an HDF5 group name and in a CLI
/// argument: not empty, not "." or "..", no '/' and no NUL.
bool IsValidAxisName(const std::string& name);

/// Refuses a dataset whose samples live outside the file (virtual datasets, external raw
/// storage), one declared but never written (wholly or in part: chunks missing), and one that
/// declares more than a file of `file_size_bytes` can hold. `values` is the declared element
/// count, `element_bytes` the stored size. Throws RecordingError. Caller holds LockHdf5().
void CheckDatasetStorage(const hdf5::Dataset& dataset, unsigned long long values,
                         std::size_t element_bytes, long long file_size_bytes);

/// What `fogpipe info` shows of a recording: samples, rate and duration, the axes with their
/// units and storage, the optional attributes and the aux channels.
std::string FormatRecordingSummary(const RecordingInfo& info);

/// Opens any HDF5 file read-only after the checks every reader of fogpipe files needs, each with
/// its RecordingError kind: missing_file, unreadable_file, empty_file, not_hdf5, truncated_file,
/// corrupt_file. Caller holds LockHdf5().
hdf5::File OpenHdf5ReadOnly(const std::string& path);

/// One axis in rad/s (takes the HDF5 lock). `axis` is a name or a decimal index.
Eigen::VectorXd ReadAxisRadPerSecond(const std::string& path, const std::string& axis,
                                     const ReadOptions& options = {}, ReadReport* report = nullptr);
/// One aux channel in its own units (takes the HDF5 lock).
Eigen::VectorXd ReadAux(const std::string& path, const std::string& name,
                        const ReadOptions& options = {}, ReadReport* report = nullptr);

}  // namespace fogpipe::io
