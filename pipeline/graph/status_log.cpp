#include "pipeline/graph/status_log.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
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
  // Absolute, so that a later `merge` from another folder finds the same input.
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(outcome.file, ec);
  line["file"] = ec ? outcome.file : absolute.lexically_normal().string();
  line["output"] = outcome.output;
  line["axes"] = outcome.axes;
  line["status"] = ToString(outcome.status);
  line["seconds"] = outcome.seconds;
  line["message"] = outcome.message;
  // Invalid UTF-8 in a path must not throw: replace it.
  return line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

StatusLog::StatusLog(const std::string& path) {
  if (path.empty()) {
    discard_ = true;
    return;
  }
  // O_NONBLOCK: a FIFO planted at the log's name would otherwise block the open until a reader
  // comes; it, a device or a second hard link to some other file is refused like a symlink.
  const int fd = ::open(path.c_str(),
                        O_WRONLY | O_APPEND | O_CREAT | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK, 0644);
  if (fd < 0) {
    problem_ = errno == ELOOP   ? "it is a symbolic link; refused"
               : errno == ENXIO ? "it is a FIFO; refused"
                                : std::strerror(errno);
    return;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    problem_ = "it is not a regular file; refused";
  } else if (st.st_nlink > 1) {
    problem_ = "it has another hard link, to a file elsewhere; refused";
  } else if (::fcntl(fd, F_SETFL, O_WRONLY | O_APPEND) != 0) {
    problem_ = std::strerror(errno);
  }
  if (!problem_.empty()) {
    ::close(fd);
    return;
  }
  fd_ = fd;
}

StatusLog::~StatusLog() {
  if (fd_ >= 0) ::close(fd_);
}

int StatusLog::Append(const FileOutcome& outcome) {
  const std::string line = ToJsonLine(outcome) + "\n";
  std::lock_guard<std::mutex> lock(mutex_);
  if (discard_) return 0;
  if (fd_ < 0) return EBADF;
  // With O_APPEND the kernel places one write at the end at once. An exclusive flock across the
  // write keeps the line whole also where one write(2) is cut short (a signal, a filesystem that
  // does not append atomically, such as NFS) and the rest needs a second call.
  while (::flock(fd_, LOCK_EX) != 0 && errno == EINTR) {
  }
  const off_t before = ::lseek(fd_, 0, SEEK_END);
  size_t done = 0;
  int error = 0;
  while (done < line.size()) {
    const ssize_t written = ::write(fd_, line.data() + done, line.size() - done);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      error = written < 0 ? errno : EIO;
      break;
    }
    done += static_cast<size_t>(written);
  }
  // A line cut by a full disk is taken back: the log holds whole lines only.
  if (error != 0 && done > 0 && before >= 0) {
    while (::ftruncate(fd_, before) != 0 && errno == EINTR) {
    }
  }
  ::flock(fd_, LOCK_UN);
  return error;
}

}  // namespace fogpipe::graph
