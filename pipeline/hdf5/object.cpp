#include "pipeline/hdf5/object.h"

#include <utility>

#include "pipeline/hdf5/detail.h"
#include "pipeline/hdf5/string_io.h"

namespace fogpipe::hdf5 {
namespace {

using detail::CheckC;
using detail::ScopedId;

std::string AttributeOperation(const char* verb, const std::string& name) {
  return std::string(verb) + " attribute '" + name + "'";
}

herr_t CollectName(hid_t, const char* name, const H5A_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}

}  // namespace

const char* ToString(TypeClass type_class) {
  switch (type_class) {
    case TypeClass::kFloat:
      return "float";
    case TypeClass::kInteger:
      return "integer";
    case TypeClass::kString:
      return "string";
    case TypeClass::kCompound:
      return "compound";
    case TypeClass::kOther:
      break;
  }
  return "other";
}

hsize_t AttributeInfo::size() const {
  hsize_t n = 1;
  for (hsize_t d : dims) n *= d;
  return n;
}

TypeInfo DescribeType(hid_t type_id) {
  TypeInfo info;
  switch (H5Tget_class(type_id)) {
    case H5T_FLOAT:
      info.type_class = TypeClass::kFloat;
      break;
    case H5T_INTEGER:
      info.type_class = TypeClass::kInteger;
      break;
    case H5T_STRING:
      info.type_class = TypeClass::kString;
      info.variable_length_string = H5Tis_variable_str(type_id) > 0;
      break;
    case H5T_COMPOUND:
      info.type_class = TypeClass::kCompound;
      break;
    default:
      info.type_class = TypeClass::kOther;
  }
  info.size_bytes = H5Tget_size(type_id);
  return info;
}

Object::Object(std::string file_path, std::string path)
    : file_path_(std::move(file_path)), path_(std::move(path)) {}

bool Object::HasAttribute(const std::string& name) const {
  return CheckC(H5Aexists(id(), name.c_str()), file_path_, path_,
                AttributeOperation("look up", name)) > 0;
}

std::vector<std::string> Object::AttributeNames() const {
  std::vector<std::string> names;
  hsize_t index = 0;
  CheckC(H5Aiterate2(id(), H5_INDEX_NAME, H5_ITER_INC, &index, CollectName, &names), file_path_,
         path_, "list attributes");
  return names;
}

hid_t Object::OpenAttribute(const std::string& name, const std::string& operation) const {
  if (!HasAttribute(name)) {
    throw Error(file_path_, path_, operation, "no attribute named '" + name + "'", "");
  }
  return CheckC(H5Aopen(id(), name.c_str(), H5P_DEFAULT), file_path_, path_, operation);
}

AttributeInfo Object::DescribeAttribute(const std::string& name) const {
  const std::string operation = AttributeOperation("describe", name);
  ScopedId attribute(OpenAttribute(name, operation), H5Aclose);
  ScopedId type(CheckC(H5Aget_type(attribute.get()), file_path_, path_, operation), H5Tclose);
  ScopedId space(CheckC(H5Aget_space(attribute.get()), file_path_, path_, operation), H5Sclose);
  AttributeInfo info;
  info.name = name;
  info.type = DescribeType(type.get());
  const int rank = CheckC(H5Sget_simple_extent_ndims(space.get()), file_path_, path_, operation);
  info.dims.resize(rank);
  if (rank > 0) H5Sget_simple_extent_dims(space.get(), info.dims.data(), nullptr);
  return info;
}

std::vector<double> Object::ReadDoubleArrayAttribute(const std::string& name) const {
  const std::string operation = AttributeOperation("read", name);
  const AttributeInfo info = DescribeAttribute(name);
  if (info.type.type_class != TypeClass::kFloat && info.type.type_class != TypeClass::kInteger) {
    throw Error(file_path_, path_, operation,
                std::string("attribute is of type class ") + ToString(info.type.type_class) +
                    ", expected a number",
                "");
  }
  std::vector<double> values(info.size());
  ScopedId attribute(OpenAttribute(name, operation), H5Aclose);
  if (!values.empty()) {
    CheckC(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, values.data()), file_path_, path_,
           operation);
  }
  return values;
}

double Object::ReadDoubleAttribute(const std::string& name) const {
  const std::vector<double> values = ReadDoubleArrayAttribute(name);
  if (values.size() != 1) {
    throw Error(file_path_, path_, AttributeOperation("read", name),
                "expected one value, found " + std::to_string(values.size()), "");
  }
  return values.front();
}

