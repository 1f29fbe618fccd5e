// Progress on stderr: one line per finished file with counts and an ETA (`run`), or per step of
// one long piece of work (`sweep`, `compare`). On a terminal the line is redrawn in place
// (carriage return); otherwise (logs, Slurm) each line is printed once.
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

#include "algorithms/common/for_each.h"

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

/// Progress within one long piece of work: its steps, and the tasks of each parallel stage
/// (a ForEach call) counted as they finish, with the stage's elapsed time and ETA. A step is
/// printed when it starts; task counts at most every 0.2 s on a terminal (and at each stage's
/// end) and every 10 s in a log, so that a log of a long sweep stays short. Nothing is printed with
/// a null stream.
class WorkProgress {
 public:
  /// `what` leads every line, e.g. "sweep rec.h5".
  WorkProgress(std::string what, std::FILE* stream, bool redraw);
  /// Finishes the line if Finish was not called (an early return).
  ~WorkProgress() { Finish(); }
  WorkProgress(const WorkProgress&) = delete;
  WorkProgress& operator=(const WorkProgress&) = delete;
  /// Starts a step, e.g. "axis x: decomposing"; its stages are numbered from 1.
  void Step(const std::string& step);
  /// `inner` with every finished body counted in a new stage of the current step. Thread-safe.
  ForEach Counting(ForEach inner);
  /// Ends the in-place line (once).
  void Finish();

 private:
  void Print(bool force);  // caller holds mutex_

  std::mutex mutex_;
  std::string what_, step_;
  std::FILE* stream_;
  bool redraw_;
  bool printed_ = false;
  int stage_ = 0, stage_total_ = 0, stage_done_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point stage_start_ = start_, last_print_ = start_;
};

/// Where a long command's progress goes, as `run` decides it: stderr when `requested`
/// (`--progress`) or when stderr is a terminal, else nowhere. `*redraw`: stderr is a terminal.
std::FILE* ProgressStream(bool requested, bool* redraw);

/// "1h02m", "3m05s", "12s".
std::string FormatDuration(double seconds);

}  // namespace fogpipe::graph
