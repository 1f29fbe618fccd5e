#include "pipeline/io/recording_reader.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>
#include <sstream>

#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/recording_limits.h"

namespace fogpipe::io {
namespace {

namespace fs = std::filesystem;
using hdf5::ObjectKind;
using hdf5::TypeClass;

std::string FloatName(const hdf5::TypeInfo& type) {
  return "float" + std::to_string(type.size_bytes * 8);
}

std::string DescribeTypeClass(const hdf5::TypeInfo& type) {
  if (type.type_class == TypeClass::kFloat) return FloatName(type);
  if (type.type_class == TypeClass::kInteger) return "int" + std::to_string(type.size_bytes * 8);
  return hdf5::ToString(type.type_class);
}

std::string ShapeText(const std::vector<hsize_t>& dims) {
  if (dims.empty()) return "scalar";
  std::ostringstream out;
  out << "[";
  for (size_t i = 0; i < dims.size(); ++i) out << (i ? ", " : "") << dims[i];
  out << "]";
  return out.str();
}

/// Checks the filters of a dataset's pipeline are available (szip, LZF, blosc, ... may not be).
void CheckFiltersAvailable(const hdf5::Dataset& dataset) {
  const hid_t plist = H5Dget_create_plist(dataset.id());
  if (plist < 0) return;
  const int count = H5Pget_nfilters(plist);
  for (int i = 0; i < count; ++i) {
    unsigned flags = 0;
    size_t values = 0;
    char name[64] = {0};
    unsigned config = 0;
    const H5Z_filter_t filter = H5Pget_filter2(plist, static_cast<unsigned>(i), &flags, &values,
                                               nullptr, sizeof(name), name, &config);
    if (filter >= 0 && H5Zfilter_avail(filter) <= 0) {
      H5Pclose(plist);
      throw RecordingError(error_kind::kUnsupportedCompression, dataset.file_path(),
                           dataset.path() + " is compressed with HDF5 filter " +
                               std::to_string(filter) +
                               (name[0] ? std::string(" (") + name + ")" : "") +
                               ", which this HDF5 library cannot decode");
    }
  }
  H5Pclose(plist);
}

/// Refuses a path whose links lead out of the file (an external link, or a user-defined one,
/// anywhere along it, also behind soft links) and soft-link cycles: fogpipe reads the input file
/// and nothing else. Checked link by link before anything is opened, so nothing outside the
/// file is ever touched. `path` is absolute; a missing link is left to the caller to report.
void CheckPathStaysInFile(const hdf5::Group& root, const std::string& path,
                          const std::string& shown) {
  const hdf5::LinkTrace trace = root.TraceLinks(path);
  if (trace.end == hdf5::LinkTrace::End::kTooManySoftLinks) {
    throw RecordingError(error_kind::kWrongType, root.file_path(),
                         shown + " goes through more than " +
                             std::to_string(hdf5::LinkTrace::kMaxSoftLinks) +
                             " soft links (a link cycle?); refused");
  }
  if (trace.end == hdf5::LinkTrace::End::kLeavesFile) {
    throw RecordingError(error_kind::kExternalData, root.file_path(),
                         shown + " is reached through an external link (" + trace.link +
                             "); fogpipe reads only the input file itself (refused: copy "
                             "the data into the recording)");
  }
}

/// How many chunks a chunked dataset of extent `dims` has when every one is written, from its
/// creation property list `plist`; 0 for other layouts.
long long ExpectedChunks(hid_t plist, const std::vector<hsize_t>& dims) {
  std::vector<hsize_t> chunk(dims.size(), 0);
  if (dims.empty() || H5Pget_layout(plist) != H5D_CHUNKED ||
      H5Pget_chunk(plist, static_cast<int>(chunk.size()), chunk.data()) !=
          static_cast<int>(dims.size())) {
    return 0;
  }
  long long count = 1;
  for (std::size_t d = 0; d < dims.size(); ++d) {
    if (chunk[d] == 0) return 0;
    // Declared sizes are bounded before this is called (no overflow of the product).
    count *= static_cast<long long>((dims[d] + chunk[d] - 1) / chunk[d]);
  }
  return count;
}

}  // namespace

/// Refuses datasets whose samples live outside the file (virtual datasets, external raw
/// storage: a FIFO, a device or any other file could stand there), and datasets declared but
/// never written. `values` is the declared element count, `element_bytes` the stored size.
void CheckDatasetStorage(const hdf5::Dataset& dataset, unsigned long long values,
                         std::size_t element_bytes, long long file_size_bytes) {
  const std::string& path = dataset.file_path();
  const std::vector<hsize_t> dims = dataset.dims();  // may throw: before the plist is open
  const hid_t plist = H5Dget_create_plist(dataset.id());
  if (plist < 0) return;
  const H5D_layout_t layout = H5Pget_layout(plist);
  const int external = H5Pget_external_count(plist);
  const long long expected_chunks = ExpectedChunks(plist, dims);
  H5Pclose(plist);
  if (layout == H5D_VIRTUAL) {
    throw RecordingError(error_kind::kExternalData, path,
                         dataset.path() +
                             " is a virtual dataset (its samples live in other "
                             "files); fogpipe reads only the input file itself "
                             "(refused: copy the data into the recording)");
  }
  if (external > 0) {
    throw RecordingError(error_kind::kExternalData, path,
                         dataset.path() + " keeps its samples in " + std::to_string(external) +
                             " external raw file(s); fogpipe reads only the input file itself "
                             "(refused: copy the data into the recording)");
  }
  H5D_space_status_t status = H5D_SPACE_STATUS_ERROR;
  if (values > 0 && H5Dget_space_status(dataset.id(), &status) >= 0) {
    if (status == H5D_SPACE_STATUS_NOT_ALLOCATED) {
      throw RecordingError(error_kind::kUnwrittenDataset, path,
                           dataset.path() + " is declared with " + std::to_string(values) +
                               " values but none was ever written (no storage allocated)");
    }
  }
  unsigned long long declared = 0;
  if (__builtin_mul_overflow(values, static_cast<unsigned long long>(element_bytes), &declared) ||
      static_cast<double>(declared) >
          limits::kMaxExpansion * static_cast<double>(std::max(file_size_bytes, 1ll))) {
    throw RecordingError(error_kind::kImplausibleShape, path,
                         dataset.path() + " declares " + std::to_string(values) + " values of " +
                             std::to_string(element_bytes) + " bytes, more than a " +
                             std::to_string(file_size_bytes) +
                             "-byte file can hold even compressed (1032:1, deflate's limit)");
  }
  // Chunks never written read as the fill value (zeros), which would be analysed as samples.
  // Counted, not judged by the space status, which reports a compressed dataset as partly
  // allocated even when every chunk was written.
  hsize_t written = 0;
  const hid_t space = expected_chunks > 0 ? H5Dget_space(dataset.id()) : -1;
  const bool counted = space >= 0 && H5Dget_num_chunks(dataset.id(), space, &written) >= 0;
  if (space >= 0) H5Sclose(space);
  if (counted && static_cast<long long>(written) < expected_chunks) {
    throw RecordingError(error_kind::kUnwrittenDataset, path,
                         dataset.path() + " is declared with " + std::to_string(values) +
                             " values but only " + std::to_string(written) + " of its " +
                             std::to_string(expected_chunks) +
                             " chunks were ever written (a recording cut short?); the others "
                             "would read as fill values");
  }
}

namespace {

/// An optional root attribute of the given class; a wrong class is a contract violation.
template <typename T>
std::optional<T> OptionalRootAttribute(const hdf5::Group& root, const std::string& name,
                                       TypeClass expected);

template <>
std::optional<std::string> OptionalRootAttribute(const hdf5::Group& root, const std::string& name,
                                                 TypeClass) {
  if (!root.HasAttribute(name)) return std::nullopt;
  const hdf5::AttributeInfo a = root.DescribeAttribute(name);
  if (a.type.type_class != TypeClass::kString || a.size() != 1) {
    throw RecordingError(error_kind::kWrongType, root.file_path(),
                         "root attribute '" + name + "' must be one string, found " +
                             DescribeTypeClass(a.type) + " " + ShapeText(a.dims));
  }
  return root.ReadStringAttribute(name);
}

template <>
std::optional<double> OptionalRootAttribute(const hdf5::Group& root, const std::string& name,
                                            TypeClass) {
  if (!root.HasAttribute(name)) return std::nullopt;
  const hdf5::AttributeInfo a = root.DescribeAttribute(name);
  if ((a.type.type_class != TypeClass::kFloat && a.type.type_class != TypeClass::kInteger) ||
      a.size() != 1) {
    throw RecordingError(error_kind::kWrongType, root.file_path(),
                         "root attribute '" + name + "' must be one float64, found " +
                             DescribeTypeClass(a.type) + " " + ShapeText(a.dims));
  }
  return root.ReadDoubleAttribute(name);
}

/// Reads the required string `units` of a dataset (missing -> missing_attribute).
std::string RequiredUnits(const hdf5::Dataset& dataset) {
  if (!dataset.HasAttribute("units")) {
    throw RecordingError(error_kind::kMissingAttribute, dataset.file_path(),
                         dataset.path() + " has no 'units' attribute (required, a string)");
  }
  const hdf5::AttributeInfo a = dataset.DescribeAttribute("units");
  if (a.type.type_class != TypeClass::kString || a.size() != 1) {
    throw RecordingError(error_kind::kWrongType, dataset.file_path(),
                         dataset.path() + " attribute 'units' must be one string, found " +
                             DescribeTypeClass(a.type) + " " + ShapeText(a.dims));
  }
  return dataset.ReadStringAttribute("units");
}

/// The dataset's type as a name: "float32", "int16", "uint16", ...
std::string SampleTypeName(const hdf5::Dataset& dataset, const hdf5::TypeInfo& type) {
  if (type.type_class != TypeClass::kInteger) return FloatName(type);
  const hid_t t = H5Dget_type(dataset.id());
  const bool is_signed = t >= 0 && H5Tget_sign(t) != H5T_SGN_NONE;
  if (t >= 0) H5Tclose(t);
  return (is_signed ? "int" : "uint") + std::to_string(type.size_bytes * 8);
}

/// Contract v1.1: what one stored value is worth in the dataset's unit. 1 for float32 / float64;
/// an integer dataset holds counts and needs a `scale_factor` attribute (units per count: one
/// finite, non-zero number), by which the reader multiplies every count.
double SampleScale(const hdf5::Dataset& dataset, const hdf5::TypeInfo& type) {
  const std::string& path = dataset.file_path();
  if (type.type_class == TypeClass::kFloat) return 1.0;
  if (type.type_class != TypeClass::kInteger) {
    throw RecordingError(error_kind::kWrongType, path,
                         dataset.path() + " has type " + DescribeTypeClass(type) +
                             "; contract v1.1 requires float32, float64, or integer counts with "
                             "a 'scale_factor' attribute");
  }
  if (!dataset.HasAttribute("scale_factor")) {
    throw RecordingError(error_kind::kMissingAttribute, path,
                         dataset.path() + " holds integers (" + SampleTypeName(dataset, type) +
                             ") but has no 'scale_factor' attribute: contract v1.1 reads integer "
                             "counts only with their scale factor (the unit per count)");
  }
  const hdf5::AttributeInfo a = dataset.DescribeAttribute("scale_factor");
  if ((a.type.type_class != TypeClass::kFloat && a.type.type_class != TypeClass::kInteger) ||
      a.size() != 1) {
    throw RecordingError(error_kind::kWrongType, path,
                         dataset.path() + " attribute 'scale_factor' must be one number, found " +
                             DescribeTypeClass(a.type) + " " + ShapeText(a.dims));
  }
  const double scale = dataset.ReadDoubleAttribute("scale_factor");
  if (!std::isfinite(scale) || scale == 0.0) {
    std::ostringstream value;
    value << scale;
    throw RecordingError(error_kind::kBadScaleFactor, path,
                         dataset.path() + " attribute 'scale_factor' is " + value.str() +
                             "; it must be a finite, non-zero number of units per count");
  }
  return scale;
}

/// Refuses samples beyond limits::kMaxMagnitude or, zero aside, below kMinMagnitude (NaNs are
/// bridged already, infinities refused).
void CheckMagnitudes(const Eigen::VectorXd& x, const std::string& what, const std::string& path) {
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double a = std::abs(x[i]);
    if (a > limits::kMaxMagnitude || (a != 0.0 && a < limits::kMinMagnitude)) {
      std::ostringstream text;
      text << what << " sample " << i << " is " << x[i]
           << ", outside the magnitudes fogpipe analyses (" << limits::kMinMagnitude << " .. "
           << limits::kMaxMagnitude
           << " in the file's unit, or 0): variances of such values overflow or underflow. A "
              "wrong unit or a damaged file? Rescale it";
      throw RecordingError(error_kind::kExtremeMagnitude, path, text.str());
    }
  }
}

/// The value HDF5 returns for elements never written (0 when the writer set none, or when it
/// cannot be read as a double).
double FillValue(const hdf5::Dataset& dataset) {
  double fill = 0.0;
  const hid_t plist = H5Dget_create_plist(dataset.id());
  if (plist < 0) return fill;
  H5D_fill_value_t status = H5D_FILL_VALUE_ERROR;
  if (H5Pfill_value_defined(plist, &status) >= 0 && status == H5D_FILL_VALUE_USER_DEFINED) {
    if (H5Pget_fill_value(plist, H5T_NATIVE_DOUBLE, &fill) < 0) fill = 0.0;
  }
  H5Pclose(plist);
  return fill;
}

bool IsConstant(const Eigen::VectorXd& x) {
  for (Eigen::Index i = 1; i < x.size(); ++i) {
    if (x[i] != x[0]) return false;
  }
  return true;
}

}  // namespace

