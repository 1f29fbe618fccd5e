// Internal helpers of pipeline/hdf5 (not part of the public API): turning H5::Exception and
// negative C return codes into hdf5::Error, and RAII for the few raw C identifiers we use.
#pragma once

#include <H5Cpp.h>

#include <string>
#include <utility>

#include "pipeline/hdf5/error.h"

namespace fogpipe::hdf5::detail {

/// Runs `body`; an H5::Exception becomes an hdf5::Error naming file, object and operation.
template <typename Body>
auto Checked(const std::string& file, const std::string& object, const std::string& operation,
             Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const H5::Exception& e) {
    throw Error(file, object, operation, e.getDetailMsg(), CurrentErrorStack());
  }
}

/// Throws hdf5::Error when a C API call returned a negative value; returns the value otherwise.
template <typename T>
T CheckC(T status, const std::string& file, const std::string& object,
         const std::string& operation) {
  if (status < 0) throw Error(file, object, operation, "", CurrentErrorStack());
  return status;
}

/// Closes an H5::DataSet or H5::Group without printing. H5Dclose / H5Gclose release the
/// identifier even when they fail (a full disk when HDF5 flushes), so the C++ object's own
/// destructor then finds nothing to close; left to it, each failure would be printed to stderr.
/// The failure itself is reported once, by the file's flush or close.
template <typename T>
void CloseQuietly(T* object) {
  try {
    object->close();
  } catch (const H5::Exception&) {
  }
}

/// Owns one C identifier and closes it with the matching H5*close.
class ScopedId {
 public:
  using Closer = herr_t (*)(hid_t);
  ScopedId(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  ScopedId(const ScopedId&) = delete;
  ScopedId& operator=(const ScopedId&) = delete;
  ScopedId(ScopedId&& other) noexcept : id_(std::exchange(other.id_, -1)), closer_(other.closer_) {}
  ~ScopedId() {
    if (id_ >= 0) closer_(id_);
  }
  hid_t get() const { return id_; }

 private:
  hid_t id_;
  Closer closer_;
};

/// Wraps a freshly created C identifier in its C++ class (H5::Group, H5::DataSet) so that the
/// C++ object is its only owner. The 1.10 constructors from an existing id increment the
/// reference count; the creator's reference is dropped here.
template <typename T>
T Adopt(hid_t created) {
  T object(created);
  if (H5Iget_ref(created) > 1) H5Idec_ref(created);
  return object;
}

/// "/a" + "b" -> "/a/b"; "/" + "b" -> "/b"; an absolute `name` is returned as it is.
inline std::string JoinPath(const std::string& parent, const std::string& name) {
  if (!name.empty() && name.front() == '/') return name;
  if (parent.empty() || parent == "/") return "/" + name;
  return parent + "/" + name;
}

}  // namespace fogpipe::hdf5::detail