long long Object::ReadInt64Attribute(const std::string& name) const {
  const std::string operation = AttributeOperation("read", name);
  const AttributeInfo info = DescribeAttribute(name);
  if (info.type.type_class != TypeClass::kInteger || info.size() != 1) {
    throw Error(file_path_, path_, operation, "expected one integer", "");
  }
  long long value = 0;
  ScopedId attribute(OpenAttribute(name, operation), H5Aclose);
  CheckC(H5Aread(attribute.get(), H5T_NATIVE_LLONG, &value), file_path_, path_, operation);
  return value;
}

std::vector<std::string> Object::ReadStringArrayAttribute(const std::string& name) const {
  const std::string operation = AttributeOperation("read", name);
  const AttributeInfo info = DescribeAttribute(name);
  if (info.type.type_class != TypeClass::kString) {
    throw Error(file_path_, path_, operation,
                std::string("attribute is of type class ") + ToString(info.type.type_class) +
                    ", expected a string",
                "");
  }
  ScopedId attribute(OpenAttribute(name, operation), H5Aclose);
  ScopedId type(CheckC(H5Aget_type(attribute.get()), file_path_, path_, operation), H5Tclose);
  ScopedId space(CheckC(H5Aget_space(attribute.get()), file_path_, path_, operation), H5Sclose);
  std::vector<std::string> values;
  const hid_t attribute_id = attribute.get();
  const bool ok = detail::ReadStrings(
      type.get(), space.get(), info.size(),
      [attribute_id](hid_t memory_type, void* buffer) {
        return H5Aread(attribute_id, memory_type, buffer);
      },
      &values);
  if (!ok) throw Error(file_path_, path_, operation, "", CurrentErrorStack());
  return values;
}

std::string Object::ReadStringAttribute(const std::string& name) const {
  const std::vector<std::string> values = ReadStringArrayAttribute(name);
  if (values.size() != 1) {
    throw Error(file_path_, path_, AttributeOperation("read", name),
                "expected one string, found " + std::to_string(values.size()), "");
  }
  return values.front();
}

void Object::WriteAttribute(const std::string& name, hid_t file_type, hid_t memory_type,
                            const std::vector<hsize_t>& dims, const void* data) {
  const std::string operation = AttributeOperation("write", name);
  if (HasAttribute(name)) {
    CheckC(H5Adelete(id(), name.c_str()), file_path_, path_, operation);
  }
  ScopedId space(dims.empty()
                     ? H5Screate(H5S_SCALAR)
                     : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                 H5Sclose);
  CheckC(space.get(), file_path_, path_, operation);
  ScopedId attribute(
      CheckC(H5Acreate2(id(), name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
             file_path_, path_, operation),
      H5Aclose);
  CheckC(H5Awrite(attribute.get(), memory_type, data), file_path_, path_, operation);
}

void Object::WriteDoubleAttribute(const std::string& name, double value) {
  WriteAttribute(name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, &value);
}

void Object::WriteInt64Attribute(const std::string& name, long long value) {
  WriteAttribute(name, H5T_STD_I64LE, H5T_NATIVE_LLONG, {}, &value);
}

void Object::WriteDoubleArrayAttribute(const std::string& name, const std::vector<double>& values) {
  WriteAttribute(name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {values.size()}, values.data());
}

void Object::WriteInt64ArrayAttribute(const std::string& name,
                                      const std::vector<long long>& values) {
  WriteAttribute(name, H5T_STD_I64LE, H5T_NATIVE_LLONG, {values.size()}, values.data());
}

void Object::WriteStringAttribute(const std::string& name, const std::string& value) {
  ScopedId type(detail::MakeVariableStringType(), H5Tclose);
  const char* pointer = value.c_str();
  WriteAttribute(name, type.get(), type.get(), {}, &pointer);
}

void Object::WriteStringArrayAttribute(const std::string& name,
                                       const std::vector<std::string>& values) {
  ScopedId type(detail::MakeVariableStringType(), H5Tclose);
  std::vector<const char*> pointers;
  pointers.reserve(values.size());
  for (const std::string& v : values) pointers.push_back(v.c_str());
  WriteAttribute(name, type.get(), type.get(), {values.size()}, pointers.data());
}

}  // namespace fogpipe::hdf5
