// Test helper: writes HDF5 files with the plain HDF5 C API (independently of fogpipe's own
// wrappers and writer), so that the reader is tested against files it had no hand in making,
// including files that break the contract on purpose.
#pragma once

#include <hdf5.h>

#include <filesystem>
#include <string>
#include <vector>

namespace fogpipe::testing {

/// A temporary folder removed at destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::string File(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

/// How /rate (or an aux dataset) is stored.
struct Layout {
  hid_t file_type = H5T_IEEE_F64LE;  ///< H5T_IEEE_F32LE, H5T_STD_I32LE, ...
  std::vector<hsize_t> chunk;        ///< empty: contiguous
  int deflate = 0;                   ///< 0: none
  bool shuffle = false;
};

/// Raw-C-API file writer used by the tests. Every call aborts the test on failure (ASSERT).
class RawFile {
 public:
  /// `user_block_bytes` (0, or a power of two >= 512) reserves a user block before the HDF5
  /// data, as MATLAB v7.3 MAT-files have (512 bytes).
  explicit RawFile(const std::string& path, hsize_t user_block_bytes = 0);
  ~RawFile();
  hid_t id() const { return file_; }
  /// Dataset of doubles (row-major) converted by HDF5 to layout.file_type.
  void Dataset(const std::string& path, const std::vector<hsize_t>& dims,
               const std::vector<double>& values, const Layout& layout = {});
  /// Variable-length string attribute on an object ("/" for root).
  void StringAttribute(const std::string& object, const std::string& name,
                       const std::string& value);
  /// Fixed-length, NUL-padded string array attribute (what numpy |S arrays become).
  void FixedStringArrayAttribute(const std::string& object, const std::string& name,
                                 const std::vector<std::string>& values);
  /// Variable-length string array attribute (what h5py writes for a list of str).
  void StringArrayAttribute(const std::string& object, const std::string& name,
                            const std::vector<std::string>& values);
  void DoubleAttribute(const std::string& object, const std::string& name, double value);
  void IntAttribute(const std::string& object, const std::string& name, int value);
  void Group(const std::string& path);
  void Close();

 private:
  /// Scalar attribute when count < 0, else 1-D of `count` elements.
  void Attribute(const std::string& object, const std::string& name, hid_t file_type,
                 hid_t memory_type, long long count, const void* data);

  hid_t file_ = -1;
};

/// Deterministic non-constant test signal: sample k of column a.
double TestValue(long long k, int a);

/// A contract-v1 recording written with the raw C API.
struct RecordingSpec {
  long long samples = 1000;
  int axes = 1;
  bool two_dimensional = false;
  std::string units = "deg/h";
  double sample_rate_hz = 10.0;
  Layout layout;
  std::vector<std::string> axis_names;  ///< written as `axes` when not empty
  bool fixed_length_axes = false;
  bool temperature = false;  ///< adds /aux/temperature [N] in degC
};
/// Writes `spec` to `path`; returns the values written, row-major [N, A].
std::vector<double> WriteRecording(const std::string& path, const RecordingSpec& spec);

}  // namespace fogpipe::testing
