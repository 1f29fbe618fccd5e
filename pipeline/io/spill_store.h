// A method::ComponentStore on disk: the IMFs (and filtered components) of an axis wait in a
// scratch file between the decomposition and their filters, and until the results writer reads
// them back one column at a time. Memory then no longer grows with the number of IMFs: a day at
// 1 kHz has about 25 IMFs of 8.64e7 samples, 17 GB of float64 that no 24 GB node could hold
// beside the rest.
//
// The file has no name (O_TMPFILE; on a file system without it, a named file unlinked at once),
// so it vanishes when closed, and when the process is killed: nothing is left behind. The
// kernel's page cache holds what fits in free memory, so short recordings never wait for the
// disk. Columns are stored as the float64 bytes they are (pwrite, pread): read back bit-identical.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include "algorithms/method/component_store.h"

namespace fogpipe::io {

/// What the scratch file throws: its folder and the system's message ("No space left on device").
class ScratchError : public std::runtime_error {
 public:
  ScratchError(const std::string& folder, const std::string& what)
      : std::runtime_error("scratch file in " + folder + ": " + what), folder_(folder) {}
  const std::string& folder() const { return folder_; }

 private:
  std::string folder_;
};

class SpillStore : public method::ComponentStore {
 public:
  /// A scratch file in `folder`. Throws ScratchError when it cannot be created.
  explicit SpillStore(const std::string& folder);
  ~SpillStore() override;
  SpillStore(const SpillStore&) = delete;
  SpillStore& operator=(const SpillStore&) = delete;

  /// Throw ScratchError (e.g. the disk is full: "No space left on device").
  void Put(Kind kind, int k, const Eigen::VectorXd& x) override;
  void Get(Kind kind, int k, Eigen::VectorXd* x) const override;
  bool Has(Kind kind, int k) const override;
  /// Punches the column's bytes out of the file (where the file system can), so its disk space
  /// and page-cache pages are free at once: the results writer releases each column as it reads
  /// it, so the scratch file shrinks while the results file grows, and the output device needs
  /// about the larger of the two instead of their sum (docs/performance.md, "Disk space").
  void Release(Kind kind, int k) override;

  /// Bytes written so far.
  std::uint64_t bytes() const;
  /// Bytes the file system holds for the file now (fstat's st_blocks), 0 if it cannot tell.
  std::uint64_t allocated_bytes() const;

 private:
  struct Extent {
    std::uint64_t offset = 0;
    Eigen::Index samples = 0;
  };
  std::string folder_;
  int fd_ = -1;
  mutable std::mutex mutex_;
  std::uint64_t end_ = 0;
  std::map<std::pair<Kind, int>, Extent> extents_;
};

}  // namespace fogpipe::io
