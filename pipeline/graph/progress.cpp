#include "pipeline/graph/progress.h"

#include <unistd.h>

#include <cmath>
#include <utility>

namespace fogpipe::graph {

std::string FormatDuration(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char text[32];
  if (s >= 3600) {
    std::snprintf(text, sizeof(text), "%ldh%02ldm", s / 3600, (s % 3600) / 60);
  } else if (s >= 60) {
    std::snprintf(text, sizeof(text), "%ldm%02lds", s / 60, s % 60);
  } else {
    std::snprintf(text, sizeof(text), "%lds", s);
  }
  return text;
}

Progress::Progress(int total, std::FILE* stream, bool redraw)
    : total_(total), stream_(stream), redraw_(redraw) {}

void Progress::FileDone(const std::string& file, const std::string& status,
                        const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!message.empty()) {
    std::fprintf(stream_, "%sfogpipe: %s: %s\n", redraw_ ? "\r\033[K" : "", status.c_str(),
                 message.c_str());
  }
  ++done_;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double eta = done_ > 0 ? elapsed / done_ * (total_ - done_) : 0.0;
  std::fprintf(stream_, "%s[%d/%d] %s %s  elapsed %s  ETA %s%s", redraw_ ? "\r\033[K" : "", done_,
               total_, status.c_str(), file.c_str(), FormatDuration(elapsed).c_str(),
               FormatDuration(eta).c_str(), redraw_ ? "" : "\n");
  std::fflush(stream_);
}

void Progress::Finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (redraw_ && done_ > 0) std::fputc('\n', stream_);
  std::fflush(stream_);
}

WorkProgress::WorkProgress(std::string what, std::FILE* stream, bool redraw)
    : what_(std::move(what)), stream_(stream), redraw_(redraw) {}

void WorkProgress::Step(const std::string& step) {
  std::lock_guard<std::mutex> lock(mutex_);
  step_ = step;
  stage_ = stage_total_ = stage_done_ = 0;
  Print(true);
}

ForEach WorkProgress::Counting(ForEach inner) {
  return [this, inner = std::move(inner)](int n, const std::function<void(int)>& body) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++stage_;
      stage_total_ = n;
      stage_done_ = 0;
      stage_start_ = std::chrono::steady_clock::now();
    }
    const auto counted = [this, &body](int i) {
      body(i);
      std::lock_guard<std::mutex> lock(mutex_);
      ++stage_done_;
      // A redrawn line also shows each stage's end, which costs nothing on a terminal.
      Print(redraw_ && stage_done_ == stage_total_);
    };
    if (inner) {
      inner(n, counted);
    } else {
      for (int i = 0; i < n; ++i) counted(i);
    }
  };
}

void WorkProgress::Print(bool force) {
  if (stream_ == nullptr) return;
  const auto now = std::chrono::steady_clock::now();
  // A redrawn line may change often; a log line stays readable when rare.
  const double interval_s = redraw_ ? 0.2 : 10.0;
  if (!force && std::chrono::duration<double>(now - last_print_).count() < interval_s) return;
  last_print_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  std::string stage, eta;
  if (stage_total_ > 0) {
    const double in_stage = std::chrono::duration<double>(now - stage_start_).count();
    stage = ", stage " + std::to_string(stage_) + " [" + std::to_string(stage_done_) + "/" +
            std::to_string(stage_total_) + "]";
    if (stage_done_ > 0)
      eta = "  ETA " + FormatDuration(in_stage / stage_done_ * (stage_total_ - stage_done_));
  }
  std::fprintf(stream_, "%s%s: %s%s  elapsed %s%s%s", redraw_ ? "\r\033[K" : "", what_.c_str(),
               step_.c_str(), stage.c_str(), FormatDuration(elapsed).c_str(), eta.c_str(),
               redraw_ ? "" : "\n");
  std::fflush(stream_);
  printed_ = true;
}

void WorkProgress::Finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (stream_ == nullptr) return;
  if (redraw_ && printed_) std::fputc('\n', stream_);
  printed_ = false;
  std::fflush(stream_);
}

std::FILE* ProgressStream(bool requested, bool* redraw) {
  *redraw = ::isatty(STDERR_FILENO) == 1;
  return requested || *redraw ? stderr : nullptr;
}

}  // namespace fogpipe::graph
