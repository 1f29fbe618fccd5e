#include "pipeline/graph/status_log.h"

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

StatusLog::StatusLog(const std::string& path) : file_(std::fopen(path.c_str(), "a")) {}

StatusLog::~StatusLog() {
  if (file_ != nullptr) std::fclose(file_);
}

void StatusLog::Append(const FileOutcome& outcome) {
  const std::string line = ToJsonLine(outcome) + "\n";
  std::lock_guard<std::mutex> lock(mutex_);
  if (file_ == nullptr) return;
  std::fwrite(line.data(), 1, line.size(), file_);
  std::fflush(file_);
}

}  // namespace fogpipe::graph