bool IsValidAxisName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos;
}

namespace {

void CheckReadable(const std::string& path, long long* size_bytes) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    throw RecordingError(error_kind::kMissingFile, path, "no such file");
  }
  if (fs::is_directory(status)) {
    throw RecordingError(error_kind::kNotHdf5, path, "is a folder, not an HDF5 file");
  }
  if (!fs::is_regular_file(status)) {
    // Opening a FIFO blocks until a writer appears; a device may never end.
    const char* what = fs::is_fifo(status)             ? "a FIFO (named pipe)"
                       : fs::is_character_file(status) ? "a character device"
                       : fs::is_block_file(status)     ? "a block device"
                       : fs::is_socket(status)         ? "a socket"
                                                       : "not a regular file";
    throw RecordingError(
        error_kind::kNotRegularFile, path,
        std::string("is ") + what + ", not a regular file; refused without opening it");
  }
  if (::access(path.c_str(), R_OK) != 0) {
    throw RecordingError(error_kind::kUnreadableFile, path, "cannot be read (permission denied)");
  }
  *size_bytes = static_cast<long long>(fs::file_size(path, ec));
  if (!ec && *size_bytes == 0) {
    throw RecordingError(error_kind::kEmptyFile, path, "is empty (0 bytes), not an HDF5 file");
  }
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // problems are reported, not printed
  const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
  if (is_hdf5 == 0) {
    throw RecordingError(error_kind::kNotHdf5, path,
                         "is not an HDF5 file (no HDF5 signature in its first bytes)");
  }
  if (is_hdf5 < 0) {
    throw RecordingError(error_kind::kCorruptFile, path,
                         "HDF5 cannot examine it:\n" + hdf5::CurrentErrorStack());
  }
}

