#include "pipeline/hdf5/hdf5_lock.h"

#include <H5Cpp.h>

namespace fogpipe::hdf5 {
namespace {

std::mutex& Hdf5Mutex() {
  static std::mutex mutex;  // function-local static: initialised on first use, thread-safe (C++11)
  return mutex;
}

}  // namespace

std::unique_lock<std::mutex> LockHdf5() { return std::unique_lock<std::mutex>(Hdf5Mutex()); }

void SilenceHdf5ErrorPrinter() {
  auto lock = LockHdf5();
  H5::Exception::dontPrint();
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

}  // namespace fogpipe::hdf5
