#include "pipeline/hdf5/group.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "pipeline/hdf5/detail.h"
#include "pipeline/hdf5/string_io.h"

namespace fogpipe::hdf5 {
namespace {

using detail::CheckC;
using detail::JoinPath;
using detail::ScopedId;

/// Links or attributes a group keeps in its own header before HDF5 moves them to dense storage.
constexpr unsigned kMaxCompactEntries = 256;

/// Dataset creation properties with HDF5's "no attributes" hint: the object header is allocated
/// at its size instead of HDF5's 256-byte minimum for datasets, and grows in place (it is last in
/// the file) when the few attributes fogpipe writes (units, a note) are added. The padding the
/// minimum would leave unused is ~100 bytes per dataset, 16 KB of a demo results file.
/// Neither groups nor datasets record access, modification, change and birth times in their
/// headers (16 bytes each): /provenance holds when the analysis ran, and without them a rerun
/// with the same inputs writes the same bytes.
ScopedId DatasetCreation(const std::string& file, const std::string& object) {
  ScopedId dcpl(CheckC(H5Pcreate(H5P_DATASET_CREATE), file, object, "create dataset"), H5Pclose);
  CheckC(H5Pset_dset_no_attrs_hint(dcpl.get(), 1), file, object, "create dataset");
  CheckC(H5Pset_obj_track_times(dcpl.get(), 0), file, object, "create dataset");
  return dcpl;
}

herr_t CollectLink(hid_t, const char* name, const H5L_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}

std::vector<std::string> SplitPath(const std::string& path) {
  std::vector<std::string> parts;
  std::string current;
  for (char c : path) {
    if (c == '/') {
      if (!current.empty()) parts.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  if (!current.empty()) parts.push_back(current);
  return parts;
}

hid_t FileTypeOf(StorageType storage) {
  switch (storage) {
    case StorageType::kFloat32:
      return H5T_IEEE_F32LE;
    case StorageType::kInt64:
      return H5T_STD_I64LE;
    case StorageType::kFloat64:
      break;
  }
  return H5T_IEEE_F64LE;
}

size_t StorageBytes(StorageType storage) { return storage == StorageType::kFloat32 ? 4 : 8; }

void RequireUnits(const std::string& units, const std::string& path) {
  if (units.empty()) {
    throw std::invalid_argument("fogpipe::hdf5: numeric dataset '" + path +
                                "' written without units (use \"1\" for dimensionless)");
  }
}

}  // namespace

Group::~Group() { detail::CloseQuietly(&group_); }

Group::Group(std::string file_path, std::string path, H5::Group group)
    : Object(std::move(file_path), std::move(path)), group_(std::move(group)) {}

ObjectKind Group::KindOf(const std::string& relative_path) const {
  const std::string operation = "look up '" + relative_path + "'";
  const std::vector<std::string> parts = SplitPath(relative_path);
  const bool absolute = !relative_path.empty() && relative_path.front() == '/';
  std::string walked = absolute ? "/" : "";
  for (const std::string& part : parts) {
    walked += (walked.empty() || walked == "/") ? part : "/" + part;
    // H5Lexists on "a/b" fails when "a" is missing, so every component is tested in turn.
    if (CheckC(H5Lexists(id(), walked.c_str(), H5P_DEFAULT), file_path(), path(), operation) <= 0) {
      return ObjectKind::kMissing;
    }
  }
  if (parts.empty()) return ObjectKind::kGroup;
  if (H5Oexists_by_name(id(), walked.c_str(), H5P_DEFAULT) <= 0) return ObjectKind::kOther;
  ScopedId object(H5Oopen(id(), walked.c_str(), H5P_DEFAULT), H5Oclose);
  if (object.get() < 0) return ObjectKind::kOther;
  switch (H5Iget_type(object.get())) {
    case H5I_GROUP:
      return ObjectKind::kGroup;
    case H5I_DATASET:
      return ObjectKind::kDataset;
    default:
      return ObjectKind::kOther;
  }
}

namespace {

LinkTrace TraceFrom(hid_t location, const std::string& path, int depth) {
  std::string prefix;
  std::size_t begin = 1;
  while (begin <= path.size()) {
    std::size_t end = path.find('/', begin);
    if (end == std::string::npos) end = path.size();
    if (end > begin) {
      prefix += "/" + path.substr(begin, end - begin);
      H5L_info_t link{};
      if (H5Lget_info(location, prefix.c_str(), &link, H5P_DEFAULT) < 0) return {};
      if (link.type == H5L_TYPE_SOFT) {
        if (depth >= LinkTrace::kMaxSoftLinks) {
          return {LinkTrace::End::kTooManySoftLinks, prefix};
        }
        std::string target(link.u.val_size + 1, '\0');
        if (H5Lget_val(location, prefix.c_str(), target.data(), target.size(), H5P_DEFAULT) < 0) {
          return {};
        }
        target.resize(std::strlen(target.c_str()));
        if (target.empty() || target[0] != '/') {
          target = prefix.substr(0, prefix.rfind('/') + 1) + target;
        }
        LinkTrace inner = TraceFrom(location, target, depth + 1);
        if (inner.end != LinkTrace::End::kInFile) return inner;
      } else if (link.type != H5L_TYPE_HARD) {
        return {LinkTrace::End::kLeavesFile, prefix};
      }
    }
    begin = end + 1;
  }
  return {};
}

}  // namespace

LinkTrace Group::TraceLinks(const std::string& absolute_path) const {
  return TraceFrom(id(), absolute_path, 0);
}

std::vector<std::string> Group::ChildNames() const {
  std::vector<std::string> names;
  hsize_t index = 0;
  CheckC(H5Literate(id(), H5_INDEX_NAME, H5_ITER_INC, &index, CollectLink, &names), file_path(),
         path(), "list children");
  std::sort(names.begin(), names.end());
  return names;
}

Group Group::OpenGroup(const std::string& relative_path) const {
  const std::string full = JoinPath(path(), relative_path);
  return detail::Checked(file_path(), full, "open group",
                         [&] { return Group(file_path(), full, group_.openGroup(relative_path)); });
}

Dataset Group::OpenDataset(const std::string& relative_path) const {
  const std::string full = JoinPath(path(), relative_path);
  return detail::Checked(file_path(), full, "open dataset", [&] {
    return Dataset(file_path(), full, group_.openDataSet(relative_path));
  });
}

Group Group::CreateGroup(const std::string& name) {
  const std::string full = JoinPath(path(), name);
  ScopedId lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  // Links and attributes stay in the group's header ("compact" storage) up to these counts; past
  // HDF5's default of 8 each moves to "dense" storage, a fractal heap and a B-tree of ~2-4 KB
  // even for 9 entries. fogpipe's groups hold tens of links (a models table, a campaign's
  // columns) and about ten attributes, which a header lists and searches quickly enough.
  ScopedId gcpl(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
  H5Pset_link_phase_change(gcpl.get(), kMaxCompactEntries, kMaxCompactEntries - 16);
  H5Pset_attr_phase_change(gcpl.get(), kMaxCompactEntries, kMaxCompactEntries - 16);
  H5Pset_obj_track_times(gcpl.get(), 0);  // as DatasetCreation says
  hid_t created = CheckC(H5Gcreate2(id(), name.c_str(), lcpl.get(), gcpl.get(), H5P_DEFAULT),
                         file_path(), full, "create group");
  return Group(file_path(), full, detail::Adopt<H5::Group>(created));
}

Group Group::RequireGroup(const std::string& name) {
  return KindOf(name) == ObjectKind::kGroup ? OpenGroup(name) : CreateGroup(name);
}

Dataset Group::CreateNumeric(const std::string& name, const std::vector<hsize_t>& dims,
                             const std::string& units, const DatasetOptions& options) {
  const std::string full = JoinPath(path(), name);
  RequireUnits(units, full);
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("fogpipe::hdf5: " + error);
  const std::string operation = "create dataset";
  ScopedId space(dims.empty()
                     ? H5Screate(H5S_SCALAR)
                     : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                 H5Sclose);
  CheckC(space.get(), file_path(), full, operation);
  ScopedId dcpl = DatasetCreation(file_path(), full);
  hsize_t elements = 1;
  for (hsize_t d : dims) elements *= d;
  if (!dims.empty() && dims[0] > 0 && elements >= options.min_chunked_elements) {
    std::vector<hsize_t> chunk = dims;
    if (options.chunk_per_column) std::fill(chunk.begin() + 1, chunk.end(), hsize_t{1});
    hsize_t chunk_row_elements = 1;
    for (std::size_t d = 1; d < chunk.size(); ++d) chunk_row_elements *= chunk[d];
    hsize_t rows = options.chunk_rows;
    if (rows == 0) {
      const hsize_t target_bytes = 512 * 1024;
      rows = std::max<hsize_t>(1, target_bytes / (std::max<hsize_t>(1, chunk_row_elements) *
                                                  StorageBytes(options.storage)));
    }
    chunk[0] = std::min(rows, dims[0]);
    CheckC(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), file_path(),
           full, operation);
    if (options.deflate_level > 0) {
      if (options.shuffle) CheckC(H5Pset_shuffle(dcpl.get()), file_path(), full, operation);
      CheckC(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(options.deflate_level)), file_path(),
             full, operation);
    }
  }
  ScopedId lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  hid_t created = CheckC(H5Dcreate2(id(), name.c_str(), FileTypeOf(options.storage), space.get(),
                                    lcpl.get(), dcpl.get(), H5P_DEFAULT),
                         file_path(), full, operation);
  Dataset dataset(file_path(), full, detail::Adopt<H5::DataSet>(created));
  dataset.WriteStringAttribute(kUnitsAttribute, units);
  return dataset;
}

Dataset Group::CreateDataset(const std::string& name, const std::vector<hsize_t>& dims,
                             const std::string& units, const DatasetOptions& options) {
  return CreateNumeric(name, dims, units, options);
}

Dataset Group::WriteDataset(const std::string& name, const double* data,
                            const std::vector<hsize_t>& dims, const std::string& units,
                            const DatasetOptions& options) {
  Dataset dataset = CreateNumeric(name, dims, units, options);
  hsize_t elements = 1;
  for (hsize_t d : dims) elements *= d;
  if (elements > 0) {
    CheckC(H5Dwrite(dataset.id(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
           file_path(), dataset.path(), "write dataset");
  }
  return dataset;
}

Dataset Group::WriteDataset(const std::string& name, const Eigen::Ref<const Eigen::VectorXd>& data,
                            const std::string& units, const DatasetOptions& options) {
  // A VectorXd (or a contiguous segment of one) has unit inner stride: its data() is row-major.
  return WriteDataset(name, data.data(), {static_cast<hsize_t>(data.size())}, units, options);
}

Dataset Group::WriteDataset(const std::string& name, const std::vector<double>& data,
                            const std::string& units, const DatasetOptions& options) {
  return WriteDataset(name, data.data(), {data.size()}, units, options);
}

Dataset Group::WriteDataset(const std::string& name, const std::vector<long long>& data,
                            const std::string& units, const DatasetOptions& options) {
  DatasetOptions integer_options = options;
  integer_options.storage = StorageType::kInt64;
  Dataset dataset = CreateNumeric(name, {data.size()}, units, integer_options);
  if (!data.empty()) {
    CheckC(H5Dwrite(dataset.id(), H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()),
           file_path(), dataset.path(), "write dataset");
  }
  return dataset;
}

Dataset Group::WriteStringDataset(const std::string& name, const std::vector<std::string>& values) {
  const std::string full = JoinPath(path(), name);
  ScopedId type(detail::MakeVariableStringType(), H5Tclose);
  const hsize_t n = values.size();
  ScopedId space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  ScopedId dcpl = DatasetCreation(file_path(), full);
  hid_t created = CheckC(
      H5Dcreate2(id(), name.c_str(), type.get(), space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
      file_path(), full, "create string dataset");
  Dataset dataset(file_path(), full, detail::Adopt<H5::DataSet>(created));
  std::vector<const char*> pointers;
  for (const std::string& v : values) pointers.push_back(v.c_str());
  if (n > 0) {
    CheckC(H5Dwrite(created, type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()),
           file_path(), full, "write string dataset");
  }
  return dataset;
}

Dataset Group::WriteTextDataset(const std::string& name, const std::string& text) {
  const std::string full = JoinPath(path(), name);
  ScopedId type(detail::MakeVariableStringType(), H5Tclose);
  ScopedId space(H5Screate(H5S_SCALAR), H5Sclose);
  ScopedId dcpl = DatasetCreation(file_path(), full);
  hid_t created = CheckC(
      H5Dcreate2(id(), name.c_str(), type.get(), space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
      file_path(), full, "create text dataset");
  Dataset dataset(file_path(), full, detail::Adopt<H5::DataSet>(created));
  const char* pointer = text.c_str();
  CheckC(H5Dwrite(created, type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &pointer), file_path(), full,
         "write text dataset");
  return dataset;
}

TableColumn TableColumn::Doubles(std::string name, std::vector<double> values) {
  TableColumn c;
  c.name = std::move(name);
  c.kind = Kind::kFloat64;
  c.doubles = std::move(values);
  return c;
}

TableColumn TableColumn::Int64s(std::string name, std::vector<long long> values) {
  TableColumn c;
  c.name = std::move(name);
  c.kind = Kind::kInt64;
  c.integers = std::move(values);
  return c;
}

TableColumn TableColumn::Strings(std::string name, std::vector<std::string> values) {
  TableColumn c;
  c.name = std::move(name);
  c.kind = Kind::kString;
  c.strings = std::move(values);
  return c;
}

std::size_t TableColumn::rows() const {
  switch (kind) {
    case Kind::kFloat64:
      return doubles.size();
    case Kind::kInt64:
      return integers.size();
    case Kind::kString:
      return strings.size();
  }
  return 0;
}

Dataset Group::WriteTable(const std::string& name, const std::vector<TableColumn>& columns) {
  const std::string full = JoinPath(path(), name);
  if (columns.empty())
    throw std::invalid_argument("fogpipe::hdf5: table " + full + " has no column");
  const std::size_t rows = columns.front().rows();
  for (const TableColumn& c : columns) {
    if (c.rows() != rows) {
      throw std::invalid_argument("fogpipe::hdf5: table " + full + ": column " + c.name + " has " +
                                  std::to_string(c.rows()) + " rows, " + columns.front().name +
                                  " " + std::to_string(rows));
    }
  }
  const std::string operation = "create table";
  // Every field is 8 bytes in memory (double, int64, char*), so the row is packed at 8 * k.
  static_assert(sizeof(double) == 8 && sizeof(long long) == 8 && sizeof(const char*) == 8);
  const std::size_t row_size = 8 * columns.size();
  ScopedId string_type(CheckC(detail::MakeVariableStringType(), file_path(), full, operation),
                       H5Tclose);
  ScopedId memory_type(CheckC(H5Tcreate(H5T_COMPOUND, row_size), file_path(), full, operation),
                       H5Tclose);
  ScopedId file_type(CheckC(H5Tcreate(H5T_COMPOUND, row_size), file_path(), full, operation),
                     H5Tclose);
  std::vector<unsigned char> buffer(row_size * rows);
  for (std::size_t k = 0; k < columns.size(); ++k) {
    const TableColumn& c = columns[k];
    const std::size_t offset = 8 * k;
    hid_t memory_field = string_type.get(), file_field = string_type.get();
    if (c.kind == TableColumn::Kind::kFloat64) {
      memory_field = H5T_NATIVE_DOUBLE;
      file_field = H5T_IEEE_F64LE;
    } else if (c.kind == TableColumn::Kind::kInt64) {
      memory_field = H5T_NATIVE_LLONG;
      file_field = H5T_STD_I64LE;
    }
    CheckC(H5Tinsert(memory_type.get(), c.name.c_str(), offset, memory_field), file_path(), full,
           operation + " field " + c.name);
    CheckC(H5Tinsert(file_type.get(), c.name.c_str(), offset, file_field), file_path(), full,
           operation + " field " + c.name);
    for (std::size_t i = 0; i < rows; ++i) {
      unsigned char* cell = buffer.data() + i * row_size + offset;
      if (c.kind == TableColumn::Kind::kFloat64) {
        std::memcpy(cell, &c.doubles[i], 8);
      } else if (c.kind == TableColumn::Kind::kInt64) {
        std::memcpy(cell, &c.integers[i], 8);
      } else {
        const char* text = c.strings[i].c_str();
        std::memcpy(cell, &text, 8);
      }
    }
  }
  const hsize_t n = rows;
  ScopedId space(CheckC(H5Screate_simple(1, &n, nullptr), file_path(), full, operation), H5Sclose);
  // Compact: a few rows live in the object header, with no separate data block to allocate.
  ScopedId dcpl = DatasetCreation(file_path(), full);
  CheckC(H5Pset_layout(dcpl.get(), H5D_COMPACT), file_path(), full, operation);
  hid_t created = CheckC(H5Dcreate2(id(), name.c_str(), file_type.get(), space.get(), H5P_DEFAULT,
                                    dcpl.get(), H5P_DEFAULT),
                         file_path(), full, operation);
  Dataset dataset(file_path(), full, detail::Adopt<H5::DataSet>(created));
  if (rows > 0) {
    CheckC(H5Dwrite(created, memory_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()),
           file_path(), full, "write table");
  }
  return dataset;
}

}  // namespace fogpipe::hdf5
