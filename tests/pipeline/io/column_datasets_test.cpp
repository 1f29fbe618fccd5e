// Tests pipeline/io/column_datasets.cpp: chunks compressed by fogpipe and stored with
// H5Dwrite_chunk read back through HDF5's own filter pipeline exactly as an ordinary H5Dwrite
// of the same values would (the reference is HDF5's conversion and filters, not our code).
#include "pipeline/io/column_datasets.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "pipeline/hdf5/file.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "tests/pipeline/io/test_recording_files.h"

namespace fogpipe::io {
namespace {

using fogpipe::testing::TempDir;

bool HasFilter(const hdf5::Dataset& d, H5Z_filter_t filter) {
  const hid_t plist = H5Dget_create_plist(d.id());
  unsigned flags = 0, config = 0;
  size_t nvalues = 0;
  const bool has =
      H5Pget_filter_by_id2(plist, filter, &flags, &nvalues, nullptr, 0, nullptr, &config) >= 0;
  H5Pclose(plist);
  return has;
}

/// Columns of gyro-like noise with different scales and a slow trend (what IMFs look like), and
/// an exact zero and a subnormal to exercise the byte shuffle on unusual bit patterns.
std::vector<Eigen::VectorXd> Columns(int n, int k) {
  std::mt19937_64 rng(42);
  std::vector<Eigen::VectorXd> columns(k, Eigen::VectorXd(n));
  for (int c = 0; c < k; ++c) {
    for (int i = 0; i < n; ++i) {
      const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53 - 0.5;
      columns[c][i] = 1e-5 * std::ldexp(u, -c) + 1e-7 * std::sin(1e-4 * i * (c + 1));
    }
  }
  columns[0][3] = 0.0;
  columns[0][4] = 4.9e-324;
  return columns;
}

std::vector<const Eigen::VectorXd*> Pointers(const std::vector<Eigen::VectorXd>& columns) {
  std::vector<const Eigen::VectorXd*> out;
  for (const auto& c : columns) out.push_back(&c);
  return out;
}

class ColumnDatasetsTest : public ::testing::Test {
 protected:
  void SetUp() override { hdf5::SilenceHdf5ErrorPrinter(); }

  /// Creates `name` in a new file, lets `write` fill its root, and reopens it read-only. The
  /// caller holds the HDF5 lock.
  template <typename Write>
  hdf5::File WriteAndReopen(const std::string& name, Write&& write) {
    const std::string path = dir_.File(name);
    {
      hdf5::File file = hdf5::File::Create(path);
      hdf5::Group root = file.Root();
      write(root);
    }
    return hdf5::File::OpenReadOnly(path);
  }

