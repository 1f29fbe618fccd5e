// Tests pipeline/io/column_datasets.cpp: chunks compressed by fogpipe and stored with
// H5Dwrite_chunk read back through HDF5's own filter pipeline exactly as an ordinary H5Dwrite
// of the same values would (the reference is HDF5's conversion and filters, not our code).
#include "pipeline/io/column_datasets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
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
