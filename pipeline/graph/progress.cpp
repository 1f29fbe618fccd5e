#include "pipeline/graph/progress.h"

#include <cmath>

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

}  // namespace fogpipe::graph
