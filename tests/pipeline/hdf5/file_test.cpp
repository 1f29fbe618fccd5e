// Tests of pipeline/hdf5: File, Group, Dataset and attributes round-trip exactly, datasets get
// chunking, shuffle, deflate and units, hyperslab reads return the right block.
#include "pipeline/hdf5/file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "pipeline/hdf5/hdf5_lock.h"
#include "tests/pipeline/io/test_recording_files.h"

namespace fogpipe::hdf5 {
namespace {

using fogpipe::testing::TempDir;

/// The filters in a dataset's pipeline, read with the C API.
std::vector<H5Z_filter_t> Filters(const Dataset& d) {
  std::vector<H5Z_filter_t> filters;
  hid_t plist = H5Dget_create_plist(d.id());
  const int n = H5Pget_nfilters(plist);
  for (int i = 0; i < n; ++i) {
    unsigned flags = 0, config = 0;
    size_t nvalues = 0;
    filters.push_back(H5Pget_filter2(plist, i, &flags, &nvalues, nullptr, 0, nullptr, &config));
  }
  H5Pclose(plist);
  return filters;
}

class Hdf5Test : public ::testing::Test {
 protected:
  void SetUp() override { SilenceHdf5ErrorPrinter(); }
  TempDir dir_;
};

TEST_F(Hdf5Test, AttributesOfEveryKindRoundTripExactly) {
  const std::string path = dir_.File("attrs.h5");
  auto lock = LockHdf5();
  {
    File file = File::Create(path);
    Group root = file.Root();
    root.WriteDoubleAttribute("rate", 0.1 + 0.2);
    root.WriteInt64Attribute("count", -9007199254740993LL);  // not representable in double
    root.WriteStringAttribute("name", "gyro \xC2\xB0 UTF-8");
    root.WriteStringArrayAttribute("axes", {"x", "y", "zeta"});
    root.WriteDoubleArrayAttribute("taus", {0.5, 1.0, 2.0});
    root.WriteInt64ArrayAttribute("m", {1, 2, 4});
    root.WriteDoubleAttribute("rate", 1.25);  // replaces
    file.Close();
  }
  File file = File::OpenReadOnly(path);
  const Group root = file.Root();
  EXPECT_EQ(root.ReadDoubleAttribute("rate"), 1.25);
  EXPECT_EQ(root.ReadInt64Attribute("count"), -9007199254740993LL);
  EXPECT_EQ(root.ReadStringAttribute("name"), "gyro \xC2\xB0 UTF-8");
  EXPECT_EQ(root.ReadStringArrayAttribute("axes"), (std::vector<std::string>{"x", "y", "zeta"}));
  EXPECT_EQ(root.ReadDoubleArrayAttribute("taus"), (std::vector<double>{0.5, 1.0, 2.0}));
  EXPECT_EQ(root.ReadDoubleArrayAttribute("m"), (std::vector<double>{1, 2, 4}));
  EXPECT_TRUE(root.HasAttribute("m"));
  EXPECT_FALSE(root.HasAttribute("nope"));
  const AttributeInfo axes = root.DescribeAttribute("axes");
  EXPECT_EQ(axes.type.type_class, TypeClass::kString);
  EXPECT_TRUE(axes.type.variable_length_string);
  EXPECT_EQ(axes.dims, (std::vector<hsize_t>{3}));
  EXPECT_TRUE(root.DescribeAttribute("rate").dims.empty());
  EXPECT_EQ(root.AttributeNames().size(), 6u);
}

TEST_F(Hdf5Test, NumericDatasetsCarryUnitsAndAreChunkedShuffledAndDeflated) {
  const std::string path = dir_.File("data.h5");
  Eigen::VectorXd x(10000);
  for (int k = 0; k < x.size(); ++k) x[k] = std::sin(0.001 * k * k) / 3.0;
  auto lock = LockHdf5();
  {
    File file = File::Create(path);
    Group root = file.Root();
    Group imfs = root.CreateGroup("axes/x/decomposition");
    imfs.WriteDataset("imf_0", x, "rad/s");
    DatasetOptions f32;
    f32.storage = StorageType::kFloat32;
    imfs.WriteDataset("imf_0_f32", x, "rad/s", f32);
    root.WriteDataset("small", std::vector<double>{1.0, 2.0, 3.0}, "s");
    root.WriteDataset("indices", std::vector<long long>{3, 1, 4, 1, 5}, "samples");
    root.WriteTextDataset("config", "threads = 2\n");
    root.WriteStringDataset("names", {"a", "bb"});
    file.Close();
  }
  File file = File::OpenReadOnly(path);
  const Group root = file.Root();
  EXPECT_EQ(root.KindOf("axes/x/decomposition"), ObjectKind::kGroup);
  EXPECT_EQ(root.KindOf("/axes/x/decomposition/imf_0"), ObjectKind::kDataset);
  EXPECT_EQ(root.KindOf("axes/y/decomposition"), ObjectKind::kMissing);
  EXPECT_EQ(root.ChildNames(),
            (std::vector<std::string>{"axes", "config", "indices", "names", "small"}));
  const Dataset imf = root.OpenDataset("axes/x/decomposition/imf_0");
  EXPECT_EQ(imf.ReadStringAttribute("units"), "rad/s");
  EXPECT_EQ(imf.type().type_class, TypeClass::kFloat);
  EXPECT_EQ(imf.type().size_bytes, 8u);
  EXPECT_FALSE(imf.chunk_dims().empty());
  EXPECT_EQ(Filters(imf), (std::vector<H5Z_filter_t>{H5Z_FILTER_SHUFFLE, H5Z_FILTER_DEFLATE}));
  const std::vector<double> back = imf.ReadDoubles();
  for (int k = 0; k < x.size(); ++k) ASSERT_EQ(back[k], x[k]) << k;
  const Dataset f32 = root.OpenDataset("axes/x/decomposition/imf_0_f32");
  EXPECT_EQ(f32.type().size_bytes, 4u);
  EXPECT_EQ(f32.ReadDoubles()[777], static_cast<double>(static_cast<float>(x[777])));
  const Dataset small = root.OpenDataset("small");
  EXPECT_TRUE(small.chunk_dims().empty());  // below min_chunked_elements: contiguous
  EXPECT_EQ(small.ReadStringAttribute("units"), "s");
  EXPECT_EQ(root.OpenDataset("indices").ReadInt64s(), (std::vector<long long>{3, 1, 4, 1, 5}));
  EXPECT_EQ(root.OpenDataset("config").ReadStrings(), (std::vector<std::string>{"threads = 2\n"}));
  EXPECT_EQ(root.OpenDataset("names").ReadStrings(), (std::vector<std::string>{"a", "bb"}));
}

TEST_F(Hdf5Test, ATableIsOneCompactCompoundDatasetWhoseFieldsReadBackExactly) {
  const std::string path = dir_.File("table.h5");
  const double nan = std::nan("");
  auto lock = LockHdf5();
  {
    File file = File::Create(path);
    Group root = file.Root();
    root.WriteTable("terms", {TableColumn::Strings("name", {"Q", "N", "B"}),
                              TableColumn::Doubles("value", {0.1 + 0.2, nan, -1e-300}),
                              TableColumn::Int64s("reliable", {1, 0, -9007199254740993LL}),
                              TableColumn::Strings("reason", {"", "slope Â° read-off", ""})});
    EXPECT_THROW(root.WriteTable("ragged", {TableColumn::Doubles("a", {1.0, 2.0}),
                                            TableColumn::Int64s("b", {1})}),
                 std::invalid_argument);
    file.Close();
  }
  File file = File::OpenReadOnly(path);
  const Dataset t = file.Root().OpenDataset("terms");
  EXPECT_EQ(t.type().type_class, TypeClass::kCompound);
  EXPECT_EQ(t.dims(), (std::vector<hsize_t>{3}));
  std::vector<std::string> names;
  for (const auto& field : t.Fields()) names.push_back(field.first);
  EXPECT_EQ(names, (std::vector<std::string>{"name", "value", "reliable", "reason"}));
  EXPECT_EQ(t.Fields()[2].second.type_class, TypeClass::kInteger);
  EXPECT_EQ(t.ReadFieldStrings("name"), (std::vector<std::string>{"Q", "N", "B"}));
  const std::vector<double> value = t.ReadFieldDoubles("value");
  EXPECT_EQ(value[0], 0.1 + 0.2);
  EXPECT_TRUE(std::isnan(value[1]));
  EXPECT_EQ(value[2], -1e-300);
  EXPECT_EQ(t.ReadFieldInt64s("reliable"), (std::vector<long long>{1, 0, -9007199254740993LL}));
  EXPECT_EQ(t.ReadFieldStrings("reason"), (std::vector<std::string>{"", "slope Â° read-off", ""}));
  EXPECT_THROW(t.ReadFieldDoubles("missing"), Error);
  EXPECT_THROW(t.ReadFieldInt64s("value"), Error);
  EXPECT_THROW(t.ReadFieldDoubles("name"), Error);
  // Compact: the rows live in the object header, no data block of their own.
  hid_t plist = H5Dget_create_plist(t.id());
  EXPECT_EQ(H5Pget_layout(plist), H5D_COMPACT);
  H5Pclose(plist);
}

TEST_F(Hdf5Test, WritingANumericDatasetWithoutUnitsIsAProgrammingError) {
  auto lock = LockHdf5();
  File file = File::Create(dir_.File("u.h5"));
  Group root = file.Root();
  EXPECT_THROW(root.WriteDataset("x", std::vector<double>{1.0}, ""), std::invalid_argument);
}

TEST_F(Hdf5Test, ReadsColumnsAndRowBlocksOfAMatrixByHyperslab) {
  const std::string path = dir_.File("m.h5");
  const hsize_t n = 1000, a = 3;
  std::vector<double> m(n * a);
  for (hsize_t i = 0; i < n * a; ++i) m[i] = static_cast<double>(i) * 0.5;
  auto lock = LockHdf5();
  {
    File file = File::Create(path);
    Group root = file.Root();
    DatasetOptions options;
    options.chunk_rows = 64;
    options.min_chunked_elements = 0;  // 3000 values would otherwise be stored contiguous
    Dataset d = root.CreateDataset("rate", {n, a}, "deg/s", options);
    d.WriteRows(0, 500, m.data());
    d.WriteRows(500, 500, m.data() + 500 * a);
    file.Close();
  }
  File file = File::OpenReadOnly(path);
  const Dataset d = file.Root().OpenDataset("rate");
  EXPECT_EQ(d.dims(), (std::vector<hsize_t>{n, a}));
  EXPECT_EQ(d.chunk_dims(), (std::vector<hsize_t>{64, a}));
  std::vector<double> column(100);
  d.ReadColumn(2, 900, 100, column.data());
  for (hsize_t k = 0; k < 100; ++k) ASSERT_EQ(column[k], m[(900 + k) * a + 2]);
  std::vector<double> rows(10 * a);
  d.ReadRows(13, 10, rows.data());
  for (hsize_t k = 0; k < 10 * a; ++k) ASSERT_EQ(rows[k], m[13 * a + k]);
  EXPECT_THROW(d.ReadColumn(3, 0, 1, column.data()), Error);
  EXPECT_THROW(d.ReadColumn(0, 990, 11, column.data()), Error);
}

// DatasetOptions::chunk_per_column: [rows, 1] chunks (the results file's IMFs), with the automatic
// row count sized for one column (512 KiB / 8 bytes = 65536 rows) instead of a whole row (16384
// rows of 4 values); the data round-trips through the shuffle + deflate filters unchanged.
TEST_F(Hdf5Test, ChunkPerColumnGivesChunksOfOneColumn) {
  const std::string path = dir_.File("columns.h5");
  const hsize_t n = 100000, a = 4;
  std::vector<double> m(n * a);
  for (hsize_t i = 0; i < n * a; ++i) m[i] = std::sin(0.001 * static_cast<double>(i));
  auto lock = LockHdf5();
  {
    File file = File::Create(path);
    Group root = file.Root();
    DatasetOptions options;
    options.chunk_per_column = true;
    root.WriteDataset("columns", m.data(), {n, a}, "rad/s", options);
    root.WriteDataset("rows", m.data(), {n, a}, "rad/s");
    options.chunk_rows = 1000;
    root.WriteDataset("vector", m.data(), {n}, "rad/s", options);
    file.Close();
  }
  File file = File::OpenReadOnly(path);
  const Dataset columns = file.Root().OpenDataset("columns");
  EXPECT_EQ(columns.chunk_dims(), (std::vector<hsize_t>{65536, 1}));
  EXPECT_EQ(Filters(columns), (std::vector<H5Z_filter_t>{H5Z_FILTER_SHUFFLE, H5Z_FILTER_DEFLATE}));
  EXPECT_EQ(columns.ReadDoubles(), m);
  EXPECT_EQ(file.Root().OpenDataset("rows").chunk_dims(), (std::vector<hsize_t>{16384, a}));
  EXPECT_EQ(file.Root().OpenDataset("vector").chunk_dims(), (std::vector<hsize_t>{1000}));
}

TEST_F(Hdf5Test, ErrorsNameTheFileTheObjectTheOperationAndCarryTheHdf5Stack) {
  const std::string path = dir_.File("e.h5");
  auto lock = LockHdf5();
  {
    File file = File::Create(path);
    file.Root().CreateGroup("g");
    file.Close();
  }
  File file = File::OpenReadOnly(path);
  try {
    file.Root().OpenDataset("g/missing");
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.object(), "/g/missing");
    EXPECT_EQ(e.operation(), "open dataset");
    EXPECT_NE(e.hdf5_stack().find("H5Dopen2"), std::string::npos) << e.hdf5_stack();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("HDF5 error stack"), std::string::npos);
  }
}

TEST_F(Hdf5Test, FilesOpenedReadOnlyRefuseWrites) {
  const std::string path = dir_.File("ro.h5");
  auto lock = LockHdf5();
  {
    File file = File::Create(path);
    file.Close();
  }
  File file = File::OpenReadOnly(path);
  Group root = file.Root();
  EXPECT_THROW(root.WriteDoubleAttribute("x", 1.0), Error);
  EXPECT_THROW(root.CreateGroup("g"), Error);
}

TEST_F(Hdf5Test, CreateRefusesToOverwriteUnlessAsked) {
  const std::string path = dir_.File("twice.h5");
  auto lock = LockHdf5();
  File::Create(path).Close();
  EXPECT_THROW(File::Create(path), Error);
  EXPECT_NO_THROW(File::Create(path, /*overwrite=*/true).Close());
}

}  // namespace
}  // namespace fogpipe::hdf5