hdf5::File OpenChecked(const std::string& path) {
  try {
    return hdf5::File::OpenReadOnly(path);
  } catch (const hdf5::Error& e) {
    if (e.hdf5_stack().find("truncated file") != std::string::npos) {
      throw RecordingError(error_kind::kTruncatedFile, path,
                           "is truncated (shorter than its HDF5 superblock says; an interrupted "
                           "copy or write?): " +
                               e.innermost_message());
    }
    throw RecordingError(error_kind::kCorruptFile, path,
                         "is a damaged HDF5 file that cannot be opened: " + e.innermost_message());
  }
}

/// The declared shape within limits (recording_limits.h), checked before anything is derived
/// from it: counts that do not fit, absurd sizes and transposed matrices.
void CheckRateShape(const std::string& path, const std::vector<hsize_t>& dims) {
  const hsize_t axes = dims.size() == 2 ? dims[1] : 1;
  if (axes == 0) {
    throw RecordingError(error_kind::kWrongShape, path,
                         "/rate has shape " + ShapeText(dims) + ": no axis at all");
  }
  if (dims.size() == 2 && axes > dims[0]) {
    throw RecordingError(error_kind::kWrongShape, path,
                         "/rate has shape " + ShapeText(dims) + ": more axes (" +
                             std::to_string(axes) + ") than samples (" + std::to_string(dims[0]) +
                             "). A transposed matrix? (MATLAB and other column-major writers "
                             "store an N x A matrix as [A, N].) Contract v1 wants [N, A], one row "
                             "per sample; transpose it when writing");
  }
  if (axes > static_cast<hsize_t>(limits::kMaxAxes)) {
    throw RecordingError(error_kind::kImplausibleShape, path,
                         "/rate has shape " + ShapeText(dims) + ": " + std::to_string(axes) +
                             " axes, more than the " + std::to_string(limits::kMaxAxes) +
                             " fogpipe accepts");
  }
  if (dims[0] > static_cast<hsize_t>(limits::kMaxSamples)) {
    throw RecordingError(error_kind::kImplausibleShape, path,
                         "/rate has shape " + ShapeText(dims) + ": " + std::to_string(dims[0]) +
                             " samples per axis, more than the " +
                             std::to_string(limits::kMaxSamples) + " fogpipe accepts");
  }
}

