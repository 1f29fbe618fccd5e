// fogpipe::hdf5::Group: navigation (children, kinds), sub-groups and datasets.
//
// Numeric datasets written through fogpipe always carry a `units` attribute: the writers below
// REQUIRE one (an empty string is a programming error, std::invalid_argument). Use "1" for a
// dimensionless quantity (UDUNITS convention), "samples" for indices and counts of samples.
//
// Every method requires the caller to hold LockHdf5() and throws hdf5::Error.
#pragma once

#include <H5Cpp.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "pipeline/hdf5/dataset.h"
#include "pipeline/hdf5/object.h"

namespace fogpipe::hdf5 {

enum class ObjectKind { kMissing, kGroup, kDataset, kOther };

/// Where the links along a path lead, found link by link without opening any object, so that
/// nothing outside the file is touched (HDF5 opens the target file of an external link as soon
/// as an object behind it is looked up).
struct LinkTrace {
  enum class End {
    kInFile,            ///< hard and soft links only (or a missing link: the caller reports it)
    kLeavesFile,        ///< an external or user-defined link, at `link`
    kTooManySoftLinks,  ///< more than kMaxSoftLinks soft links followed: a cycle, most likely
  };
  static constexpr int kMaxSoftLinks = 16;
  End end = End::kInFile;
  std::string link;  ///< the link where the path leaves the file
};

/// The name of the attribute every numeric dataset carries.
inline constexpr const char* kUnitsAttribute = "units";

/// One named column of a small table written by Group::WriteTable: float64, int64 or UTF-8
/// strings. The columns of one table have the same number of rows.
struct TableColumn {
  enum class Kind { kFloat64, kInt64, kString };
  std::string name;
  Kind kind = Kind::kFloat64;
  std::vector<double> doubles;
  std::vector<long long> integers;
  std::vector<std::string> strings;

  static TableColumn Doubles(std::string name, std::vector<double> values);
  static TableColumn Int64s(std::string name, std::vector<long long> values);
  static TableColumn Strings(std::string name, std::vector<std::string> values);
  std::size_t rows() const;
};

class Group : public Object {
 public:
  Group(std::string file_path, std::string path, H5::Group group);
  Group(const Group&) = default;
  Group(Group&&) = default;
  Group& operator=(const Group&) = default;
  Group& operator=(Group&&) = default;
  /// Closes quietly (detail::CloseQuietly).
  ~Group() override;

  /// What `relative_path` (may contain '/', or be absolute) names: a group, a dataset, something
  /// else (named datatype, dangling link) or nothing. Missing intermediate groups give kMissing.
  ObjectKind KindOf(const std::string& relative_path) const;
  bool Exists(const std::string& relative_path) const {
    return KindOf(relative_path) != ObjectKind::kMissing;
  }
  /// Follows the links of `absolute_path` from the file's root (see LinkTrace).
  LinkTrace TraceLinks(const std::string& absolute_path) const;
  /// Names of the direct children (links), sorted by name.
  std::vector<std::string> ChildNames() const;

  Group OpenGroup(const std::string& relative_path) const;
  Dataset OpenDataset(const std::string& relative_path) const;
  /// Creates `name` (and any missing intermediate groups).
  Group CreateGroup(const std::string& name);
  /// Opens `name` if it is a group, else creates it.
  Group RequireGroup(const std::string& name);

  /// Creates an empty dataset of shape `dims` for later Dataset::WriteRows, with its `units`.
  Dataset CreateDataset(const std::string& name, const std::vector<hsize_t>& dims,
                        const std::string& units, const DatasetOptions& options = {});
  /// Writes `data` (row-major, product(dims) values) as a new dataset with its `units`.
  Dataset WriteDataset(const std::string& name, const double* data,
                       const std::vector<hsize_t>& dims, const std::string& units,
                       const DatasetOptions& options = {});
  Dataset WriteDataset(const std::string& name, const Eigen::Ref<const Eigen::VectorXd>& data,
                       const std::string& units, const DatasetOptions& options = {});
  Dataset WriteDataset(const std::string& name, const std::vector<double>& data,
                       const std::string& units, const DatasetOptions& options = {});
  /// Integer data (indices, counts): stored as int64 whatever options.storage says.
  Dataset WriteDataset(const std::string& name, const std::vector<long long>& data,
                       const std::string& units, const DatasetOptions& options = {});
  /// A 1-D dataset of variable-length UTF-8 strings (no units: not numeric).
  Dataset WriteStringDataset(const std::string& name, const std::vector<std::string>& values);
  /// A scalar variable-length UTF-8 string dataset, e.g. a configuration text too long for an
  /// attribute (attributes in the object header are limited to 64 KiB).
  Dataset WriteTextDataset(const std::string& name, const std::string& text);
  /// A small table as ONE 1-D compound dataset, one element per row and one field per column
  /// (IEEE float64 LE, int64 LE, variable-length UTF-8), laid out compact (inside the object
  /// header): one object instead of one dataset per value. h5py reads it as a structured array,
  /// MATLAB's h5read as a struct of columns. No `units` attribute: a table whose rows have
  /// different units carries them as a column. Throws std::invalid_argument when the columns
  /// differ in length or there are none.
  Dataset WriteTable(const std::string& name, const std::vector<TableColumn>& columns);

  hid_t id() const override { return group_.getId(); }

 private:
  Dataset CreateNumeric(const std::string& name, const std::vector<hsize_t>& dims,
                        const std::string& units, const DatasetOptions& options);

  H5::Group group_;
};

}  // namespace fogpipe::hdf5