  TempDir dir_;
};

TEST(ShuffleBytes, PutsByteBOfElementIAtBTimesElementsPlusI) {
  const unsigned char in[] = {0, 1, 2, 3, 10, 11, 12, 13, 20, 21, 22, 23};  // 3 elements of 4
  unsigned char out[12];
  ShuffleBytes(in, 3, 4, out);
  const unsigned char expected[] = {0, 10, 20, 1, 11, 21, 2, 12, 22, 3, 13, 23};
  for (int i = 0; i < 12; ++i) EXPECT_EQ(out[i], expected[i]) << i;
  // An edge chunk of 5 elements holding 3: each byte plane is 5 long, its last 2 bytes untouched
  // (the zero padding EncodeChunk leaves there).
  unsigned char padded[20] = {};
  ShuffleBytes(in, 3, 4, padded, 5);
  const unsigned char planes[] = {0, 10, 20, 0, 0, 1, 11, 21, 0, 0,
                                  2, 12, 22, 0, 0, 3, 13, 23, 0, 0};
  for (int i = 0; i < 20; ++i) EXPECT_EQ(padded[i], planes[i]) << i;
}

std::vector<unsigned char> UniformBytes(std::size_t count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<unsigned char> bytes(count);
  for (auto& b : bytes) b = static_cast<unsigned char>(rng() >> 56);
  return bytes;
}

TEST(IsRandomBytePlane, AcceptsIndependentUniformBytesAtEveryPlaneLength) {
  // Storing such a plane costs nothing in size; the threshold (7.95 corrected bits) sits about
  // 0.05 bits below where uniform bytes read, many times their spread (O(1 / count) bits).
  int accepted = 0, trials = 0;
  for (const std::size_t count : {std::size_t{4096}, std::size_t{65536}}) {
    for (std::uint64_t seed = 1; seed <= 100; ++seed, ++trials) {
      const auto bytes = UniformBytes(count, seed);
      accepted += IsRandomBytePlane(bytes.data(), count);
    }
  }
  EXPECT_EQ(accepted, trials);
}

TEST(IsRandomBytePlane, RejectsPlanesDeflateCanShrink) {
  const std::size_t count = 65536;
  // Seven bits of entropy: Huffman saves 1/8 of the plane.
  auto seven_bits = UniformBytes(count, 7);
  for (auto& b : seven_bits) b &= 0x7f;
  EXPECT_FALSE(IsRandomBytePlane(seven_bits.data(), count));
  // A flat histogram (8 bits) in runs of three: the run-length matches Z_RLE codes.
  std::vector<unsigned char> runs(count);
  for (std::size_t i = 0; i < count; ++i) runs[i] = static_cast<unsigned char>((i / 3) * 97);
  EXPECT_FALSE(IsRandomBytePlane(runs.data(), count));
  // Uniform bytes with such runs only in the last 2048: 1365 repeats, above the 512 allowed, all
  // after the first blocks were judged.
  auto late_runs = UniformBytes(count, 8);
  for (std::size_t i = count - 2048; i < count; ++i)
    late_runs[i] = static_cast<unsigned char>((i / 3) * 97);
  EXPECT_FALSE(IsRandomBytePlane(late_runs.data(), count));
  // The exponent byte of noise of one scale: a handful of values.
  std::vector<unsigned char> exponent(count);
  for (std::size_t i = 0; i < count; ++i) exponent[i] = 0x3e + (i % 7 == 0);
  EXPECT_FALSE(IsRandomBytePlane(exponent.data(), count));
  // Too short to judge: always compressed.
  const auto short_plane = UniformBytes(4095, 1);
  EXPECT_FALSE(IsRandomBytePlane(short_plane.data(), short_plane.size()));
}

TEST(EncodeChunk, IsAZlibStreamOfTheShuffledChunkNoLargerThanZlibOfTheWholeChunk) {
  // The reference is zlib itself: one deflate of the whole shuffled chunk at the same level and
  // strategy, and zlib's own uncompress() as the decoder.
  const std::size_t rows = 65536;
  for (const auto type : {hdf5::StorageType::kFloat64, hdf5::StorageType::kFloat32}) {
    const std::size_t element = type == hdf5::StorageType::kFloat32 ? 4 : 8;
    const auto columns = Columns(static_cast<int>(rows), 4);
    for (const auto& column : columns) {
      ColumnStorage storage;
      storage.type = type;
      const std::vector<unsigned char> encoded = EncodeChunk(column.data(), rows, storage);
      std::vector<unsigned char> raw(rows * element);
      if (type == hdf5::StorageType::kFloat32) {
        std::vector<float> f(column.data(), column.data() + rows);
        std::memcpy(raw.data(), f.data(), raw.size());
      } else {
        std::memcpy(raw.data(), column.data(), raw.size());
      }
      std::vector<unsigned char> shuffled(raw.size());
      ShuffleBytes(raw.data(), rows, element, shuffled.data());

      // The noise's low mantissa bytes are random planes: the stored blocks are exercised.
      int random_planes = 0;
      for (std::size_t b = 0; b < element; ++b) {
        random_planes += IsRandomBytePlane(shuffled.data() + b * rows, rows);
      }
      EXPECT_GE(random_planes, 1) << element;
      EXPECT_LT(random_planes, static_cast<int>(element)) << element;

      std::vector<unsigned char> decoded(raw.size());
      uLongf decoded_size = static_cast<uLongf>(decoded.size());
      ASSERT_EQ(uncompress(decoded.data(), &decoded_size, encoded.data(),
                           static_cast<uLong>(encoded.size())),
                Z_OK);
      ASSERT_EQ(decoded_size, decoded.size());
      EXPECT_EQ(decoded, shuffled);

      z_stream stream{};
      ASSERT_EQ(deflateInit2(&stream, storage.deflate_level, Z_DEFLATED, 15, 8, Z_RLE), Z_OK);
      std::vector<unsigned char> whole(deflateBound(&stream, static_cast<uLong>(raw.size())));
      stream.next_in = shuffled.data();
      stream.avail_in = static_cast<uInt>(shuffled.size());
      stream.next_out = whole.data();
      stream.avail_out = static_cast<uInt>(whole.size());
      ASSERT_EQ(deflate(&stream, Z_FINISH), Z_STREAM_END);
      const std::size_t whole_size = whole.size() - stream.avail_out;
      deflateEnd(&stream);
      // Each stored plane may be 0.6 % of itself larger than deflate's best (IsRandomBytePlane),
      // plus 5 bytes per stored block of at most 64 KiB and a few bytes per switch of level.
      const double bound = static_cast<double>(whole_size) +
                           0.006 * static_cast<double>(rows) * static_cast<double>(element) +
                           16.0 * static_cast<double>(element) + 5.0 * element * 2;
      EXPECT_LE(static_cast<double>(encoded.size()), bound) << element << " " << whole_size;
    }
  }
}

TEST_F(ColumnDatasetsTest, Float64ColumnsReadBackBitIdenticalThroughHdf5sFilters) {
  // 3 chunks per column, the last one short (an edge chunk padded by the writer).
  const int n = 2 * 4096 + 1234, k = 5;
  const auto columns = Columns(n, k);
  ColumnStorage storage;
  storage.chunk_rows = 4096;
  auto lock = hdf5::LockHdf5();
  const hdf5::File file = WriteAndReopen("f64.h5", [&](hdf5::Group& root) {
    WriteColumnDataset(root, "imfs", Pointers(columns), true, "rad/s", storage);
    WriteColumnDataset(root, "residue", {&columns[1]}, false, "rad/s", storage);
  });
  const hdf5::Dataset imfs = file.Root().OpenDataset("imfs");
  EXPECT_EQ(imfs.dims(), (std::vector<hsize_t>{static_cast<hsize_t>(n), k}));
  EXPECT_EQ(imfs.chunk_dims(), (std::vector<hsize_t>{4096, 1}));
  EXPECT_TRUE(HasFilter(imfs, H5Z_FILTER_SHUFFLE));
  EXPECT_TRUE(HasFilter(imfs, H5Z_FILTER_DEFLATE));
  EXPECT_EQ(imfs.ReadStringAttribute("units"), "rad/s");
  EXPECT_EQ(imfs.type().size_bytes, 8u);
  const std::vector<double> back = imfs.ReadDoubles();
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < k; ++c) {
      ASSERT_EQ(std::memcmp(&back[i * k + c], &columns[c][i], 8), 0) << i << "," << c;
    }
  }
  const hdf5::Dataset residue = file.Root().OpenDataset("residue");
  EXPECT_EQ(residue.chunk_dims(), (std::vector<hsize_t>{4096}));
  const std::vector<double> r = residue.ReadDoubles();
  ASSERT_EQ(r.size(), static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) ASSERT_EQ(std::memcmp(&r[i], &columns[1][i], 8), 0) << i;
}

