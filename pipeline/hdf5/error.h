// fogpipe::hdf5::Error: every failure of an HDF5 call made through pipeline/hdf5, with the file,
// the object path, the operation and the text of the HDF5 error stack (walked with H5Ewalk2).
#pragma once

#include <stdexcept>
#include <string>

namespace fogpipe::hdf5 {

class Error : public std::runtime_error {
 public:
  /// `hdf5_stack` is the text returned by CurrentErrorStack() at the point of failure.
  Error(std::string file, std::string object, std::string operation, std::string detail,
        std::string hdf5_stack);

  const std::string& file() const { return file_; }
  const std::string& object() const { return object_; }
  const std::string& operation() const { return operation_; }
  /// One line per stack entry, innermost (where HDF5 noticed the problem) last; may be empty.
  const std::string& hdf5_stack() const { return hdf5_stack_; }
  /// What the innermost stack entry says, i.e. what the library found wrong ("truncated file:
  /// eof = ...", "inflate() failed [Data filters / ...]"); the whole message if there is no stack.
  std::string innermost_message() const;

 private:
  std::string file_, object_, operation_, hdf5_stack_;
};

/// The calling thread's current HDF5 error stack as text, one line per entry
/// ("H5Fopen(): unable to open file: truncated file: eof = 96, ... [File accessibility / ...]").
/// Does not clear the stack. The caller must hold LockHdf5().
std::string CurrentErrorStack();

}  // namespace fogpipe::hdf5
