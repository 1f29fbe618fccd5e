#include "pipeline/io/matlab_import.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>
#include <vector>

#include "pipeline/hdf5/file.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/inputs.h"
#include "pipeline/io/recording_error.h"
#include "pipeline/io/recording_reader.h"
#include "pipeline/io/sha256.h"

namespace fogpipe::io {
namespace {

namespace fs = std::filesystem;
using hdf5::ObjectKind;
using hdf5::TypeClass;

constexpr char kHdf5Signature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
constexpr const char* kClassAttribute = "MATLAB_class";

/// "gyro.rate" -> "/gyro/rate" (a struct's field); an absolute HDF5 path stays as it is.
std::string HdfPath(const std::string& variable) {
  if (variable.front() == '/') return variable;
  std::string path = "/" + variable;
  std::replace(path.begin(), path.end(), '.', '/');
  return path;
}

std::string DimsText(const std::vector<hsize_t>& dims) {
  std::string text = "[";
  for (std::size_t k = 0; k < dims.size(); ++k) {
    text += (k > 0 ? ", " : "") + std::to_string(dims[k]);
  }
  return text + "]";
}

bool IsNumericClass(const std::string& matlab_class) {
  static const char* const kNumeric[] = {"double", "single", "int8",   "uint8", "int16",
                                         "uint16", "int32",  "uint32", "int64", "uint64"};
  return std::find(std::begin(kNumeric), std::end(kNumeric), matlab_class) != std::end(kNumeric);
}

/// A numeric variable read whole, seen as a rows x cols matrix in MATLAB's orientation.
struct Variable {
  std::string label;         ///< "variable 'rate'", for messages
  std::string path;          ///< the HDF5 path
  std::string matlab_class;  ///< "" when the dataset has no MATLAB_class attribute
  std::vector<hsize_t> hdf5_dims;
  long long rows = 1;
  long long cols = 1;
  bool column_major = false;  ///< values hold the rows x cols matrix column by column
  std::vector<double> values;