void InspectRate(const hdf5::Group& root, RecordingInfo* info) {
  const std::string& path = info->path;
  CheckPathStaysInFile(root, "/rate", "/rate");
  const ObjectKind kind = root.KindOf("rate");
  if (kind == ObjectKind::kMissing) {
    throw RecordingError(error_kind::kMissingDataset, path,
                         "has no dataset /rate (contract v1: /rate [N] or [N, A], float32/64)");
  }
  if (kind != ObjectKind::kDataset) {
    throw RecordingError(error_kind::kWrongType, path, "/rate is not a dataset");
  }
  const hdf5::Dataset rate = root.OpenDataset("rate");
  const hdf5::TypeInfo type = rate.type();
  info->rate_scale_factor = SampleScale(rate, type);
  info->rate_dtype = SampleTypeName(rate, type);
  const std::vector<hsize_t> dims = rate.dims();
  if (dims.size() != 1 && dims.size() != 2) {
    throw RecordingError(error_kind::kWrongRank, path,
                         "/rate has rank " + std::to_string(dims.size()) + " (" + ShapeText(dims) +
                             "); contract v1 requires [N] or [N, A]");
  }
  info->two_dimensional = dims.size() == 2;
  CheckRateShape(path, dims);
  info->samples = static_cast<long long>(dims[0]);
  info->axis_count = info->two_dimensional ? static_cast<int>(dims[1]) : 1;
  CheckDatasetStorage(rate, dims[0] * (info->two_dimensional ? dims[1] : 1), type.size_bytes,
                      info->file_size_bytes);
  for (hsize_t c : rate.chunk_dims()) info->rate_chunk.push_back(c);
  CheckFiltersAvailable(rate);

  info->rate_units = RequiredUnits(rate);
  const std::optional<units::RateUnit> unit = units::ParseRateUnit(info->rate_units);
  if (!unit) {
    throw RecordingError(error_kind::kUnknownUnits, path,
                         "/rate has units '" + info->rate_units +
                             "'; contract v1 allows 'deg/h', 'deg/s' or 'rad/s'");
  }
  info->rate_unit = *unit;

  if (rate.HasAttribute("axes")) {
    const hdf5::AttributeInfo a = rate.DescribeAttribute("axes");
    if (a.type.type_class != TypeClass::kString || a.dims.size() > 1) {
      throw RecordingError(error_kind::kWrongType, path,
                           "/rate attribute 'axes' must be a 1-D array of strings, found " +
                               DescribeTypeClass(a.type) + " " + ShapeText(a.dims));
    }
    info->axis_names = rate.ReadStringArrayAttribute("axes");
    if (static_cast<int>(info->axis_names.size()) != info->axis_count) {
      throw RecordingError(error_kind::kBadAxes, path,
                           "/rate attribute 'axes' names " +
                               std::to_string(info->axis_names.size()) + " axes but /rate has " +
                               std::to_string(info->axis_count));
    }
    std::set<std::string> seen;
    for (const std::string& name : info->axis_names) {
      if (!IsValidAxisName(name) || !seen.insert(name).second) {
        throw RecordingError(error_kind::kBadAxes, path,
                             "/rate attribute 'axes' has an empty, repeated or invalid name '" +
                                 name + "' (names must be unique, non-empty, without '/')");
      }
    }
    info->axis_names_from_file = true;
  } else {
    for (int a = 0; a < info->axis_count; ++a)
      info->axis_names.push_back("axis" + std::to_string(a));
  }
}

