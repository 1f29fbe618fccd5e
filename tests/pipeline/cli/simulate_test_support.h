// Helpers shared by the simulate tests: a private scratch folder and small HDF5 readers written
// directly on the HDF5 C++ API (independent of fogpipe's own reader).
#pragma once

#include <H5Cpp.h>
#include <unistd.h>

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace fogpipe::testing {

/// A fresh folder under the system temp dir, removed when the object dies.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag)
      : path_(std::filesystem::temp_directory_path() /
              ("fogpipe-" + tag + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::string ReadStringAttribute(const H5::H5Object& object, const std::string& name) {
  H5::Attribute attribute = object.openAttribute(name);
  std::string value;
  attribute.read(attribute.getStrType(), value);
  return value;
}

inline double ReadDoubleAttribute(const H5::H5Object& object, const std::string& name) {
  double value = 0.0;
  object.openAttribute(name).read(H5::PredType::NATIVE_DOUBLE, &value);
  return value;
}

inline std::vector<hsize_t> Dims(const H5::DataSet& dataset) {
  H5::DataSpace space = dataset.getSpace();
  std::vector<hsize_t> dims(static_cast<size_t>(space.getSimpleExtentNdims()));
  space.getSimpleExtentDims(dims.data());
  return dims;
}

/// The whole dataset as float64, row-major.
inline Eigen::VectorXd ReadAll(const H5::DataSet& dataset) {
  hsize_t total = 1;
  for (hsize_t d : Dims(dataset)) total *= d;
  Eigen::VectorXd values(static_cast<Eigen::Index>(total));
  dataset.read(values.data(), H5::PredType::NATIVE_DOUBLE);
  return values;
}

}  // namespace fogpipe::testing
