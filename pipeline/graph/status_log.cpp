#include "pipeline/graph/status_log.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <nlohmann/json.hpp>

namespace fogpipe::graph {

const char* ToString(FileStatus status) {
  switch (status) {
    case FileStatus::kOk:
      return "ok";
    case FileStatus::kFailed:
      return "failed";
    case FileStatus::kSkipped:
      return "skipped";
  }
  return "failed";
}

std::string ToJsonLine(const FileOutcome& outcome) {
  nlohmann::ordered_json line;
  line["file"] = outcome.file;
  line["output"] = outcome.output;
  line["axes"] = outcome.axes;
  line["status"] = ToString(outcome.status);
  line["seconds"] = outcome.seconds;
  line["message"] = outcome.message;
  // Invalid UTF-8 in a path must not throw: replace it.
  return line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

StatusLog::StatusLog(const std::string& path)
    : fd_(::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644)) {}

StatusLog::~StatusLog() {
  if (fd_ >= 0) ::close(fd_);
}

void StatusLog::Append(const FileOutcome& outcome) {
  const std::string line = ToJsonLine(outcome) + "\n";
  std::lock_guard<std::mutex> lock(mutex_);
  if (fd_ < 0) return;
  // One call: with O_APPEND the kernel places the whole line at the end at once.
  ssize_t written = -1;
  do {
    written = ::write(fd_, line.data(), line.size());
  } while (written < 0 && errno == EINTR);
}

}  // namespace fogpipe::graph
