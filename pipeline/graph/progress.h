// Progress on stderr: one line per finished file with counts and an ETA. On a terminal the line is
// redrawn in place (carriage return); otherwise (logs, Slurm) each line is printed once.
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace fogpipe::graph {

class Progress {
 public:
  /// `total` files to process (skipped files count as done at once). `redraw` defaults to
  /// isatty(stderr).
  Progress(int total, std::FILE* stream, bool redraw);
  /// Reports one finished file. A non-empty `message` (why it failed) is printed on a line of its
  /// own that is never overwritten. Thread-safe.
  void FileDone(const std::string& file, const std::string& status,
                const std::string& message = "");
  /// Ends the in-place line (prints the newline a redrawn line lacks).
  void Finish();

 private:
  std::mutex mutex_;
  int total_;
  int done_ = 0;
  std::FILE* stream_;
  bool redraw_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// "1h02m", "3m05s", "12s".
std::string FormatDuration(double seconds);

}  // namespace fogpipe::graph