TEST_F(ColumnDatasetsTest, Float32ColumnsEqualHdf5sOwnConversionOfTheSameValues) {
  const int n = 5000, k = 3;
  const auto columns = Columns(n, k);
  std::vector<double> row_major(n * k);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < k; ++c) row_major[i * k + c] = columns[c][i];
  ColumnStorage storage;
  storage.type = hdf5::StorageType::kFloat32;
  storage.chunk_rows = 1024;
  const std::string path = dir_.File("f32.h5");
  auto lock = hdf5::LockHdf5();
  {
    hdf5::File file = hdf5::File::Create(path);
    hdf5::Group root = file.Root();
    WriteColumnDataset(root, "ours", Pointers(columns), true, "rad/s", storage);
    hdf5::DatasetOptions reference;  // HDF5 converts double -> float and filters itself
    reference.storage = hdf5::StorageType::kFloat32;
    root.WriteDataset("hdf5", row_major.data(), {static_cast<hsize_t>(n), k}, "rad/s", reference);
  }
  hdf5::File file = hdf5::File::OpenReadOnly(path);
  const hdf5::Dataset ours = file.Root().OpenDataset("ours");
  EXPECT_EQ(ours.type().size_bytes, 4u);
  const std::vector<double> a = ours.ReadDoubles();
  const std::vector<double> b = file.Root().OpenDataset("hdf5").ReadDoubles();
  ASSERT_EQ(a.size(), b.size());
  int differing = 0;
  for (size_t i = 0; i < a.size(); ++i) differing += std::memcmp(&a[i], &b[i], 8) != 0;
  EXPECT_EQ(differing, 0);
}

