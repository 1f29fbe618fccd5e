// The bad-input corpus: every kind of broken recording, generated here with the raw HDF5 C API
// and file surgery, gives a RecordingError with its own kind and a message that names the file
// and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <set>

#include "pipeline/io/recording_check.h"
#include "pipeline/io/recording_reader.h"
#include "tests/pipeline/io/test_recording_files.h"

namespace fogpipe::io {
namespace {

using testing::Layout;
using testing::RawFile;
using testing::RecordingSpec;

namespace fs = std::filesystem;

/// /rate of n samples from TestValue (optionally edited) in rad/s at 10 Hz.
void WriteRate(const std::string& path, std::vector<double> values, const Layout& layout = {},
               const std::string& units = "rad/s") {
  RawFile file(path);
  file.Dataset("/rate", {values.size()}, values, layout);
  file.StringAttribute("/rate", "units", units);
  file.DoubleAttribute("/", "sample_rate_hz", 10.0);
}

std::vector<double> Signal(int n) {
  std::vector<double> v;
  for (int k = 0; k < n; ++k) v.push_back(testing::TestValue(k, 0));
  return v;
}

/// A good chunked + deflated recording of 4000 samples.
void WriteGoodCompressed(const std::string& path) {
  WriteRate(path, Signal(4000), Layout{H5T_IEEE_F64LE, {1000}, 6, true});
}

void Overwrite(const std::string& path, long long offset, int count, char byte) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(offset);
  for (int i = 0; i < count; ++i) f.put(byte);
}

struct BadCase {
  std::string name;
  std::string kind;
  std::string phrase;  ///< must appear in the message
  std::function<void(const std::string& path)> make;
  std::string axis = "0";
};

std::vector<BadCase> Corpus() {
  using namespace error_kind;
  return {
      {"missing_file", kMissingFile, "no such file", [](const std::string&) {}},
      {"empty_file", kEmptyFile, "is empty (0 bytes)",
       [](const std::string& p) { std::ofstream(p).close(); }},
      {"text_file", kNotHdf5, "not an HDF5 file",
       [](const std::string& p) { std::ofstream(p) << "time,rate\n0,0.1\n0.1,0.2\n"; }},
      {"truncated", kTruncatedFile, "is truncated",
       [](const std::string& p) {
         WriteGoodCompressed(p);
         fs::resize_file(p, fs::file_size(p) / 2);  // an interrupted copy
       }},
      {"corrupt_superblock", kCorruptFile, "damaged HDF5 file",
       [](const std::string& p) {
         WriteGoodCompressed(p);
         Overwrite(p, 8, 16, '\xA5');  // version numbers and sizes after the signature
       }},
      {"corrupt_chunk", kCorruptFile, "damaged data",
       [](const std::string& p) {
         WriteGoodCompressed(p);
         // Find chunk 0 of /rate and overwrite the middle of its deflate stream.
         hid_t f = H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
         hid_t d = H5Dopen2(f, "/rate", H5P_DEFAULT);
         hsize_t offset[1] = {0};
         unsigned mask = 0;
         haddr_t address = 0;
         hsize_t size = 0;
         hid_t space = H5Dget_space(d);
         H5Dget_chunk_info(d, space, 0, offset, &mask, &address, &size);
         H5Sclose(space);
         H5Dclose(d);
         H5Fclose(f);
         ASSERT_GT(size, 64u);
         Overwrite(p, static_cast<long long>(address + size / 2), 32, '\x5A');
       }},
      {"no_rate", kMissingDataset, "has no dataset /rate",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/gyro", {100}, Signal(100));
         file.StringAttribute("/gyro", "units", "rad/s");
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
      {"rate_is_group", kWrongType, "/rate is not a dataset",
       [](const std::string& p) {
         RawFile file(p);
         file.Group("/rate");
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
      {"no_sample_rate", kMissingAttribute, "'sample_rate_hz'",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100}, Signal(100));
         file.StringAttribute("/rate", "units", "rad/s");
       }},
      {"no_units", kMissingAttribute, "/rate has no 'units' attribute",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100}, Signal(100));
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
      {"integer_rate_without_scale_factor", kMissingAttribute,
       "/rate holds integers (int32) but has no 'scale_factor' attribute",
       [](const std::string& p) {
         WriteRate(p, Signal(100), Layout{H5T_STD_I32LE, {}, 0, false});
       }},
      {"integer_rate_with_zero_scale_factor", kBadScaleFactor,
       "/rate attribute 'scale_factor' is 0; it must be a finite, non-zero number",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100}, Signal(100), Layout{H5T_STD_I16LE, {}, 0, false});
         file.StringAttribute("/rate", "units", "rad/s");
         file.DoubleAttribute("/rate", "scale_factor", 0.0);
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
      {"integer_rate_with_nan_scale_factor", kBadScaleFactor, "'scale_factor' is nan",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100}, Signal(100), Layout{H5T_STD_I16LE, {}, 0, false});
         file.StringAttribute("/rate", "units", "rad/s");
         file.DoubleAttribute("/rate", "scale_factor", std::nan(""));
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
      {"string_sample_rate", kWrongType, "'sample_rate_hz' must be one float64",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100}, Signal(100));
         file.StringAttribute("/rate", "units", "rad/s");
         file.StringAttribute("/", "sample_rate_hz", "100 Hz");
       }},
      {"rank_3", kWrongRank, "/rate has rank 3",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {50, 2, 2}, Signal(200));
         file.StringAttribute("/rate", "units", "rad/s");
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
      {"scalar_rate", kWrongRank, "/rate has rank 0",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {}, {1.0});
         file.StringAttribute("/rate", "units", "rad/s");
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
      {"zero_axes", kWrongShape, "no axis at all",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100, 0}, {});
         file.StringAttribute("/rate", "units", "rad/s");
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
      {"unknown_units", kUnknownUnits, "units 'dps'",
       [](const std::string& p) { WriteRate(p, Signal(100), {}, "dps"); }},
      {"zero_sample_rate", kBadSampleRate, "'sample_rate_hz' is 0",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100}, Signal(100));
         file.StringAttribute("/rate", "units", "rad/s");
         file.DoubleAttribute("/", "sample_rate_hz", 0.0);
       }},
      {"nan_sample_rate", kBadSampleRate, "'sample_rate_hz' is nan",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100}, Signal(100));
         file.StringAttribute("/rate", "units", "rad/s");
         file.DoubleAttribute("/", "sample_rate_hz", std::nan(""));
       }},
      {"axes_length", kBadAxes, "names 3 axes but /rate has 2",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100, 2}, Signal(200));
         file.StringAttribute("/rate", "units", "rad/s");
         file.StringArrayAttribute("/rate", "axes", {"x", "y", "z"});
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
      {"axes_repeated", kBadAxes, "repeated or invalid name 'x'",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100, 2}, Signal(200));
         file.StringAttribute("/rate", "units", "rad/s");
         file.StringArrayAttribute("/rate", "axes", {"x", "x"});
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
      {"unknown_axis", kUnknownAxis, "has no axis 'q'",
       [](const std::string& p) { WriteRate(p, Signal(100)); }, "q"},
      {"aux_length", kAuxLengthMismatch, "/aux/temperature has 99 samples but /rate has 100",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100}, Signal(100));
         file.StringAttribute("/rate", "units", "rad/s");
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
         file.Dataset("/aux/temperature", {99}, std::vector<double>(99, 25.0));
         file.StringAttribute("/aux/temperature", "units", "degC");
       }},
      {"aux_no_units", kMissingAttribute, "/aux/temperature has no 'units' attribute",
       [](const std::string& p) {
         RawFile file(p);
         file.Dataset("/rate", {100}, Signal(100));
         file.StringAttribute("/rate", "units", "rad/s");
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
         file.Dataset("/aux/temperature", {100}, std::vector<double>(100, 25.0));
       }},
      {"long_nan_gap", kNanGapTooLong, "run of 11 missing (NaN) samples starting at sample 40",
       [](const std::string& p) {
         std::vector<double> v = Signal(200);
         for (int k = 40; k < 51; ++k) v[k] = std::nan("");
         WriteRate(p, v);
       }},
      {"all_nan", kNanGapTooLong, "every sample is NaN",
       [](const std::string& p) { WriteRate(p, std::vector<double>(100, std::nan(""))); }},
      {"infinite_value", kNonFiniteValue, "1 infinite value(s), the first at sample 17",
       [](const std::string& p) {
         std::vector<double> v = Signal(100);
         v[17] = HUGE_VAL;
         WriteRate(p, v);
       }},
      {"too_few_samples", kTooFewSamples, "has 10 samples",
       [](const std::string& p) { WriteRate(p, Signal(10)); }},
      {"constant", kConstantSignal, "is constant (every sample is 0.25)",
       [](const std::string& p) { WriteRate(p, std::vector<double>(500, 0.25)); }},
      {"unavailable_filter", kUnsupportedCompression, "HDF5 filter 32000",
       [](const std::string& p) {
         // LZF (id 32000) is h5py's own filter: plain libhdf5 cannot decode it. An optional
         // filter can be recorded in the pipeline even though it is not available here.
         RawFile file(p);
         const hsize_t n = 100, chunk = 50;
         hid_t space = H5Screate_simple(1, &n, nullptr);
         hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
         H5Pset_chunk(dcpl, 1, &chunk);
         H5Pset_filter(dcpl, 32000, H5Z_FLAG_OPTIONAL, 0, nullptr);
         hid_t d =
             H5Dcreate2(file.id(), "/rate", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
         const std::vector<double> v = Signal(100);
         H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
         H5Dclose(d);
         H5Pclose(dcpl);
         H5Sclose(space);
         file.StringAttribute("/rate", "units", "rad/s");
         file.DoubleAttribute("/", "sample_rate_hz", 10.0);
       }},
  };
}

