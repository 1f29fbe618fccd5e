#include "pipeline/io/column_datasets.h"

#include <H5Dpublic.h>
#include <oneapi/tbb/parallel_pipeline.h>
#include <oneapi/tbb/task_arena.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "pipeline/hdf5/detail.h"

namespace fogpipe::io {
namespace {

std::size_t ElementBytes(hdf5::StorageType type) {
  return type == hdf5::StorageType::kFloat32 ? 4 : 8;
}

// A zlib stream (RFC 1950) of `in`, which HDF5's deflate filter decodes with inflate(). With
// planes > 1, `in` is a shuffled chunk of that many byte planes and each plane becomes its own
// deflate blocks: a plane of random bytes (IsRandomBytePlane) as stored blocks (level 0), the
// others compressed at `level`. Switching with deflateParams ends the current block (Z_BLOCK), so
// the stream stays one valid zlib stream whatever the mix (RFC 1951, 3.2.3: stored and compressed
// blocks may alternate).
void Deflate(const unsigned char* in, std::size_t bytes, int level, bool run_length,
             std::size_t planes, std::vector<unsigned char>* out) {
  const int strategy = run_length ? Z_RLE : Z_DEFAULT_STRATEGY;
  z_stream stream{};
  if (deflateInit2(&stream, level, Z_DEFLATED, 15, 8, strategy) != Z_OK) {
    throw std::runtime_error("zlib deflateInit2 failed");
  }
  // Room for the worst case of either kind of block: deflateBound at `level`, and a stored block
  // header (5 bytes) per 16 KiB of input, zlib's smallest stored-block size, with every plane's
  // block ended early (plus its empty end).
  out->resize(deflateBound(&stream, static_cast<uLong>(bytes)) + bytes / 16384 * 5 + 16 * planes +
              64);
  stream.next_out = out->data();
  stream.avail_out = static_cast<uInt>(out->size());
  const std::size_t plane_bytes = planes > 1 ? bytes / planes : bytes;
  int current = level;
  int status = Z_OK;
  for (std::size_t p = 0; p < (planes > 1 ? planes : 1) && status == Z_OK; ++p) {
    const unsigned char* plane = in + p * plane_bytes;
    const int wanted = planes > 1 && IsRandomBytePlane(plane, plane_bytes) ? 0 : level;
    if (wanted != current) {
      if (deflateParams(&stream, wanted, strategy) != Z_OK) {
        deflateEnd(&stream);
        throw std::runtime_error("zlib deflateParams failed");
      }
      current = wanted;
    }
    stream.next_in = const_cast<unsigned char*>(plane);
    stream.avail_in = static_cast<uInt>(plane_bytes);
    status = deflate(&stream, Z_NO_FLUSH);
    if (status == Z_OK && stream.avail_in != 0) status = Z_BUF_ERROR;
  }
  if (status == Z_OK) status = deflate(&stream, Z_FINISH);
  const std::size_t written = out->size() - stream.avail_out;
  deflateEnd(&stream);
  if (status != Z_STREAM_END) throw std::runtime_error("zlib deflate did not finish a chunk");
  out->resize(written);
}

}  // namespace

bool IsRandomBytePlane(const unsigned char* bytes, std::size_t count) {
  if (count < 4096) return false;
  // Z_RLE's matches are runs (distance 1): with at most twice the repeats of independent uniform
  // bytes (1/256 of the positions), runs of 3 or more cover well under 0.1 % of the plane. The
  // count only grows, so a plane is rejected as soon as it has too many (the exponent planes
  // within their first block).
  std::uint32_t histogram[256] = {};
  std::size_t repeats = 0;
  histogram[bytes[0]]++;
  constexpr std::size_t kBlock = 4096;
  for (std::size_t start = 1; start < count; start += kBlock) {
    const std::size_t end = std::min(count, start + kBlock);
    for (std::size_t i = start; i < end; ++i) {
      histogram[bytes[i]]++;
      repeats += bytes[i] == bytes[i - 1];
    }
    if (repeats * 128 > count) return false;
  }
  double entropy_bits = 0.0;
  int used = 0;
  const double total = static_cast<double>(count);
  for (const std::uint32_t h : histogram) {
    if (h == 0) continue;
    ++used;
    const double q = static_cast<double>(h) / total;
    entropy_bits -= q * std::log2(q);
  }
  // The histogram's entropy is low by (used - 1) / (2 count ln 2) bits on average (Miller 1955):
  // 0.045 bits for 4096 uniform bytes, 0.003 for 65536. Corrected, uniform bytes read 8 bits at
  // every plane length. A Huffman code of independent bytes is no shorter than their entropy
  // (Shannon 1948), so deflate could save at most (8 - H) / 8 of the plane: 0.6 % at 7.95 bits.
  entropy_bits += (used - 1) / (2.0 * total * std::log(2.0));
  return entropy_bits >= 7.95;
}

bool ColumnStorage::IsValid(std::string* error) const {
  auto fail = [error](const char* what) {
    if (error) *error = what;
    return false;
  };
  if (type != hdf5::StorageType::kFloat64 && type != hdf5::StorageType::kFloat32) {
    return fail("column storage must be float64 or float32");
  }
  if (chunk_rows < 1) return fail("chunk_rows must be >= 1");
  // One chunk must fit zlib's 32-bit lengths and HDF5's 4 GiB chunk limit.
  if (chunk_rows > (1ull << 26)) return fail("chunk_rows must be <= 2^26");
  if (deflate_level < 0 || deflate_level > 9) return fail("deflate_level must be in 0..9");
  return true;
}

void ShuffleBytes(const unsigned char* in, std::size_t elements, std::size_t element_size,
                  unsigned char* out, std::size_t plane_stride) {
  if (plane_stride == 0) plane_stride = elements;
  for (std::size_t i = 0; i < elements; ++i) {
    const unsigned char* element = in + i * element_size;
    for (std::size_t b = 0; b < element_size; ++b) out[b * plane_stride + i] = element[b];
  }
}

std::vector<unsigned char> EncodeChunk(const double* values, std::size_t rows,
                                       const ColumnStorage& storage) {
  const std::size_t element = ElementBytes(storage.type);
  const std::size_t chunk = storage.chunk_rows;
  const bool filtered = storage.deflate_level > 0;
  // The chunk's bytes as the filters see them, zero past `rows` (once shuffled, the padding of an
  // edge chunk lies at the end of every byte plane). Each value is written once before deflate:
  // straight into place, or, for a shuffled float32 chunk, converted first (HDF5's conversion:
  // round to nearest, static_cast<float>).
  std::vector<unsigned char> bytes(chunk * element, 0);
  const unsigned char* in = reinterpret_cast<const unsigned char*>(values);
  std::vector<float> converted;
  if (storage.type == hdf5::StorageType::kFloat32) {
    if (!filtered) {
      for (std::size_t i = 0; i < rows; ++i) {
        const float v = static_cast<float>(values[i]);
        std::memcpy(bytes.data() + i * 4, &v, 4);
      }
      return bytes;
    }
    converted.assign(values, values + rows);
    in = reinterpret_cast<const unsigned char*>(converted.data());
  } else if (!filtered) {
    std::memcpy(bytes.data(), values, rows * 8);
    return bytes;
  }
  ShuffleBytes(in, rows, element, bytes.data(), chunk);
  std::vector<unsigned char> out;
  Deflate(bytes.data(), bytes.size(), storage.deflate_level, storage.run_length, element, &out);
  return out;
}

namespace {

// Throws std::invalid_argument unless the columns make a dataset.
void CheckShape(const std::string& name, int num_columns, bool matrix,
                const ColumnStorage& storage) {
  std::string error;
  if (!storage.IsValid(&error)) throw std::invalid_argument("fogpipe::io: " + error);
  if (num_columns < 1 || (!matrix && num_columns != 1)) {
    throw std::invalid_argument("fogpipe::io: " + name + ": a vector dataset needs one column");
  }
}

// A small dataset: contiguous, one plain write.
void WriteContiguous(hdf5::Group& group, const std::string& name, int num_columns,
                     const ColumnLoader& load, const std::vector<hsize_t>& dims,
                     const std::string& units, hdf5::StorageType type) {
  const hsize_t n = dims[0];
  const hsize_t k = static_cast<hsize_t>(num_columns);
  hdf5::DatasetOptions plain;
  plain.storage = type;
  plain.deflate_level = 0;
  plain.min_chunked_elements = ~hsize_t{0};
  std::vector<double> data(n * k);
  for (hsize_t c = 0; c < k; ++c) {
    const double* column = load(static_cast<int>(c));
    for (hsize_t r = 0; r < n; ++r) data[r * k + c] = column[r];
  }
  group.WriteDataset(name, data.data(), dims, units, plain);
}
// The layout the chunks are encoded for: [chunk_rows, 1] chunks, shuffle + deflate declared so
// that every reader decodes them (the writes bypass the filters).
hdf5::Dataset CreateChunked(hdf5::Group& group, const std::string& name,
                            const std::vector<hsize_t>& dims, const std::string& units,
                            const ColumnStorage& storage) {
  hdf5::DatasetOptions layout;
  layout.storage = storage.type;
  layout.chunk_rows = storage.chunk_rows;
  layout.deflate_level = storage.deflate_level;
  layout.shuffle = true;
  layout.min_chunked_elements = 0;  // n >= min_chunked_rows: always chunked
  layout.chunk_per_column = true;
  return group.CreateDataset(name, dims, units, layout);
}

// The chunks of one column top to bottom. A pipeline of at most 2 x threads chunks in flight
// (bounded memory: ~1.5 chunk sizes each): encoded in parallel, written one at a time in order
// while the next ones are being encoded. The write may run on a TBB worker thread: it is an HDF5
// C API call (thread-safe in Debian's build), serialized by the serial_in_order filter, while this
// thread holds the fogpipe HDF5 lock for all of it.
void WriteColumnChunks(const hdf5::Dataset& dataset, const double* column, hsize_t n,
                       hsize_t column_index, const ColumnStorage& storage) {
  const hsize_t chunk_rows = storage.chunk_rows;
  const hsize_t total = (n + chunk_rows - 1) / chunk_rows;
  const std::size_t tokens =
      2 * static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  const hid_t dataset_id = dataset.id();
  struct Encoded {
    hsize_t index = 0;
    std::vector<unsigned char> bytes;
  };
  hsize_t next = 0;
  // Isolated: while this thread waits for the pipeline it holds the HDF5 lock, so it must not
  // pick up unrelated work (a reader node takes that lock: it would wait for itself).
  tbb::this_task_arena::isolate([&] {
    tbb::parallel_pipeline(
        tokens,
        tbb::make_filter<void, hsize_t>(tbb::filter_mode::serial_in_order,
                                        [&](tbb::flow_control& control) -> hsize_t {
                                          if (next == total) control.stop();
                                          return next < total ? next++ : 0;
                                        }) &
            tbb::make_filter<hsize_t, Encoded>(
                tbb::filter_mode::parallel,
                [&](hsize_t i) {
                  const hsize_t row0 = i * chunk_rows;
                  return Encoded{
                      i, EncodeChunk(column + row0, std::min(chunk_rows, n - row0), storage)};
                }) &
            tbb::make_filter<Encoded, void>(
                tbb::filter_mode::serial_in_order, [&](const Encoded& chunk) {
                  H5Eset_auto2(H5E_DEFAULT, nullptr,
                               nullptr);  // errors are thrown, not printed
                  const hsize_t row0 = chunk.index * chunk_rows;
                  const hsize_t offset[2] = {row0, column_index};
                  hdf5::detail::CheckC(H5Dwrite_chunk(dataset_id, H5P_DEFAULT, 0, offset,
                                                      chunk.bytes.size(), chunk.bytes.data()),
                                       dataset.file_path(), dataset.path(),
                                       "write chunk at row " + std::to_string(row0));
                }));
  });
}

}  // namespace

void WriteColumnDataset(hdf5::Group& group, const std::string& name, int num_columns,
                        unsigned long long rows, const ColumnLoader& load, bool matrix,
                        const std::string& units, const ColumnStorage& storage) {
  CheckShape(name, num_columns, matrix, storage);
  const hsize_t n = rows;
  const hsize_t k = static_cast<hsize_t>(num_columns);
  const std::vector<hsize_t> dims = matrix ? std::vector<hsize_t>{n, k} : std::vector<hsize_t>{n};
  if (n < storage.min_chunked_rows) {
    WriteContiguous(group, name, num_columns, load, dims, units, storage.type);
    return;
  }
  ColumnStorage effective = storage;
  effective.chunk_rows = std::min<unsigned long long>(storage.chunk_rows, n);
  // Z_RLE buys speed on long records (header of column_datasets.h). A column of one chunk is at
  // most 64 Ki samples, deflated in well under a millisecond either way, and zlib's default
  // strategy stores it 2-3 % smaller (the demo campaign's IMFs: 138 KB instead of 142 KB).
  if (n <= storage.chunk_rows) effective.run_length = false;
  const hdf5::Dataset dataset = CreateChunked(group, name, dims, units, effective);
  // Chunks in file order: column 0 top to bottom, then column 1, ...
  for (hsize_t c = 0; c < k; ++c)
    WriteColumnChunks(dataset, load(static_cast<int>(c)), n, c, effective);
}

void WriteColumnDataset(hdf5::Group& group, const std::string& name,
                        const std::vector<const Eigen::VectorXd*>& columns, bool matrix,
                        const std::string& units, const ColumnStorage& storage) {
  CheckShape(name, static_cast<int>(columns.size()), matrix, storage);
  const hsize_t n = static_cast<hsize_t>(columns[0]->size());
  for (const Eigen::VectorXd* c : columns) {
    if (static_cast<hsize_t>(c->size()) != n) {
      throw std::invalid_argument("fogpipe::io: " + name + ": columns of different lengths");
    }
  }
  WriteColumnDataset(
      group, name, static_cast<int>(columns.size()), n,
      [&columns](int c) { return columns[c]->data(); }, matrix, units, storage);
}

}  // namespace fogpipe::io
