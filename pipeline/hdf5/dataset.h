// fogpipe::hdf5::Dataset: one HDF5 dataset, read whole (small ones) or by hyperslab (columns of
// an [N, A] matrix, blocks of rows), written whole or by blocks of rows.
//
// Every method requires the caller to hold LockHdf5() and throws hdf5::Error naming the file, the
// dataset and the operation.
#pragma once

#include <H5Cpp.h>

#include <string>
#include <utility>
#include <vector>

#include "pipeline/hdf5/object.h"

namespace fogpipe::hdf5 {

/// How numbers are stored in the file. Memory is always double or int64.
enum class StorageType { kFloat64, kFloat32, kInt64 };

/// Layout of a dataset created by Group::CreateDataset / WriteDataset.
///
/// Chunking + shuffle + deflate is the combination HDF5 recommends for floating-point arrays
/// (the byte shuffle groups exponent bytes and typically gains 10-30 % over deflate alone;
/// HDF Group, "Using Compression in HDF5"). Chunks are kept at or below 1 MiB, the default size
/// of HDF5's per-dataset chunk cache, so that a reader never re-inflates a chunk it already holds.
struct DatasetOptions {
  StorageType storage = StorageType::kFloat64;
  /// Rows per chunk; 0 picks about 512 KiB per chunk (never more than the number of rows).
  hsize_t chunk_rows = 0;
  /// zlib level 0..9; 0 stores chunks uncompressed.
  int deflate_level = 4;
  /// Byte shuffle before deflate (ignored when deflate_level is 0).
  bool shuffle = true;
  /// Datasets with fewer elements are stored contiguous and uncompressed: chunk headers and the
  /// B-tree cost more than compression saves on a few hundred numbers.
  hsize_t min_chunked_elements = 4096;
  /// Each chunk holds one column (chunk shape [chunk_rows, 1, ...]) instead of whole rows, so that
  /// reading one column of an [N, K] dataset inflates only that column's chunks (the IMFs of a
  /// results file, io/column_datasets.h). chunk_rows = 0 then targets 512 KiB of one column.
  bool chunk_per_column = false;

  bool IsValid(std::string* error) const;
};

class Dataset : public Object {
 public:
  Dataset(std::string file_path, std::string path, H5::DataSet dataset);
  Dataset(const Dataset&) = default;
  Dataset(Dataset&&) = default;
  Dataset& operator=(const Dataset&) = default;
  Dataset& operator=(Dataset&&) = default;
  /// Closes quietly (detail::CloseQuietly).
  ~Dataset() override;

  /// Extent of each dimension; empty for a scalar dataset.
  std::vector<hsize_t> dims() const;
  int rank() const { return static_cast<int>(dims().size()); }
  /// Total number of elements (1 for a scalar).
  hsize_t size() const;
  TypeInfo type() const;
  /// Chunk extent per dimension; empty for contiguous or compact layout.
  std::vector<hsize_t> chunk_dims() const;

  /// The whole dataset converted to double (row-major). Meant for small datasets.
  std::vector<double> ReadDoubles() const;
  /// The whole dataset as int64 (integer datasets only).
  std::vector<long long> ReadInt64s() const;
  /// The whole dataset as strings (string datasets only).
  std::vector<std::string> ReadStrings() const;

  // Tables (1-D compound datasets, Group::WriteTable): one field, all rows. Each throws
  // hdf5::Error when the dataset is not compound or has no such field.
  /// The fields (name and type), in the stored order.
  std::vector<std::pair<std::string, TypeInfo>> Fields() const;
  /// A numeric field converted to double.
  std::vector<double> ReadFieldDoubles(const std::string& field) const;
  /// An integer field as int64.
  std::vector<long long> ReadFieldInt64s(const std::string& field) const;
  /// A string field (fixed or variable length).
  std::vector<std::string> ReadFieldStrings(const std::string& field) const;

  /// Rows [row0, row0 + rows) of column `column` of a [N, A] dataset (or of a [N] dataset when
  /// column is 0), converted to double, into out[0 .. rows). Reads only that hyperslab.
  void ReadColumn(hsize_t column, hsize_t row0, hsize_t rows, double* out) const;
  /// Rows [row0, row0 + rows) of a [N] or [N, A] dataset, all columns, row-major into out.
  void ReadRows(hsize_t row0, hsize_t rows, double* out) const;
  /// Writes rows [row0, row0 + rows) (all columns, row-major) from `data`.
  void WriteRows(hsize_t row0, hsize_t rows, const double* data);

  hid_t id() const override { return dataset_.getId(); }

 private:
  /// Selects a block of rows x columns in the file space and reads/writes it with a 1-D memory
  /// space of rows * columns elements.
  void TransferBlock(const std::vector<hsize_t>& start, const std::vector<hsize_t>& count,
                     hid_t memory_type, void* buffer, bool write,
                     const std::string& operation) const;

  /// Start and count (in *count) of rows [row0, row0 + rows) x all columns; throws when the
  /// rows are outside the extent.
  std::vector<hsize_t> RowBlockStart(hsize_t row0, hsize_t rows, std::vector<hsize_t>* count,
                                     const std::string& operation) const;

  H5::DataSet dataset_;
};

}  // namespace fogpipe::hdf5
