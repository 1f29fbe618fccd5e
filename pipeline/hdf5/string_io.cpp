#include "pipeline/hdf5/string_io.h"

#include <cstring>

#include "pipeline/hdf5/detail.h"

namespace fogpipe::hdf5::detail {

hid_t MakeVariableStringType() {
  hid_t type = H5Tcopy(H5T_C_S1);
  if (type < 0) return type;
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  return type;
}

bool ReadStrings(hid_t file_type, hid_t space, size_t count,
                 const std::function<herr_t(hid_t, void*)>& read, std::vector<std::string>* out) {
  out->clear();
  const H5T_cset_t cset = H5Tget_cset(file_type);
  if (H5Tis_variable_str(file_type) > 0) {
    ScopedId memory_type(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(memory_type.get(), H5T_VARIABLE);
    H5Tset_cset(memory_type.get(), cset);
    std::vector<char*> pointers(count, nullptr);
    if (read(memory_type.get(), pointers.data()) < 0) return false;
    for (char* p : pointers) out->emplace_back(p ? p : "");
    // Frees the strings the library allocated (H5Dvlen_reclaim works for attributes as well).
    H5Dvlen_reclaim(memory_type.get(), space, H5P_DEFAULT, pointers.data());
    return true;
  }
  const size_t size = H5Tget_size(file_type);
  ScopedId memory_type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(memory_type.get(), size);
  H5Tset_cset(memory_type.get(), cset);
  const H5T_str_t pad = H5Tget_strpad(file_type);
  H5Tset_strpad(memory_type.get(), pad);
  std::vector<char> buffer(count * size + 1, '\0');
  if (read(memory_type.get(), buffer.data()) < 0) return false;
  for (size_t i = 0; i < count; ++i) {
    const char* begin = buffer.data() + i * size;
    size_t length = strnlen(begin, size);
    if (pad == H5T_STR_SPACEPAD) {
      while (length > 0 && begin[length - 1] == ' ') --length;
    }
    out->emplace_back(begin, length);
  }
  return true;
}

}  // namespace fogpipe::hdf5::detail
