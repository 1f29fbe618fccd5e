// The one process-wide lock for the HDF5 C++ API.
//
// Debian's libhdf5 (1.10.8) is built thread-safe for the C API only: the C++ wrappers
// (H5::H5File, H5::DataSet, ...) keep reference counts and error state that are not protected.
// fogpipe therefore runs EVERY H5:: call, including the destructors of H5:: objects, under this
// one mutex, and never lets an HDF5 object (or a fogpipe::hdf5 wrapper, which owns one) cross
// threads: create it, use it and destroy it in the same thread while holding the lock.
//
//   {
//     auto lock = fogpipe::hdf5::LockHdf5();      // declared first, so released last
//     auto file = fogpipe::hdf5::File::OpenReadOnly(path);
//     ...                                          // every wrapper object dies inside this scope
//   }
//
// The wrappers in pipeline/hdf5 and the classes in pipeline/io that hold HDF5 objects expect the
// caller to hold the lock. Free functions that take a path and return plain data (e.g.
// fogpipe::io::InspectRecording(path)) take the lock themselves: do NOT call them while holding it
// (std::mutex is not recursive).
#pragma once

#include <mutex>

namespace fogpipe::hdf5 {

/// Locks the process-wide HDF5 mutex for the lifetime of the returned lock.
std::unique_lock<std::mutex> LockHdf5();

/// Turns off HDF5's automatic printing of error stacks to stderr for the calling thread
/// (H5::Exception::dontPrint() and H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); the error stack
/// is per thread in a thread-safe build). fogpipe reports the stack inside hdf5::Error instead.
/// Call it once in every thread that does I/O; it is cheap and idempotent. Takes the lock itself.
void SilenceHdf5ErrorPrinter();

}  // namespace fogpipe::hdf5