void InspectRootAttributes(const hdf5::Group& root, RecordingInfo* info) {
  const std::string& path = info->path;
  if (!root.HasAttribute("sample_rate_hz")) {
    throw RecordingError(error_kind::kMissingAttribute, path,
                         "has no root attribute 'sample_rate_hz' (required, float64 > 0)");
  }
  const hdf5::AttributeInfo a = root.DescribeAttribute("sample_rate_hz");
  if ((a.type.type_class != TypeClass::kFloat && a.type.type_class != TypeClass::kInteger) ||
      a.size() != 1) {
    throw RecordingError(error_kind::kWrongType, path,
                         "root attribute 'sample_rate_hz' must be one float64, found " +
                             DescribeTypeClass(a.type) + " " + ShapeText(a.dims));
  }
  info->sample_rate_hz = root.ReadDoubleAttribute("sample_rate_hz");
  if (!std::isfinite(info->sample_rate_hz) || info->sample_rate_hz <= 0.0) {
    std::ostringstream value;
    value << info->sample_rate_hz;
    throw RecordingError(
        error_kind::kBadSampleRate, path,
        "root attribute 'sample_rate_hz' is " + value.str() + "; it must be a finite rate > 0 Hz");
  }
  if (info->sample_rate_hz < limits::kMinSampleRateHz ||
      info->sample_rate_hz > limits::kMaxSampleRateHz) {
    std::ostringstream value;
    value << "root attribute 'sample_rate_hz' is " << info->sample_rate_hz
          << " Hz, outside the range fogpipe accepts (" << limits::kMinSampleRateHz << " .. "
          << limits::kMaxSampleRateHz << " Hz): every tau = m / rate would be meaningless";
    throw RecordingError(error_kind::kBadSampleRate, path, value.str());
  }
  info->start_time_utc =
      OptionalRootAttribute<std::string>(root, "start_time_utc", TypeClass::kString);
  info->instrument = OptionalRootAttribute<std::string>(root, "instrument", TypeClass::kString);
  info->serial = OptionalRootAttribute<std::string>(root, "serial", TypeClass::kString);
  info->latitude_deg = OptionalRootAttribute<double>(root, "latitude_deg", TypeClass::kFloat);
}

