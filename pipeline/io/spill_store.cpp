#include "pipeline/io/spill_store.h"

#include <fcntl.h>
#include <linux/falloc.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace fogpipe::io {
namespace {

ScratchError SpillError(const std::string& folder, const std::string& what, int error) {
  return ScratchError(folder, what + ": " + std::strerror(error));
}

// O_TMPFILE where the file system offers it; else a unique name, unlinked at once.
int OpenScratch(const std::string& folder) {
#ifdef O_TMPFILE
  const int unnamed = ::open(folder.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (unnamed >= 0) return unnamed;
  if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL)
    throw SpillError(folder, "cannot create", errno);
#endif
  // mkstemp: a random name no other process (another node on a shared file system) can hold.
  std::string path = folder + "/.fogpipe-scratch-XXXXXX";
  const int fd = ::mkostemp(path.data(), O_CLOEXEC);
  if (fd < 0) throw SpillError(folder, "cannot create", errno);
  if (::unlink(path.c_str()) != 0) {
    const int error = errno;
    ::close(fd);
    throw SpillError(folder, "cannot unlink " + path, error);
  }
  return fd;
}

}  // namespace

SpillStore::SpillStore(const std::string& folder)
    : folder_(folder.empty() ? "." : folder), fd_(OpenScratch(folder_)) {}

SpillStore::~SpillStore() {
  if (fd_ >= 0) ::close(fd_);
}

void SpillStore::Put(Kind kind, int k, const Eigen::VectorXd& x) {
  const std::uint64_t size = static_cast<std::uint64_t>(x.size()) * sizeof(double);
  std::uint64_t offset = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    offset = end_;
    end_ += size;
  }
  const char* data = reinterpret_cast<const char*>(x.data());
  for (std::uint64_t done = 0; done < size;) {
    const ssize_t n = ::pwrite(fd_, data + done, size - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : EIO;  // 0 bytes written: no errno of its own
      throw SpillError(folder_, "writing " + std::to_string(size) + " bytes", error);
    }
    done += static_cast<std::uint64_t>(n);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  extents_[{kind, k}] = Extent{offset, x.size()};
}

void SpillStore::Get(Kind kind, int k, Eigen::VectorXd* x) const {
  Extent extent;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = extents_.find({kind, k});
    if (it == extents_.end()) {
      throw ScratchError(folder_, "column " + std::to_string(k) + " was never stored");
    }
    extent = it->second;
  }
  x->resize(extent.samples);
  const std::uint64_t size = static_cast<std::uint64_t>(extent.samples) * sizeof(double);
  char* data = reinterpret_cast<char*>(x->data());
  for (std::uint64_t done = 0; done < size;) {
    const ssize_t n =
        ::pread(fd_, data + done, size - done, static_cast<off_t>(extent.offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      throw SpillError(folder_, "reading back", error);
    }
    if (n == 0) throw ScratchError(folder_, "truncated");
    done += static_cast<std::uint64_t>(n);
  }
}

void SpillStore::Release(Kind kind, int k) {
  Extent extent;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = extents_.find({kind, k});
    if (it == extents_.end()) return;
    extent = it->second;
    extents_.erase(it);
  }
  // A file system without hole punching keeps the bytes until the file is closed: nothing is
  // lost but the early release, so the result is not checked.
  const off_t size = static_cast<off_t>(extent.samples) * static_cast<off_t>(sizeof(double));
  if (size > 0) {
    [[maybe_unused]] const int ignored = ::fallocate(
        fd_, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, static_cast<off_t>(extent.offset), size);
  }
}

bool SpillStore::Has(Kind kind, int k) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return extents_.count({kind, k}) > 0;
}

std::uint64_t SpillStore::allocated_bytes() const {
  struct stat status {};
  if (::fstat(fd_, &status) != 0) return 0;
  return static_cast<std::uint64_t>(status.st_blocks) * 512;  // st_blocks counts 512-byte units
}

std::uint64_t SpillStore::bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return end_;
}

}  // namespace fogpipe::io
