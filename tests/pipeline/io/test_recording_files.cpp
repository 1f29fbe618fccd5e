#include "tests/pipeline/io/test_recording_files.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstring>

namespace fogpipe::testing {
namespace {

void Check(long long status, const std::string& what) {
  if (status < 0) {
    ADD_FAILURE() << "HDF5 C API call failed in test fixture: " << what;
    throw std::runtime_error("test fixture: " + what);
  }
}

hid_t VariableString() {
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  return t;
}

}  // namespace

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = std::filesystem::temp_directory_path() /
          ("fogpipe-io-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

RawFile::RawFile(const std::string& path, hsize_t user_block_bytes) {
  hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  if (user_block_bytes > 0) Check(H5Pset_userblock(fcpl, user_block_bytes), "user block");
  file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
  H5Pclose(fcpl);
  Check(file_, "create " + path);
}

RawFile::~RawFile() { Close(); }

void RawFile::Close() {
  if (file_ >= 0) H5Fclose(file_);
  file_ = -1;
}

void RawFile::Dataset(const std::string& path, const std::vector<hsize_t>& dims,
                      const std::vector<double>& values, const Layout& layout) {
  hid_t space = dims.empty()
                    ? H5Screate(H5S_SCALAR)
                    : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  if (!layout.chunk.empty()) {
    Check(H5Pset_chunk(dcpl, static_cast<int>(layout.chunk.size()), layout.chunk.data()), "chunk");
    if (layout.shuffle) H5Pset_shuffle(dcpl);
    if (layout.deflate > 0) H5Pset_deflate(dcpl, layout.deflate);
  }
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t dset = H5Dcreate2(file_, path.c_str(), layout.file_type, space, lcpl, dcpl, H5P_DEFAULT);
  Check(dset, "create dataset " + path);
  if (!values.empty()) {
    Check(H5Dwrite(dset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
          "write " + path);
  }
  H5Dclose(dset);
  H5Pclose(lcpl);
  H5Pclose(dcpl);
  H5Sclose(space);
}

void RawFile::Attribute(const std::string& object, const std::string& name, hid_t file_type,
                        hid_t memory_type, long long count, const void* data) {
  const hsize_t n = static_cast<hsize_t>(count);
  hid_t space = count < 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr);
  hid_t attr = H5Acreate_by_name(file_, object.c_str(), name.c_str(), file_type, space, H5P_DEFAULT,
                                 H5P_DEFAULT, H5P_DEFAULT);
  Check(attr, "attribute " + name);
  Check(H5Awrite(attr, memory_type, data), "write attribute " + name);
  H5Aclose(attr);
  H5Sclose(space);
}

void RawFile::StringAttribute(const std::string& object, const std::string& name,
                              const std::string& value) {
  hid_t type = VariableString();
  const char* p = value.c_str();
  Attribute(object, name, type, type, -1, &p);
  H5Tclose(type);
}

void RawFile::FixedStringArrayAttribute(const std::string& object, const std::string& name,
                                        const std::vector<std::string>& values) {
  size_t width = 1;
  for (const auto& v : values) width = std::max(width, v.size());
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, width);
  H5Tset_strpad(type, H5T_STR_NULLPAD);
  std::vector<char> buffer(values.size() * width, '\0');
  for (size_t i = 0; i < values.size(); ++i) {
    std::memcpy(buffer.data() + i * width, values[i].data(), values[i].size());
  }
  Attribute(object, name, type, type, static_cast<long long>(values.size()), buffer.data());
  H5Tclose(type);
}

void RawFile::StringArrayAttribute(const std::string& object, const std::string& name,
                                   const std::vector<std::string>& values) {
  hid_t type = VariableString();
  std::vector<const char*> pointers;
  for (const auto& v : values) pointers.push_back(v.c_str());
  Attribute(object, name, type, type, static_cast<long long>(values.size()), pointers.data());
  H5Tclose(type);
}

void RawFile::DoubleAttribute(const std::string& object, const std::string& name, double value) {
  Attribute(object, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, -1, &value);
}

void RawFile::IntAttribute(const std::string& object, const std::string& name, int value) {
  Attribute(object, name, H5T_STD_I32LE, H5T_NATIVE_INT, -1, &value);
}

void RawFile::Group(const std::string& path) {
  hid_t g = H5Gcreate2(file_, path.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  Check(g, "group " + path);
  H5Gclose(g);
}

double TestValue(long long k, int a) {
  // Irrational frequencies: no two samples repeat and float32 rounding is exercised.
  return (a + 1) * 10.0 + std::sin(0.1 * std::sqrt(2.0) * k + a) + 0.25 * std::cos(0.7 * k);
}

std::vector<double> WriteRecording(const std::string& path, const RecordingSpec& spec) {
  std::vector<double> values;
  const long long n = spec.samples;
  const int a = spec.axes;
  for (long long k = 0; k < n; ++k) {
    for (int j = 0; j < a; ++j) values.push_back(TestValue(k, j));
  }
  RawFile file(path);
  std::vector<hsize_t> dims = {static_cast<hsize_t>(n)};
  if (spec.two_dimensional) dims.push_back(static_cast<hsize_t>(a));
  file.Dataset("/rate", dims, values, spec.layout);
  file.StringAttribute("/rate", "units", spec.units);
  if (!spec.axis_names.empty()) {
    if (spec.fixed_length_axes) {
      file.FixedStringArrayAttribute("/rate", "axes", spec.axis_names);
    } else {
      file.StringArrayAttribute("/rate", "axes", spec.axis_names);
    }
  }
  file.DoubleAttribute("/", "sample_rate_hz", spec.sample_rate_hz);
  file.StringAttribute("/", "instrument", "test gyro");
  file.StringAttribute("/", "serial", "SN-0001");
  file.StringAttribute("/", "start_time_utc", "2026-03-01T08:00:00Z");
  file.DoubleAttribute("/", "latitude_deg", 48.5);
  if (spec.temperature) {
    std::vector<double> temperature;
    for (long long k = 0; k < n; ++k) temperature.push_back(25.0 + 0.001 * k);
    Layout aux_layout = spec.layout;
    if (!aux_layout.chunk.empty()) aux_layout.chunk.resize(1);
    file.Dataset("/aux/temperature", {static_cast<hsize_t>(n)}, temperature, aux_layout);
    file.StringAttribute("/aux/temperature", "units", "degC");
  }
  return values;
}

}  // namespace fogpipe::testing