void InspectAux(const hdf5::Group& root, RecordingInfo* info) {
  const std::string& path = info->path;
  CheckPathStaysInFile(root, "/aux", "/aux");
  const ObjectKind kind = root.KindOf("aux");
  if (kind == ObjectKind::kMissing) return;
  if (kind != ObjectKind::kGroup) {
    throw RecordingError(error_kind::kWrongType, path, "/aux exists but is not a group");
  }
  const hdf5::Group aux = root.OpenGroup("aux");
  for (const std::string& name : aux.ChildNames()) {
    CheckPathStaysInFile(root, "/aux/" + name, "/aux/" + name);
    if (aux.KindOf(name) != ObjectKind::kDataset) continue;  // unknown things are ignored
    const hdf5::Dataset channel = aux.OpenDataset(name);
    const hdf5::TypeInfo type = channel.type();
    const double scale = SampleScale(channel, type);
    const std::vector<hsize_t> dims = channel.dims();
    if (dims.size() != 1) {
      throw RecordingError(
          error_kind::kWrongRank, path,
          channel.path() + " has shape " + ShapeText(dims) + "; contract v1 requires [N]");
    }
    if (static_cast<long long>(dims[0]) != info->samples) {
      throw RecordingError(error_kind::kAuxLengthMismatch, path,
                           channel.path() + " has " + std::to_string(dims[0]) +
                               " samples but /rate has " + std::to_string(info->samples) +
                               " (aux channels share the sampling of /rate)");
    }
    CheckDatasetStorage(channel, dims[0], type.size_bytes, info->file_size_bytes);
    CheckFiltersAvailable(channel);
    info->aux.push_back({name, RequiredUnits(channel), SampleTypeName(channel, type), scale});
  }
}

}  // namespace

bool ReadOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& text) {
    if (error) *error = text;
    return false;
  };
  if (max_nan_gap_samples < 0) return fail("max_nan_gap_samples must be >= 0");
  if (min_samples < 1) return fail("min_samples must be >= 1");
  if (block_rows < 1) return fail("block_rows must be >= 1");
  return true;
}

RecordingReader::RecordingReader(const std::string& path) : file_(OpenHdf5ReadOnly(path)) {
  info_.path = path;
  std::error_code ec;
  info_.file_size_bytes = static_cast<long long>(fs::file_size(path, ec));
  try {
    const hdf5::Group root = file_.Root();
    InspectRate(root, &info_);
    InspectRootAttributes(root, &info_);
    InspectAux(root, &info_);
  } catch (const hdf5::Error& e) {
    throw RecordingError(error_kind::kCorruptFile, path,
                         "HDF5 failed while reading its metadata (" + e.operation() + " of '" +
                             e.object() + "'): " + e.innermost_message());
  }
}

