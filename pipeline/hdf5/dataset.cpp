#include "pipeline/hdf5/dataset.h"

#include <utility>

#include "pipeline/hdf5/detail.h"
#include "pipeline/hdf5/string_io.h"

namespace fogpipe::hdf5 {
namespace {

using detail::CheckC;
using detail::ScopedId;

}  // namespace

bool DatasetOptions::IsValid(std::string* error) const {
  if (deflate_level < 0 || deflate_level > 9) {
    if (error) *error = "deflate_level must be in 0..9, got " + std::to_string(deflate_level);
    return false;
  }
  return true;
}

Dataset::~Dataset() { detail::CloseQuietly(&dataset_); }

Dataset::Dataset(std::string file_path, std::string path, H5::DataSet dataset)
    : Object(std::move(file_path), std::move(path)), dataset_(std::move(dataset)) {}

std::vector<hsize_t> Dataset::dims() const {
  ScopedId space(CheckC(H5Dget_space(id()), file_path(), path(), "get dataspace"), H5Sclose);
  const int rank = CheckC(H5Sget_simple_extent_ndims(space.get()), file_path(), path(), "get rank");
  std::vector<hsize_t> extent(rank);
  if (rank > 0) H5Sget_simple_extent_dims(space.get(), extent.data(), nullptr);
  return extent;
}

hsize_t Dataset::size() const {
  hsize_t n = 1;
  for (hsize_t d : dims()) n *= d;
  return n;
}

TypeInfo Dataset::type() const {
  ScopedId type(CheckC(H5Dget_type(id()), file_path(), path(), "get datatype"), H5Tclose);
  return DescribeType(type.get());
}

std::vector<hsize_t> Dataset::chunk_dims() const {
  ScopedId plist(CheckC(H5Dget_create_plist(id()), file_path(), path(), "get creation properties"),
                 H5Pclose);
  if (H5Pget_layout(plist.get()) != H5D_CHUNKED) return {};
  std::vector<hsize_t> chunk(dims().size());
  CheckC(H5Pget_chunk(plist.get(), static_cast<int>(chunk.size()), chunk.data()), file_path(),
         path(), "get chunk shape");
  return chunk;
}

std::vector<double> Dataset::ReadDoubles() const {
  const TypeInfo t = type();
  if (t.type_class != TypeClass::kFloat && t.type_class != TypeClass::kInteger) {
    throw Error(file_path(), path(), "read numbers",
                std::string("dataset is of type class ") + ToString(t.type_class), "");
  }
  std::vector<double> values(size());
  if (!values.empty()) {
    CheckC(H5Dread(id(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
           file_path(), path(), "read numbers");
  }
  return values;
}

std::vector<long long> Dataset::ReadInt64s() const {
  if (type().type_class != TypeClass::kInteger) {
    throw Error(file_path(), path(), "read integers", "dataset is not of an integer type", "");
  }
  std::vector<long long> values(size());
  if (!values.empty()) {
    CheckC(H5Dread(id(), H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
           file_path(), path(), "read integers");
  }
  return values;
}

std::vector<std::string> Dataset::ReadStrings() const {
  if (type().type_class != TypeClass::kString) {
    throw Error(file_path(), path(), "read strings", "dataset is not of a string type", "");
  }
  ScopedId file_type(CheckC(H5Dget_type(id()), file_path(), path(), "read strings"), H5Tclose);
  ScopedId space(CheckC(H5Dget_space(id()), file_path(), path(), "read strings"), H5Sclose);
  std::vector<std::string> values;
  const hid_t dataset_id = id();
  const bool ok = detail::ReadStrings(
      file_type.get(), space.get(), size(),
      [dataset_id](hid_t memory_type, void* buffer) {
        return H5Dread(dataset_id, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer);
      },
      &values);
  if (!ok) throw Error(file_path(), path(), "read strings", "", CurrentErrorStack());
  return values;
}

namespace {

/// The member type of `field` in the compound `file_type`; throws naming what is wrong.
ScopedId FieldType(hid_t file_type, const std::string& field, const std::string& file,
                   const std::string& object, const std::string& operation) {
  if (H5Tget_class(file_type) != H5T_COMPOUND) {
    throw Error(file, object, operation, "dataset is not a table (compound type)", "");
  }
  const int index = H5Tget_member_index(file_type, field.c_str());
  if (index < 0) throw Error(file, object, operation, "table has no field '" + field + "'", "");
  return ScopedId(
      CheckC(H5Tget_member_type(file_type, static_cast<unsigned>(index)), file, object, operation),
      H5Tclose);
}

/// A compound memory type holding only `field`, of `member_type`: HDF5 then reads that field
/// alone, converting it (e.g. int64 to double) on the way.
ScopedId SingleFieldType(const std::string& field, hid_t member_type) {
  ScopedId type(H5Tcreate(H5T_COMPOUND, H5Tget_size(member_type)), H5Tclose);
  H5Tinsert(type.get(), field.c_str(), 0, member_type);
  return type;
}

}  // namespace

std::vector<std::pair<std::string, TypeInfo>> Dataset::Fields() const {
  ScopedId file_type(CheckC(H5Dget_type(id()), file_path(), path(), "list fields"), H5Tclose);
  if (H5Tget_class(file_type.get()) != H5T_COMPOUND) {
    throw Error(file_path(), path(), "list fields", "dataset is not a table (compound type)", "");
  }
  std::vector<std::pair<std::string, TypeInfo>> fields;
  const int n = CheckC(H5Tget_nmembers(file_type.get()), file_path(), path(), "list fields");
  for (unsigned i = 0; i < static_cast<unsigned>(n); ++i) {
    char* name = H5Tget_member_name(file_type.get(), i);
    ScopedId member(
        CheckC(H5Tget_member_type(file_type.get(), i), file_path(), path(), "list fields"),
        H5Tclose);
    fields.emplace_back(name ? name : "", DescribeType(member.get()));
    H5free_memory(name);
  }
  return fields;
}

std::vector<double> Dataset::ReadFieldDoubles(const std::string& field) const {
  const std::string operation = "read field " + field;
  ScopedId file_type(CheckC(H5Dget_type(id()), file_path(), path(), operation), H5Tclose);
  const ScopedId member = FieldType(file_type.get(), field, file_path(), path(), operation);
  const H5T_class_t c = H5Tget_class(member.get());
  if (c != H5T_FLOAT && c != H5T_INTEGER) {
    throw Error(file_path(), path(), operation, "field is not numeric", "");
  }
  const ScopedId memory_type = SingleFieldType(field, H5T_NATIVE_DOUBLE);
  std::vector<double> values(size());
  if (!values.empty()) {
    CheckC(H5Dread(id(), memory_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
           file_path(), path(), operation);
  }
  return values;
}

std::vector<long long> Dataset::ReadFieldInt64s(const std::string& field) const {
  const std::string operation = "read field " + field;
  ScopedId file_type(CheckC(H5Dget_type(id()), file_path(), path(), operation), H5Tclose);
  const ScopedId member = FieldType(file_type.get(), field, file_path(), path(), operation);
  if (H5Tget_class(member.get()) != H5T_INTEGER) {
    throw Error(file_path(), path(), operation, "field is not of an integer type", "");
  }
  const ScopedId memory_type = SingleFieldType(field, H5T_NATIVE_LLONG);
  std::vector<long long> values(size());
  if (!values.empty()) {
    CheckC(H5Dread(id(), memory_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
           file_path(), path(), operation);
  }
  return values;
}

std::vector<std::string> Dataset::ReadFieldStrings(const std::string& field) const {
  const std::string operation = "read field " + field;
  ScopedId file_type(CheckC(H5Dget_type(id()), file_path(), path(), operation), H5Tclose);
  const ScopedId member = FieldType(file_type.get(), field, file_path(), path(), operation);
  if (H5Tget_class(member.get()) != H5T_STRING) {
    throw Error(file_path(), path(), operation, "field is not of a string type", "");
  }
  ScopedId space(CheckC(H5Dget_space(id()), file_path(), path(), operation), H5Sclose);
  std::vector<std::string> values;
  const hid_t dataset_id = id();
  const bool ok = detail::ReadStrings(
      member.get(), space.get(), size(),
      [dataset_id, &field](hid_t string_type, void* buffer) {
        // The string type read inside a one-field compound has the same memory layout.
        const ScopedId memory_type = SingleFieldType(field, string_type);
        return H5Dread(dataset_id, memory_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer);
      },
      &values);
  if (!ok) throw Error(file_path(), path(), operation, "", CurrentErrorStack());
  return values;
}

void Dataset::TransferBlock(const std::vector<hsize_t>& start, const std::vector<hsize_t>& count,
                            hid_t memory_type, void* buffer, bool write,
                            const std::string& operation) const {
  hsize_t elements = 1;
  for (hsize_t c : count) elements *= c;
  if (elements == 0) return;
  ScopedId file_space(CheckC(H5Dget_space(id()), file_path(), path(), operation), H5Sclose);
  CheckC(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                             nullptr),
         file_path(), path(), operation);
  ScopedId memory_space(H5Screate_simple(1, &elements, nullptr), H5Sclose);
  if (write) {
    CheckC(H5Dwrite(id(), memory_type, memory_space.get(), file_space.get(), H5P_DEFAULT, buffer),
           file_path(), path(), operation);
  } else {
    CheckC(H5Dread(id(), memory_type, memory_space.get(), file_space.get(), H5P_DEFAULT, buffer),
           file_path(), path(), operation);
  }
}

void Dataset::ReadColumn(hsize_t column, hsize_t row0, hsize_t rows, double* out) const {
  const std::vector<hsize_t> extent = dims();
  const std::string operation = "read column " + std::to_string(column) + " rows [" +
                                std::to_string(row0) + ", " + std::to_string(row0 + rows) + ")";
  const bool fits =
      (extent.size() == 1 && column == 0) || (extent.size() == 2 && column < extent[1]);
  if (!fits || row0 + rows > extent[0]) {
    throw Error(file_path(), path(), operation, "outside the dataset's extent", "");
  }
  if (extent.size() == 1) {
    TransferBlock({row0}, {rows}, H5T_NATIVE_DOUBLE, out, false, operation);
  } else {
    TransferBlock({row0, column}, {rows, 1}, H5T_NATIVE_DOUBLE, out, false, operation);
  }
}

std::vector<hsize_t> Dataset::RowBlockStart(hsize_t row0, hsize_t rows, std::vector<hsize_t>* count,
                                            const std::string& operation) const {
  *count = dims();
  if (count->empty() || row0 + rows > (*count)[0]) {
    throw Error(file_path(), path(), operation, "outside the dataset's extent", "");
  }
  std::vector<hsize_t> start(count->size(), 0);
  start[0] = row0;
  (*count)[0] = rows;
  return start;
}

void Dataset::ReadRows(hsize_t row0, hsize_t rows, double* out) const {
  const std::string operation =
      "read rows [" + std::to_string(row0) + ", " + std::to_string(row0 + rows) + ")";
  std::vector<hsize_t> count;
  const std::vector<hsize_t> start = RowBlockStart(row0, rows, &count, operation);
  TransferBlock(start, count, H5T_NATIVE_DOUBLE, out, false, operation);
}

void Dataset::WriteRows(hsize_t row0, hsize_t rows, const double* data) {
  const std::string operation =
      "write rows [" + std::to_string(row0) + ", " + std::to_string(row0 + rows) + ")";
  std::vector<hsize_t> count;
  const std::vector<hsize_t> start = RowBlockStart(row0, rows, &count, operation);
  TransferBlock(start, count, H5T_NATIVE_DOUBLE, const_cast<double*>(data), true, operation);
}

}  // namespace fogpipe::hdf5
