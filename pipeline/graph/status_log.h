// OUTDIR/status.jsonl: one JSON object per line and per input file, appended and flushed line by
// line, so that a run killed at any point leaves only complete lines behind.
//   {"file": "...", "output": "...", "axes": 3, "status": "ok", "seconds": 12.5, "message": ""}
// status is "ok", "failed" or "skipped" (output present with the same configuration hash).
#pragma once

#include <cstdio>
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
  std::string message;   ///< Why it failed, or what was skipped; empty when ok.
};

class StatusLog {
 public:
  /// Opens `path` for appending (creates it). Check ok() before use.
  explicit StatusLog(const std::string& path);
  ~StatusLog();
  StatusLog(const StatusLog&) = delete;
  StatusLog& operator=(const StatusLog&) = delete;

  bool ok() const { return file_ != nullptr; }
  /// Appends one line and flushes it to the OS (fflush + fsync are not needed for a killed
  /// process; the kernel keeps written data). Thread-safe.
  void Append(const FileOutcome& outcome);

 private:
  std::mutex mutex_;
  std::FILE* file_ = nullptr;
};

/// The JSON line for one outcome (no trailing newline).
std::string ToJsonLine(const FileOutcome& outcome);

}  // namespace fogpipe::graph
