// fogpipe::hdf5::AtomicOutputFile: an output HDF5 file that appears under its final name only
// when complete.
//
// The file is written as "<final>.tmp-<pid>-<n>" in the SAME folder (rename(2) is atomic only
// within one file system), and Commit() flushes, closes, fsyncs and renames it to <final>. A
// destructor without Commit() (an exception, an error, a stop request) closes and deletes the
// temporary file. After SIGKILL a temporary file may remain: its name never matches "*.h5", and
// IsAtomicTempName() lets a rerun recognise and remove it. A reader therefore never sees a
// partial file under a final name.
//
// Requires the caller to hold LockHdf5() from construction until CloseFile() (or destruction).
// After CloseFile() only POSIX calls remain: Commit()'s fsync and rename, which can take a while
// on a large file, and the destructor need no lock, so other threads' HDF5 work goes on.
#pragma once

#include <filesystem>
#include <string>

#include "pipeline/hdf5/file.h"

namespace fogpipe::hdf5 {

class AtomicOutputFile {
 public:
  /// Creates the temporary file next to `final_path` (whose folder must exist). An existing
  /// file at final_path is left alone until Commit() replaces it.
  explicit AtomicOutputFile(std::filesystem::path final_path);
  ~AtomicOutputFile();
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

  File& file() { return file_; }
  Group Root() const { return file_.Root(); }
  const std::filesystem::path& final_path() const { return final_path_; }
  const std::filesystem::path& temp_path() const { return temp_path_; }
  bool committed() const { return committed_; }

  /// Flushes and closes the HDF5 file (every wrapper taken from file() becomes invalid). Needs
  /// the lock. Throws hdf5::Error; the temporary file is then removed by the destructor.
  void CloseFile();

  /// CloseFile() if not done, then fsyncs and renames the temporary file to final_path,
  /// replacing any file there. Throws hdf5::Error or std::filesystem::filesystem_error; on
  /// failure the temporary file is removed. Needs the lock only if CloseFile() was not called.
  void Commit();

 private:
  std::filesystem::path final_path_;
  std::filesystem::path temp_path_;
  File file_;
  bool committed_ = false;
};

/// Removes every temporary file of this process that is neither committed nor removed yet: for a
/// stop that ends the process without running destructors (graph/interrupt.h). Thread-safe.
void RemoveUncommittedTempFiles();

/// The temporary name used for `final_path` by this process: "<final>.tmp-<pid>-<n>", n counting
/// up per process so that concurrent writers never collide.
std::filesystem::path MakeAtomicTempPath(const std::filesystem::path& final_path);

/// True when `path`'s file name has the form "<something>.tmp-<digits>-<digits>".
bool IsAtomicTempName(const std::filesystem::path& path);

/// True when a temporary file may still be written by a live process: its writer's pid (from the
/// name) is alive on this machine, or another process holds a lock on it (HDF5 1.10 flock()s
/// every file it opens for writing; a killed writer's lock is gone with it). A cleaner removes
/// only temporary files for which this is false, so overlapping runs never delete each other's.
bool AtomicTempInUse(const std::filesystem::path& path);

}  // namespace fogpipe::hdf5