TEST_F(ColumnDatasetsTest, DeflateLevelZeroStoresUnfilteredChunksThatReadBackExactly) {
  const int n = 9000, k = 2;
  const auto columns = Columns(n, k);
  ColumnStorage storage;
  storage.deflate_level = 0;
  storage.chunk_rows = 4096;
  auto lock = hdf5::LockHdf5();
  const hdf5::File file = WriteAndReopen("raw.h5", [&](hdf5::Group& root) {
    WriteColumnDataset(root, "x", Pointers(columns), true, "rad/s", storage);
  });
  const hdf5::Dataset x = file.Root().OpenDataset("x");
  EXPECT_FALSE(HasFilter(x, H5Z_FILTER_SHUFFLE));
  EXPECT_FALSE(HasFilter(x, H5Z_FILTER_DEFLATE));
  const std::vector<double> back = x.ReadDoubles();
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < k; ++c) ASSERT_EQ(back[i * k + c], columns[c][i]);
}

TEST_F(ColumnDatasetsTest, ShortColumnsAreContiguousAndExact) {
  const int n = 100, k = 3;
  const auto columns = Columns(n, k);
  auto lock = hdf5::LockHdf5();
  const hdf5::File file = WriteAndReopen("short.h5", [&](hdf5::Group& root) {
    WriteColumnDataset(root, "x", Pointers(columns), true, "rad/s", ColumnStorage());
  });
  const hdf5::Dataset x = file.Root().OpenDataset("x");
  EXPECT_TRUE(x.chunk_dims().empty());
  EXPECT_EQ(x.ReadStringAttribute("units"), "rad/s");
  const std::vector<double> back = x.ReadDoubles();
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < k; ++c) ASSERT_EQ(back[i * k + c], columns[c][i]);
}

TEST_F(ColumnDatasetsTest, RejectsColumnsOfDifferentLengthsAndBadOptions) {
  const auto columns = Columns(5000, 2);
  const Eigen::VectorXd shorter = columns[0].head(4000);
  auto lock = hdf5::LockHdf5();
  hdf5::File file = hdf5::File::Create(dir_.File("bad.h5"));
  hdf5::Group root = file.Root();
  EXPECT_THROW(WriteColumnDataset(root, "a", {&columns[0], &shorter}, true, "rad/s", {}),
               std::invalid_argument);
  EXPECT_THROW(WriteColumnDataset(root, "b", Pointers(columns), false, "rad/s", {}),
               std::invalid_argument);
  ColumnStorage bad;
  bad.deflate_level = 10;
  std::string error;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_THROW(WriteColumnDataset(root, "c", {&columns[0]}, false, "rad/s", bad),
               std::invalid_argument);
}

}  // namespace
}  // namespace fogpipe::io