  bool is_vector() const { return rows == 1 || cols == 1; }
  /// "3 x 1000 matrix (MATLAB size; HDF5 dims [1000, 3])" for noun "matrix".
  std::string SizeText(const std::string& noun) const {
    return std::to_string(rows) + " x " + std::to_string(cols) + " " + noun +
           (matlab_class.empty() ? " (HDF5 dims " : " (MATLAB size; HDF5 dims ") +
           DimsText(hdf5_dims) + ")";
  }
};

std::string VariableList(const hdf5::Group& group) {
  std::string list;
  for (const std::string& name : group.ChildNames()) {
    if (name.empty() || name.front() == '#') continue;  // MATLAB's #refs# and #subsystem#
    list += (list.empty() ? "'" : ", '") + name + "'";
  }
  return list.empty() ? "none" : list;
}

// Reads `variable` as a real numeric array of rank <= 2. Caller holds the HDF5 lock.
bool ReadVariable(const hdf5::Group& root, const std::string& variable, Variable* out,
                  std::string* error, bool read_values = true) {
  out->path = HdfPath(variable);
  out->label = "variable '" + variable + "'";
  auto fail = [&](const std::string& message) {
    *error = out->label + " " + message;
    return false;
  };
  const hdf5::LinkTrace trace = root.TraceLinks(out->path);
  if (trace.end != hdf5::LinkTrace::End::kInFile) {
    return fail("leads out of the file or through a loop of links at '" + trace.link +
                "'; not followed");
  }
  const ObjectKind kind = root.KindOf(out->path);
  if (kind == ObjectKind::kMissing) {
    return fail("is not in the file (variables: " + VariableList(root) + ")");
  }
  if (kind == ObjectKind::kGroup) {
    const hdf5::Group group = root.OpenGroup(out->path);
    if (group.HasAttribute("MATLAB_sparse")) return fail("is a sparse matrix; save full(...)");
    return fail("is a struct or another group, not a matrix (its fields: " + VariableList(group) +
                ")");
  }
  if (kind != ObjectKind::kDataset) return fail("is not a dataset");
  const hdf5::Dataset dataset = root.OpenDataset(out->path);
  if (dataset.HasAttribute(kClassAttribute)) {
    out->matlab_class = dataset.ReadStringAttribute(kClassAttribute);
    if (!IsNumericClass(out->matlab_class)) {
      return fail("is a MATLAB '" + out->matlab_class + "' array, not a numeric matrix");
    }
    if (dataset.HasAttribute("MATLAB_empty") && dataset.ReadDoubleAttribute("MATLAB_empty") != 0) {
      return fail("is empty");
    }
  }
  const hdf5::TypeInfo type = dataset.type();
  if (type.type_class != TypeClass::kFloat && type.type_class != TypeClass::kInteger) {
    return fail(std::string("has HDF5 type class ") + hdf5::ToString(type.type_class) +
                ", not real numbers (a complex array is not a rate)");
  }
  out->hdf5_dims = dataset.dims();
  const std::vector<hsize_t>& dims = out->hdf5_dims;
  if (dims.size() > 2) {
    return fail("has " + std::to_string(dims.size()) + " dimensions " + DimsText(dims) +
                "; a matrix has 2");
  }
  if (dims.size() == 1) out->rows = static_cast<long long>(dims[0]);
  if (dims.size() == 2) {
    // MATLAB writes column-major: its rows x cols matrix is HDF5 [cols, rows].
    out->column_major = !out->matlab_class.empty();
    out->rows = static_cast<long long>(out->column_major ? dims[1] : dims[0]);
    out->cols = static_cast<long long>(out->column_major ? dims[0] : dims[1]);
  }
  if (out->rows == 0 || out->cols == 0) return fail("is empty");
  // The same storage checks as the recording reader's: nothing outside the file is read, and
  // a declared size is believed only if the file can hold it.
  try {
    std::error_code ec;
    const auto file_bytes = std::filesystem::file_size(root.file_path(), ec);
    CheckDatasetStorage(
        dataset,
        static_cast<unsigned long long>(out->rows) * static_cast<unsigned long long>(out->cols),
        type.size_bytes, ec ? 0 : static_cast<long long>(file_bytes));
  } catch (const RecordingError& e) {
    return fail("is refused: " + e.problem());
  }
  if (read_values) out->values = dataset.ReadDoubles();
  return true;
}

// The rate matrix [N, A] of a variable by the shape rule of matlab_import.h.
bool RateMatrix(const Variable& v, Eigen::MatrixXd* rate, std::string* error) {
  if (v.is_vector()) {
    *rate = Eigen::Map<const Eigen::VectorXd>(v.values.data(),
                                              static_cast<Eigen::Index>(v.values.size()));
    return true;
  }
  if (v.cols > v.rows) {
    *error = v.label + " is a " + v.SizeText("matrix") + ": more axes (" + std::to_string(v.cols) +
             ") than samples (" + std::to_string(v.rows) +
             "): a transposed matrix? fogpipe reads one row per sample and one column per axis "
             "(N x A); save the transpose (rate.') instead";
    return false;
  }
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  if (v.column_major) {
    *rate = Eigen::Map<const Eigen::MatrixXd>(v.values.data(), v.rows, v.cols);
  } else {
    *rate = Eigen::Map<const RowMajor>(v.values.data(), v.rows, v.cols);
  }
  return true;
}

// Reads everything the options name from the open file into `source`. Caller holds the lock.
bool ReadSource(const hdf5::File& file, const MatlabImportOptions& options, ImportSource* source,
                std::string* error) {
  const hdf5::Group root = file.Root();
  if (options.variable.empty()) {
    *error =
        "which variable holds the rate? give --variable (variables: " + VariableList(root) + ")";
    return false;
  }
  Variable rate;
  if (!ReadVariable(root, options.variable, &rate, error) ||
      !RateMatrix(rate, &source->rate, error)) {
    return false;
  }
  source->format = rate.matlab_class.empty() ? "hdf5" : "matlab-v7.3";
  source->found = {{"variable", rate.path},       {"matlab_class", rate.matlab_class},
                   {"hdf5_dims", rate.hdf5_dims}, {"matrix_rows", rate.rows},
                   {"matrix_columns", rate.cols}, {"read_column_major", rate.column_major}};
  if (!options.sample_rate_variable.empty()) {
    Variable fs_variable;
    if (!ReadVariable(root, options.sample_rate_variable, &fs_variable, error)) return false;
    if (fs_variable.values.size() != 1) {
      *error = fs_variable.label + " is a " + fs_variable.SizeText("array") +
               "; the sample rate is one number";
      return false;
    }
    source->sample_rate_hz = fs_variable.values.front();
    source->sample_rate_from = fs_variable.label;
    if (!(source->sample_rate_hz > 0.0) || !std::isfinite(source->sample_rate_hz)) {
      *error = fs_variable.label + " holds " + std::to_string(source->sample_rate_hz) +
               "; a sample rate is finite and > 0 Hz";
      return false;
    }
  }
  for (const AuxImportSpec& spec : options.metadata.aux) {
    Variable aux;
    if (!ReadVariable(root, spec.source, &aux, error)) return false;
    if (!aux.is_vector() || static_cast<Eigen::Index>(aux.values.size()) != source->rate.rows()) {
      *error = "aux '" + spec.name + "': " + aux.label + " is a " + aux.SizeText("array") +
               "; it must be a vector of " + std::to_string(source->rate.rows()) +
               " values, one per sample of the rate";
      return false;
    }
    source->aux[spec.name] = Eigen::Map<const Eigen::VectorXd>(
        aux.values.data(), static_cast<Eigen::Index>(aux.values.size()));
  }
  return true;
}

}  // namespace

std::string CheckMatlabVariables(const std::string& path, const MatlabImportOptions& options) {
  hdf5::SilenceHdf5ErrorPrinter();
  try {
    auto lock = hdf5::LockHdf5();  // declared first, released last
    const hdf5::File file = OpenHdf5ReadOnly(path);
    const hdf5::Group root = file.Root();
    std::vector<std::string> names = {options.variable, options.sample_rate_variable};
    for (const AuxImportSpec& spec : options.metadata.aux) names.push_back(spec.source);
    for (const std::string& name : names) {
      Variable v;
      std::string error;
      if (!name.empty() && !ReadVariable(root, name, &v, &error, /*read_values=*/false)) {
        return path + ": " + error;
      }
    }
  } catch (const RecordingError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return path + ": " + e.what();
  }
  return "";
}

std::optional<ImportSourceKind> DetectImportSourceKind(const std::string& path,
                                                       std::string* error) {
  // Before any open: a FIFO blocks it, a device never ends.
  if (const std::string problem = RegularFileProblem(path); !problem.empty()) {
    if (error) *error = path + ": cannot be imported: " + problem;
    return std::nullopt;
  }
  std::error_code ec;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (error) *error = path + ": cannot open for reading: " + std::strerror(errno);
    return std::nullopt;
  }
  char head[8] = {};
  in.read(head, sizeof head);
  const std::streamsize got = in.gcount();
  if (got == 8 && std::memcmp(head, kHdf5Signature, 8) == 0) return ImportSourceKind::kHdf5;
  // HDF5 finds its superblock at 0 or behind a user block of 512, 1024, 2048, ... bytes.
  const auto size = fs::is_regular_file(path, ec) ? fs::file_size(path, ec) : 0;
  for (std::uintmax_t offset = 512; !ec && offset + 8 <= size; offset *= 2) {
    char signature[8] = {};
    in.clear();
    in.seekg(static_cast<std::streamoff>(offset));
    in.read(signature, sizeof signature);
    if (in.gcount() == 8 && std::memcmp(signature, kHdf5Signature, 8) == 0) {
      return ImportSourceKind::kHdf5;
    }
  }
  if (got >= 6 && std::memcmp(head, "MATLAB", 6) == 0) return ImportSourceKind::kOldMatFile;
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".mat" ? ImportSourceKind::kOldMatFile : ImportSourceKind::kText;
}

