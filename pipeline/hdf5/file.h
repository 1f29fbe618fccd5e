// fogpipe::hdf5::File: opening inputs read-only and creating outputs.
//
// Requires the caller to hold LockHdf5() for the whole lifetime of the File and of every Group or
// Dataset taken from it; throws hdf5::Error. Opening or creating a file also turns off HDF5's
// automatic error printing for the calling thread (as SilenceHdf5ErrorPrinter() does).
#pragma once

#include <H5Cpp.h>

#include <memory>
#include <string>

#include "pipeline/hdf5/group.h"

namespace fogpipe::hdf5 {

class File {
 public:
  /// Opens an existing file with H5F_ACC_RDONLY: fogpipe never modifies its inputs.
  static File OpenReadOnly(const std::string& path);
  /// Creates a new file. With `overwrite` false an existing file is an error (H5F_ACC_EXCL).
  /// Files created here use the strong close degree: Close() closes every object still open in
  /// them and writes everything out, so that a closed file is complete on disk.
  static File Create(const std::string& path, bool overwrite = false);

  const std::string& path() const { return path_; }
  bool is_open() const { return file_ != nullptr; }
  /// The root group "/".
  Group Root() const;
  /// Writes buffered data and metadata to the file (H5Fflush, global scope).
  void Flush();
  /// Closes the file; a no-op when already closed. Wrappers taken from a created file are
  /// invalid afterwards. When HDF5 fails to close it (a write error while flushing: ENOSPC),
  /// throws and abandons the file: never closed again (AbandonedFiles()).
  void Close();
  hid_t id() const;

 private:
  File(std::string path, std::unique_ptr<H5::H5File> file);

  std::string path_;
  std::shared_ptr<H5::H5File> file_;
};

/// How many files Close() abandoned. HDF5 1.10 crashes when such a file is closed a second time,
/// including by its own clean-up at exit (H5close): a process with abandoned files must end by
/// _Exit after flushing its streams, not by returning from main.
int AbandonedFiles();

}  // namespace fogpipe::hdf5