int AxisIndex(const RecordingInfo& info, const std::string& axis) {
  const auto found = std::find(info.axis_names.begin(), info.axis_names.end(), axis);
  if (found != info.axis_names.end()) return static_cast<int>(found - info.axis_names.begin());
  if (!axis.empty() &&
      std::all_of(axis.begin(), axis.end(), [](unsigned char c) { return std::isdigit(c); }) &&
      axis.size() < 9) {
    const int index = std::stoi(axis);
    if (index < info.axis_count) return index;
  }
  std::string names;
  for (const std::string& n : info.axis_names) names += (names.empty() ? "" : ", ") + n;
  throw RecordingError(error_kind::kUnknownAxis, info.path,
                       "has no axis '" + axis + "' (axes: " + names + ", or an index 0.." +
                           std::to_string(info.axis_count - 1) + ")");
}

std::vector<int> SelectAxes(const RecordingInfo& info, const std::string& axis) {
  const bool named =
      std::find(info.axis_names.begin(), info.axis_names.end(), axis) != info.axis_names.end();
  if (axis != kAllAxes || named) return {AxisIndex(info, axis)};
  std::vector<int> all(info.axis_count);
  for (int i = 0; i < info.axis_count; ++i) all[i] = i;
  return all;
}

int RecordingReader::AxisIndex(const std::string& axis) const { return io::AxisIndex(info_, axis); }

Eigen::VectorXd RecordingReader::ReadColumn(const hdf5::Dataset& dataset, int column, double scale,
                                            const std::string& what, const ReadOptions& options,
                                            bool reject_constant, ReadReport* report) const {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("fogpipe::io::ReadOptions: " + error);
  const long long n = info_.samples;
  if (n < options.min_samples) {
    throw RecordingError(error_kind::kTooFewSamples, info_.path,
                         what + " has " + std::to_string(n) + " samples, fewer than the " +
                             std::to_string(options.min_samples) +
                             " the analysis needs (min_samples)");
  }
  // Blocks aligned to whole chunks: each chunk is read and inflated once per column.
  const std::vector<hsize_t> chunk = dataset.chunk_dims();
  long long block = options.block_rows;
  if (!chunk.empty() && chunk[0] > 0) {
    const long long chunk_rows = static_cast<long long>(chunk[0]);
    block = std::max<long long>(1, block / chunk_rows) * chunk_rows;
  }
  Eigen::VectorXd x(n);
  ReadReport local;
  for (long long row0 = 0; row0 < n; row0 += block) {
    const long long rows = std::min(block, n - row0);
    try {
      dataset.ReadColumn(static_cast<hsize_t>(column), static_cast<hsize_t>(row0),
                         static_cast<hsize_t>(rows), x.data() + row0);
    } catch (const hdf5::Error& e) {
      throw RecordingError(error_kind::kCorruptFile, info_.path,
                           "cannot read samples " + std::to_string(row0) + ".." +
                               std::to_string(row0 + rows - 1) + " of " + what +
                               " (damaged data): " + e.innermost_message());
    }
    ++local.blocks_read;
  }
  if (scale != 1.0) x *= scale;
  if (!BridgeNanRuns(x, options.max_nan_gap_samples, &local.nan)) {
    const BridgeReport& r = local.nan;
    if (r.infinite_samples > 0) {
      throw RecordingError(error_kind::kNonFiniteValue, info_.path,
                           what + " holds " + std::to_string(r.infinite_samples) +
                               " infinite value(s), the first at sample " +
                               std::to_string(r.first_infinite_index) +
                               " (only NaN may mark a missing sample)");
    }
    std::ostringstream start_s;
    start_s << static_cast<double>(r.longest_run_start) / info_.sample_rate_hz;
    throw RecordingError(error_kind::kNanGapTooLong, info_.path,
                         what + " has a run of " + std::to_string(r.longest_run) +
                             " missing (NaN) samples starting at sample " +
                             std::to_string(r.longest_run_start) + " (t = " + start_s.str() +
                             " s), longer than max_nan_gap_samples = " +
                             std::to_string(options.max_nan_gap_samples) +
                             (r.longest_run == n ? " (every sample is NaN)" : ""));
  }
  CheckMagnitudes(x, what, info_.path);
  local.repeats = FindRepeatedRun(x, FillValue(dataset) * scale);
  if (reject_constant && IsConstant(x)) {
    std::ostringstream value;
    value << x[0];
    throw RecordingError(
        error_kind::kConstantSignal, info_.path,
        what + " is constant (every sample is " + value.str() + "): there is no noise to analyse");
  }
  if (report) *report = local;
  return x;
}