std::string OldMatFileMessage(const std::string& path) {
  return path +
         ": is a MATLAB MAT-file older than v7.3 (v4, v5 or v7 are not HDF5), which fogpipe "
         "cannot read: save it again with save('file.mat', 'rate', '-v7.3'), or export the data "
         "as CSV (writematrix(rate, 'file.csv'))";
}

bool MatlabImportOptions::IsValid(std::string* error) const {
  // An empty `variable` is refused by ImportMatlab, which can then list the file's variables.
  if (!sample_rate_variable.empty() && metadata.sample_rate_hz > 0.0) {
    if (error) *error = "give the sample rate or the variable holding it, not both";
    return false;
  }
  return metadata.IsValid(error);
}

nlohmann::json MatlabImportOptions::ToJson() const {
  return {{"variable", variable}, {"sample_rate_variable", sample_rate_variable}};
}

ImportResult ImportMatlab(const std::string& path, const MatlabImportOptions& options) {
  ImportResult failed;
  std::string error;
  if (!options.IsValid(&error)) {
    failed.error = path + ": " + error;
    return failed;
  }
  const std::optional<ImportSourceKind> kind = DetectImportSourceKind(path, &error);
  if (!kind) {
    failed.error = error;
    return failed;
  }
  if (*kind == ImportSourceKind::kOldMatFile) {
    failed.error = OldMatFileMessage(path);
    return failed;
  }
  ImportSource source;
  source.path = path;
  hdf5::SilenceHdf5ErrorPrinter();
  try {
    auto lock = hdf5::LockHdf5();  // declared first, released last
    const hdf5::File file = OpenHdf5ReadOnly(path);
    if (!ReadSource(file, options, &source, &error)) {
      failed.error = path + ": " + error;
      return failed;
    }
  } catch (const RecordingError& e) {
    failed.error = e.what();
    return failed;
  } catch (const std::exception& e) {
    failed.error = path + ": " + e.what();
    return failed;
  }
  const std::optional<std::string> sha = Sha256FileHex(path, &error);
  if (!sha) {
    failed.error = error;
    return failed;
  }
  source.sha256 = *sha;
  std::error_code ec;
  source.size_bytes = static_cast<long long>(fs::file_size(path, ec));
  source.options = options.ToJson();
  return FinishImport(std::move(source), options.metadata);
}

}  // namespace fogpipe::io
