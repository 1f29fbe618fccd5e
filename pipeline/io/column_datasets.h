// The large datasets of a results file (IMFs, residue, filtered components, method-1 and method-2
// outputs: each N samples, up to ~20 of them per axis) written with the chunks compressed in
// parallel.
//
// Why: HDF5 runs its filter pipeline (shuffle, deflate) serially inside H5Dwrite, under the one
// process-wide HDF5 lock. On a 24 h recording at 100 Hz (8.64e6 samples, 21 IMFs, ~1.7 GB of
// float64) zlib at level 4 took 27 s of the writer's single thread, half of the whole run's CPU
// (perf record, 2026-11-21), for a ratio of only 0.80: the low mantissa bytes of noise are random.
//
// How: each chunk holds ONE column (chunk shape [chunk_rows, 1], or [chunk_rows] for a vector), so
// that reading one IMF inflates only that IMF's chunks. The chunks are encoded in parallel
// exactly as HDF5's filters would store them, byte shuffle (H5Z_FILTER_SHUFFLE) then deflate
// (H5Z_FILTER_DEFLATE, a zlib stream), and written in order with H5Dwrite_chunk (HDF5 >= 1.10.3,
// "direct chunk write"), which stores them as they are. The dataset's creation properties declare
// the same two filters, so every HDF5 reader (h5py, MATLAB, HDFView, h5dump) decodes the chunks
// with its ordinary inflate; nothing fogpipe-specific is needed to read the file. Compression is
// lossless: the values read back are bit-identical to what an H5Dwrite of the same array stores
// (float32 storage: the same round-to-nearest conversion HDF5 applies, static_cast<float>).
//
// zlib strategy: Z_RLE (matches of distance 1 only, Huffman-coded) instead of the default LZ77
// search. After the byte shuffle the compressible part of a float64 noise chunk is the runs of
// equal exponent / high-mantissa bytes, which run-length matching finds; measured on the IMFs of
// that 24 h recording: ratio 0.769 at ~3x the speed of level 4's 0.803 (level 1: 0.812, no
// faster). With one column per chunk the default strategy would give 0.718 at level 4 but at a
// third of the speed. Deflate level 0 stores the chunks uncompressed (and unshuffled).
//
// Random byte planes are stored, not compressed: the low mantissa bytes of noise are independent
// uniform bytes (order-0 entropy 7.997 bits per byte), on which deflate spends about half of its
// time for nothing. Each plane of a shuffled chunk gets its own deflate blocks, stored blocks for
// the planes IsRandomBytePlane accepts and compressed blocks for the others, in one zlib stream
// that every inflate() reads (RFC 1951 lets the two kinds alternate).
//
// Every function requires the caller to hold LockHdf5() and throws hdf5::Error (HDF5) or
// std::runtime_error (zlib). Compression runs in the calling thread's TBB arena, overlapped with
// the writes of the chunks already encoded (tbb::parallel_pipeline); those H5Dwrite_chunk calls
// may run on a TBB worker thread, one at a time, while the caller holds the lock (the HDF5 C
// library is built thread-safe; no C++ wrapper object is touched there).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "pipeline/hdf5/dataset.h"
#include "pipeline/hdf5/group.h"

namespace fogpipe::io {

struct ColumnStorage {
  /// kFloat64 (exact) or kFloat32 (round to nearest).
  hdf5::StorageType type = hdf5::StorageType::kFloat64;
  /// Rows per chunk: 65536 rows = 512 KiB of float64, at most HDF5's default chunk cache (1 MiB),
  /// so a reader never inflates a chunk twice.
  unsigned long long chunk_rows = 65536;
  /// zlib level 1..9, or 0 to store the chunks uncompressed.
  int deflate_level = 1;
  /// zlib strategy Z_RLE (default, see above) instead of Z_DEFAULT_STRATEGY.
  bool run_length = true;
  /// Columns with fewer samples are written contiguous and uncompressed by plain H5Dwrite (the
  /// chunk index and filter messages, ~0.5 KB with hdf5::File's small index nodes, cost more than
  /// deflate saves). From 1024 samples (8 KB of float64) on, compression pays: on the demo
  /// campaign's 3600-sample signals it saves 15 % of the IMFs and up to 99 % of a filtered signal
  /// (docs/performance.md, "Results size").
  unsigned long long min_chunked_rows = 1024;

  bool IsValid(std::string* error) const;
};

/// HDF5's shuffle filter (H5Zshuffle.c) on one chunk: byte b of element i goes to
/// out[b * plane_stride + i] (plane_stride 0: `elements`; a larger one leaves room for the zero
/// padding of an edge chunk of plane_stride elements). `in` holds elements * element_size bytes,
/// `out` element_size * plane_stride, and they do not overlap.
void ShuffleBytes(const unsigned char* in, std::size_t elements, std::size_t element_size,
                  unsigned char* out, std::size_t plane_stride = 0);

/// Whether one byte plane of a shuffled chunk looks like independent uniform bytes, which
/// deflate cannot shrink by more than 0.6 %: an order-0 entropy of at least 7.95 bits per byte
/// and at most 1/128 of the bytes equal to their predecessor. EncodeChunk stores such planes as
/// they are (deflate's stored blocks) instead of spending the compressor's time on them; planes
/// shorter than 4096 bytes are always compressed.
bool IsRandomBytePlane(const unsigned char* bytes, std::size_t count);

/// One chunk of `rows` values (the last chunk of a column may be short: it is padded with zeros
/// to chunk_rows, the dataset's fill value, as HDF5 stores edge chunks) converted to the storage
/// type and encoded by the filter pipeline of ColumnStorage: the bytes H5Dwrite_chunk stores.
std::vector<unsigned char> EncodeChunk(const double* values, std::size_t rows,
                                       const ColumnStorage& storage);

/// Creates `name` with `units` and writes the columns: as [N] when `matrix` is false (then
/// exactly one column), else as [N, K] with column k = *columns[k]. All columns have N samples.
void WriteColumnDataset(hdf5::Group& group, const std::string& name,
                        const std::vector<const Eigen::VectorXd*>& columns, bool matrix,
                        const std::string& units, const ColumnStorage& storage);

/// The samples of column c, loaded when asked (e.g. read back from a scratch file, so that the
/// columns need not all be in memory): a pointer to the dataset's `rows` samples, valid until the
/// next call. The loader checks the length; the writer cannot.
using ColumnLoader = std::function<const double*(int column)>;

/// WriteColumnDataset with `num_columns` columns of `rows` samples each from `load`, called once
/// per column in order.
void WriteColumnDataset(hdf5::Group& group, const std::string& name, int num_columns,
                        unsigned long long rows, const ColumnLoader& load, bool matrix,
                        const std::string& units, const ColumnStorage& storage);

}  // namespace fogpipe::io