Eigen::VectorXd RecordingReader::ReadAxisNative(int axis, const ReadOptions& options,
                                                ReadReport* report) const {
  if (axis < 0 || axis >= info_.axis_count) {
    throw RecordingError(error_kind::kUnknownAxis, info_.path,
                         "has no axis index " + std::to_string(axis));
  }
  const std::string what = "/rate axis '" + info_.axis_names[axis] + "'";
  try {
    const hdf5::Dataset rate = file_.Root().OpenDataset("rate");
    return ReadColumn(rate, axis, info_.rate_scale_factor, what, options, options.reject_constant,
                      report);
  } catch (const hdf5::Error& e) {
    throw RecordingError(error_kind::kCorruptFile, info_.path,
                         "HDF5 failed on " + what + ": " + e.innermost_message());
  }
}

Eigen::VectorXd RecordingReader::ReadAxisRadPerSecond(int axis, const ReadOptions& options,
                                                      ReadReport* report) const {
  Eigen::VectorXd x = ReadAxisNative(axis, options, report);
  x *= units::ToRadPerSecond(info_.rate_unit);
  return x;
}

Eigen::VectorXd RecordingReader::ReadAxisRadPerSecond(const std::string& axis,
                                                      const ReadOptions& options,
                                                      ReadReport* report) const {
  return ReadAxisRadPerSecond(AxisIndex(axis), options, report);
}

Eigen::VectorXd RecordingReader::ReadAux(const std::string& name, const ReadOptions& options,
                                         ReadReport* report) const {
  const auto channel_info = std::find_if(info_.aux.begin(), info_.aux.end(),
                                         [&](const AuxChannelInfo& a) { return a.name == name; });
  if (channel_info == info_.aux.end()) {
    throw RecordingError(error_kind::kUnknownAux, info_.path, "has no aux channel /aux/" + name);
  }
  const std::string what = "/aux/" + name;
  try {
    const hdf5::Dataset channel = file_.Root().OpenDataset(what);
    return ReadColumn(channel, 0, channel_info->scale_factor, what, options,
                      /*reject_constant=*/false, report);
  } catch (const hdf5::Error& e) {
    throw RecordingError(error_kind::kCorruptFile, info_.path,
                         "HDF5 failed on " + what + ": " + e.innermost_message());
  }
}

std::string FormatRecordingSummary(const RecordingInfo& info) {
  std::ostringstream out;
  out << info.path << "\n"
      << "  recording  " << info.samples << " samples at " << info.sample_rate_hz << " Hz ("
      << info.duration_s() << " s), " << info.file_size_bytes << " bytes\n"
      << "  rate       " << info.axis_count << (info.axis_count == 1 ? " axis" : " axes") << " (";
  for (std::size_t i = 0; i < info.axis_names.size(); ++i) {
    out << (i ? ", " : "") << info.axis_names[i];
  }
  out << ") in " << info.rate_units << ", " << info.rate_dtype;
  if (info.rate_scale_factor != 1.0) {
    out << " counts x " << info.rate_scale_factor << " " << info.rate_units;
  }
  out << ", " << (info.rate_chunk.empty() ? "contiguous" : "chunked") << "\n";
  if (info.start_time_utc) out << "  start      " << *info.start_time_utc << "\n";
  if (info.instrument) out << "  instrument " << *info.instrument << "\n";
  if (info.serial) out << "  serial     " << *info.serial << "\n";
  if (info.latitude_deg) out << "  latitude   " << *info.latitude_deg << " deg\n";
  for (const AuxChannelInfo& aux : info.aux) {
    out << "  aux        " << aux.name << " in " << aux.units << ", " << aux.dtype;
    if (aux.scale_factor != 1.0) out << " counts x " << aux.scale_factor << " " << aux.units;
    out << "\n";
  }
  return out.str();
}

hdf5::File OpenHdf5ReadOnly(const std::string& path) {
  long long size_bytes = 0;
  CheckReadable(path, &size_bytes);
  return OpenChecked(path);
}

Eigen::VectorXd ReadAxisRadPerSecond(const std::string& path, const std::string& axis,
                                     const ReadOptions& options, ReadReport* report) {
  auto lock = hdf5::LockHdf5();
  RecordingReader reader(path);
  return reader.ReadAxisRadPerSecond(axis, options, report);
}

Eigen::VectorXd ReadAux(const std::string& path, const std::string& name,
                        const ReadOptions& options, ReadReport* report) {
  auto lock = hdf5::LockHdf5();
  RecordingReader reader(path);
  return reader.ReadAux(name, options, report);
}

}  // namespace fogpipe::io
