// OUTDIR/status.jsonl: one JSON object per line and per input file, each line written under an
// exclusive flock on a descriptor opened with O_APPEND, so that a run killed at any point leaves
// only complete lines and concurrent runs appending to one log never interleave within a line,
// whatever its length. A symlink, FIFO, device or hard link planted in its place is refused,
// never written through.
//   {"file": "...", "output": "...", "axes": 3, "status": "ok", "seconds": 12.5, "message": ""}
// status is "ok", "failed" or "skipped" (output present with the same configuration hash).
#pragma once

#include <mutex>
#include <string>

namespace fogpipe::graph {

enum class FileStatus { kOk, kFailed, kSkipped };
const char* ToString(FileStatus status);

struct FileOutcome {
  std::string file;    ///< Input path.
  std::string output;  ///< Results file written or found (empty when failed).
  int axes = 0;        ///< Axes analysed (or found in the results file when skipped).
  FileStatus status = FileStatus::kFailed;
  double seconds = 0.0;  ///< Wall time spent on this file in this run.
  /// Why it failed, or what was skipped; when ok, empty or the data's warnings ("warning: axis
  /// x: ...", a flagged run of one repeated value: pipeline/io/repeated_samples.h).
  std::string message;
};

class StatusLog {
 public:
  /// Opens `path` for appending (creates it); "" gives a log that discards every line (a dry
  /// run). Check ok() before use.
  explicit StatusLog(const std::string& path);
  ~StatusLog();
  StatusLog(const StatusLog&) = delete;
  StatusLog& operator=(const StatusLog&) = delete;

  bool ok() const { return fd_ >= 0 || discard_; }
  /// Why it could not be opened ("" when ok()).
  const std::string& problem() const { return problem_; }
  /// Appends one line under an exclusive flock (fsync is not needed for a killed process; the
  /// kernel keeps written data). Thread-safe, and safe between processes. Returns 0, or the
  /// errno of a failed write (ENOSPC, say), after which the log holds no part of the line.
  int Append(const FileOutcome& outcome);

 private:
  std::mutex mutex_;
  int fd_ = -1;
  bool discard_ = false;
  std::string problem_;
};

/// The JSON line for one outcome (no trailing newline).
std::string ToJsonLine(const FileOutcome& outcome);

}  // namespace fogpipe::graph
