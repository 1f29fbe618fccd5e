#include "pipeline/hdf5/atomic_output_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <mutex>
#include <set>
#include <string>
#include <system_error>

namespace fogpipe::hdf5 {
namespace {

/// fsync(2) on a file or folder; durability of the rename after a power cut (POSIX leaves it to
/// the file system otherwise). Failures to sync are not fatal: the data is still correct.
void SyncPath(const std::filesystem::path& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

bool AllDigits(const std::string& text) {
  if (text.empty()) return false;
  for (char c : text) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

// The temporary files of this process not yet committed or removed, for a stop that cannot wait
// (RemoveUncommittedTempFiles). Never destroyed: a detached thread may use them during exit.
std::mutex& RegistryMutex() {
  static auto* mutex = new std::mutex;
  return *mutex;
}
std::set<std::string>& Registry() {
  static auto* paths = new std::set<std::string>;
  return *paths;
}
void Register(const std::filesystem::path& path) {
  std::lock_guard<std::mutex> lock(RegistryMutex());
  Registry().insert(path.string());
}
void Unregister(const std::filesystem::path& path) {
  std::lock_guard<std::mutex> lock(RegistryMutex());
  Registry().erase(path.string());
}

}  // namespace

void RemoveUncommittedTempFiles() {
  std::lock_guard<std::mutex> lock(RegistryMutex());
  for (const std::string& path : Registry()) ::unlink(path.c_str());
  Registry().clear();
}

std::filesystem::path MakeAtomicTempPath(const std::filesystem::path& final_path) {
  static std::atomic<unsigned long long> counter{0};
  std::filesystem::path temp = final_path;
  temp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
  return temp;
}

bool IsAtomicTempName(const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  const size_t tag = name.rfind(".tmp-");
  if (tag == std::string::npos || tag == 0) return false;
  const std::string rest = name.substr(tag + 5);
  const size_t dash = rest.find('-');
  if (dash == std::string::npos) return false;
  return AllDigits(rest.substr(0, dash)) && AllDigits(rest.substr(dash + 1));
}

bool AtomicTempInUse(const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  const std::string rest = name.substr(name.rfind(".tmp-") + 5);
  const long pid = std::strtol(rest.c_str(), nullptr, 10);
  if (pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM)) return true;
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return false;
  const bool locked = ::flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);  // releases the probe's own lock
  return locked;
}

namespace {

/// File::Create, removing what it left when it failed: H5Fcreate makes the file before writing
/// its superblock, and on a full device it throws after that, before any destructor of ours
/// could run.
File CreateOrRemove(const std::filesystem::path& path) {
  try {
    return File::Create(path.string(), /*overwrite=*/false);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    throw;
  }
}

}  // namespace

AtomicOutputFile::AtomicOutputFile(std::filesystem::path final_path)
    : final_path_(std::move(final_path)),
      temp_path_(MakeAtomicTempPath(final_path_)),
      file_(CreateOrRemove(temp_path_)) {
  Register(temp_path_);
}

AtomicOutputFile::~AtomicOutputFile() {
  if (committed_) return;
  try {
    file_.Close();  // nothing to do after CloseFile()
  } catch (...) {
    // Nothing useful to report from a destructor; the file is removed below either way.
  }
  std::error_code ignored;
  std::filesystem::remove(temp_path_, ignored);
  Unregister(temp_path_);
}

void AtomicOutputFile::CloseFile() {
  if (!file_.is_open()) return;
  file_.Flush();
  file_.Close();
}

void AtomicOutputFile::Commit() {
  if (committed_) return;
  CloseFile();
  SyncPath(temp_path_, false);
  std::filesystem::rename(temp_path_, final_path_);  // throws filesystem_error; dtor cleans up
  committed_ = true;
  Unregister(temp_path_);
  SyncPath(final_path_.parent_path().empty() ? "." : final_path_.parent_path(), true);
}

}  // namespace fogpipe::hdf5
