// Internal: reading and writing HDF5 strings, fixed or variable length, for attributes and
// datasets alike (one piece of code for both).
#pragma once

#include <hdf5.h>

#include <functional>
#include <string>
#include <vector>

namespace fogpipe::hdf5::detail {

/// Reads every string element of an attribute or dataset whose stored type is `file_type` and
/// whose dataspace holds `count` elements. `read(memory_type, buffer)` performs the H5Aread or
/// H5Dread and returns its status. Fixed-length strings are cut at the first NUL and, when
/// space-padded, have trailing spaces removed. Returns false if `read` failed.
bool ReadStrings(hid_t file_type, hid_t space, size_t count,
                 const std::function<herr_t(hid_t, void*)>& read, std::vector<std::string>* out);

/// A variable-length UTF-8 C string type; the caller closes it with H5Tclose.
hid_t MakeVariableStringType();

}  // namespace fogpipe::hdf5::detail