// Names the case in ctest output instead of dumping its bytes.
void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class BadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadInput, GivesItsOwnKindAndAMessageNamingTheFileAndTheProblem) {
  const BadCase& c = GetParam();
  testing::TempDir dir;
  const std::string path = dir.File(c.name + ".h5");
  c.make(path);
  if (::testing::Test::HasFatalFailure()) return;
  try {
    const Eigen::VectorXd x = ReadAxisRadPerSecond(path, c.axis);
    FAIL() << c.name << ": no error, read " << x.size() << " samples";
  } catch (const RecordingError& e) {
    std::cout << "[" << e.kind() << "] " << e.what() << "\n";  // the corpus, as users see it
    EXPECT_EQ(e.kind(), c.kind) << e.what();
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(c.phrase), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << c.phrase;
  }
}

INSTANTIATE_TEST_SUITE_P(RecordingReader, BadInput, ::testing::ValuesIn(Corpus()),
                         [](const auto& info) { return info.param.name; });

TEST(BadInputCorpus, CoversAtLeastTenDistinctKinds) {
  std::set<std::string> kinds;
  for (const BadCase& c : Corpus()) kinds.insert(c.kind);
  EXPECT_GE(kinds.size(), 10u);
}

TEST(RecordingReader, NeverModifiesItsInput) {
  testing::TempDir dir;
  const std::string path = dir.File("good.h5");
  WriteGoodCompressed(path);
  const auto before_time = fs::last_write_time(path);
  std::ifstream in(path, std::ios::binary);
  const std::string before((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ReadAxisRadPerSecond(path, "0");
  InspectRecording(path);
  std::ifstream again(path, std::ios::binary);
  const std::string after((std::istreambuf_iterator<char>(again)),
                          std::istreambuf_iterator<char>());
  EXPECT_EQ(before, after);
  EXPECT_EQ(before_time, fs::last_write_time(path));
}

}  // namespace
}  // namespace fogpipe::io
