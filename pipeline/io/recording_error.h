// fogpipe::io::RecordingError: a recording that fogpipe cannot analyse, with a short machine
// `kind` (for status.jsonl, tests and scripts) and a message for people that names the file and
// the problem.
#pragma once

#include <stdexcept>
#include <string>

namespace fogpipe::io {

/// The kinds a RecordingError can have. Stable strings: scripts match on them.
namespace error_kind {
inline constexpr const char* kMissingFile = "missing_file";        ///< no such file
inline constexpr const char* kUnreadableFile = "unreadable_file";  ///< e.g. no read permission
inline constexpr const char* kEmptyFile = "empty_file";            ///< zero bytes
inline constexpr const char* kNotHdf5 = "not_hdf5";                ///< no HDF5 signature
inline constexpr const char* kTruncatedFile =
    "truncated_file";                                        ///< shorter than its superblock says
inline constexpr const char* kCorruptFile = "corrupt_file";  ///< HDF5 cannot open or read it
inline constexpr const char* kMissingDataset = "missing_dataset";  ///< no /rate
inline constexpr const char* kMissingAttribute = "missing_attribute";
inline constexpr const char* kWrongType = "wrong_type";    ///< e.g. integer /rate, string rate
inline constexpr const char* kWrongRank = "wrong_rank";    ///< /rate not [N] or [N, A]
inline constexpr const char* kWrongShape = "wrong_shape";  ///< [N, 0]
inline constexpr const char* kUnknownUnits = "unknown_units";
inline constexpr const char* kBadSampleRate = "bad_sample_rate";  ///< <= 0, NaN or Inf
/// an integer dataset's `scale_factor` is 0, NaN or Inf (contract v1.1)
inline constexpr const char* kBadScaleFactor = "bad_scale_factor";
inline constexpr const char* kBadAxes = "bad_axes";  ///< `axes` of wrong length, empty or repeated
inline constexpr const char* kUnknownAxis = "unknown_axis";  ///< asked for an axis not in the file
inline constexpr const char* kAuxLengthMismatch = "aux_length_mismatch";
inline constexpr const char* kUnknownAux = "unknown_aux";  ///< asked for an aux channel not there
inline constexpr const char* kUnsupportedCompression = "unsupported_compression";
inline constexpr const char* kNanGapTooLong = "nan_gap_too_long";
inline constexpr const char* kNonFiniteValue = "non_finite_value";  ///< +-Inf in /rate
inline constexpr const char* kTooFewSamples = "too_few_samples";
inline constexpr const char* kConstantSignal = "constant_signal";
inline constexpr const char* kNotRegularFile = "not_regular_file";  ///< a FIFO, device, socket
/// External links, virtual datasets or external raw storage: data from outside the file.
inline constexpr const char* kExternalData = "external_data";
inline constexpr const char* kUnwrittenDataset = "unwritten_dataset";  ///< declared, never written
/// Declared dims the file cannot hold, or beyond what fogpipe accepts (recording_limits.h).
inline constexpr const char* kImplausibleShape = "implausible_shape";
inline constexpr const char* kExtremeMagnitude =
    "extreme_magnitude";  ///< |x| beyond 1e+-60 (recording_limits.h)
/// Passed the reader's checks but not the recording-v1 layout (schemas/recording-v1.json).
inline constexpr const char* kLayoutViolation = "layout_violation";
/// The isolated inspection or read (isolated_call.h) crashed, hung or ran out of memory.
inline constexpr const char* kReaderCrashed = "reader_crashed";
inline constexpr const char* kReaderTimeout = "reader_timeout";
inline constexpr const char* kReaderOutOfMemory = "reader_out_of_memory";
inline constexpr const char* kInterrupted = "interrupted";
}  // namespace error_kind

class RecordingError : public std::runtime_error {
 public:
  /// what() is "<file>: <problem>".
  RecordingError(std::string kind, std::string file, std::string problem);

  const std::string& kind() const { return kind_; }
  const std::string& file() const { return file_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string kind_, file_, problem_;
};

}  // namespace fogpipe::io
