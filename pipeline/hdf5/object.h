// fogpipe::hdf5::Object: what groups and datasets share: a file path and an object path (for
// messages), and attributes (scalars and 1-D arrays of float64, int64 and strings).
//
// Every method requires the caller to hold LockHdf5() (see hdf5_lock.h) and throws hdf5::Error.
#pragma once

#include <hdf5.h>

#include <string>
#include <vector>

#include "pipeline/hdf5/error.h"

namespace fogpipe::hdf5 {

/// The class of an HDF5 datatype, as far as fogpipe cares.
enum class TypeClass { kFloat, kInteger, kString, kCompound, kOther };

/// "float", "integer", "string", "compound", "other" (the spelling used by schema files).
const char* ToString(TypeClass type_class);

struct TypeInfo {
  TypeClass type_class = TypeClass::kOther;
  /// Size of one element in bytes (for a variable-length string: the size of the pointer).
  size_t size_bytes = 0;
  bool variable_length_string = false;
};

/// Shape and type of one attribute; `dims` is empty for a scalar.
struct AttributeInfo {
  std::string name;
  TypeInfo type;
  std::vector<hsize_t> dims;
  /// Number of elements (1 for a scalar).
  hsize_t size() const;
};

/// Describes an HDF5 datatype identifier.
TypeInfo DescribeType(hid_t type_id);

class Object {
 public:
  virtual ~Object() = default;

  /// The file this object lives in (as opened), for messages.
  const std::string& file_path() const { return file_path_; }
  /// The absolute path of the object inside the file, e.g. "/rate".
  const std::string& path() const { return path_; }

  bool HasAttribute(const std::string& name) const;
  /// Attribute names in creation/name order as HDF5 lists them.
  std::vector<std::string> AttributeNames() const;
  AttributeInfo DescribeAttribute(const std::string& name) const;

  /// A numeric (float or integer) attribute with exactly one element, converted to double.
  double ReadDoubleAttribute(const std::string& name) const;
  /// An integer attribute with exactly one element.
  long long ReadInt64Attribute(const std::string& name) const;
  /// A string attribute (fixed or variable length) with exactly one element.
  std::string ReadStringAttribute(const std::string& name) const;
  /// A string attribute of any number of elements (fixed or variable length).
  std::vector<std::string> ReadStringArrayAttribute(const std::string& name) const;
  /// A numeric attribute of any number of elements, converted to double.
  std::vector<double> ReadDoubleArrayAttribute(const std::string& name) const;

  // Writers replace an existing attribute of the same name. Strings are variable-length UTF-8
  // (what h5py reads as str); numbers are stored as IEEE float64 / int64 little-endian.
  void WriteDoubleAttribute(const std::string& name, double value);
  void WriteInt64Attribute(const std::string& name, long long value);
  void WriteStringAttribute(const std::string& name, const std::string& value);
  void WriteDoubleArrayAttribute(const std::string& name, const std::vector<double>& values);
  void WriteInt64ArrayAttribute(const std::string& name, const std::vector<long long>& values);
  void WriteStringArrayAttribute(const std::string& name, const std::vector<std::string>& values);

  /// The HDF5 identifier (valid while this object lives). For code in pipeline/ that needs a C call
  /// the wrappers do not offer; still under LockHdf5().
  virtual hid_t id() const = 0;

 protected:
  Object(std::string file_path, std::string path);

 private:
  /// Opens attribute `name` (throws hdf5::Error naming it when absent).
  hid_t OpenAttribute(const std::string& name, const std::string& operation) const;
  void WriteAttribute(const std::string& name, hid_t file_type, hid_t memory_type,
                      const std::vector<hsize_t>& dims, const void* data);

  std::string file_path_;
  std::string path_;
};

}  // namespace fogpipe::hdf5
