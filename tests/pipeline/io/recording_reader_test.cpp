// Tests of pipeline/io/recording_reader: every accepted variant of contract v1 reads back exactly.
#include "pipeline/io/recording_reader.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <thread>

#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/recording_check.h"
#include "tests/pipeline/io/test_recording_files.h"

namespace fogpipe::io {
namespace {

using testing::Layout;
using testing::RecordingSpec;
using testing::TempDir;

constexpr double kPi = 3.14159265358979323846;

// Conversion factors written out from their definitions (not taken from units.h).
double ExpectedFactor(const std::string& unit) {
  if (unit == "rad/s") return 1.0;
  if (unit == "deg/s") return kPi / 180.0;
  return kPi / 180.0 / 3600.0;  // deg/h
}

struct Variant {
  std::string name;
  bool two_dimensional;
  int axes;
  hid_t file_type;
  Layout layout;
  std::string units;
  bool temperature;
};

std::vector<Variant> AllVariants() {
  std::vector<Variant> variants;
  const std::vector<std::pair<std::string, Layout>> layouts = {
      {"contiguous", Layout{}},
      {"chunked", Layout{H5T_IEEE_F64LE, {128}, 0, false}},
      {"deflate", Layout{H5T_IEEE_F64LE, {100}, 6, false}},
      {"shuffle_deflate", Layout{H5T_IEEE_F64LE, {333}, 4, true}},
  };
  const std::vector<std::string> units = {"deg/h", "deg/s", "rad/s"};
  int i = 0;
  for (bool two_d : {false, true}) {
    for (hid_t type : {H5T_IEEE_F64LE, H5T_IEEE_F32LE}) {
      for (const auto& [layout_name, layout] : layouts) {
        const std::string unit = units[i % 3];
        const int axes = two_d ? 1 + (i % 3) : 1;
        Variant v{std::string(two_d ? "2d" : "1d") + "_" +
                      (type == H5T_IEEE_F32LE ? "f32" : "f64") + "_" + layout_name + "_" +
                      std::to_string(axes) + "axes_" +
                      (unit == "deg/h"   ? "degh"
                       : unit == "deg/s" ? "degs"
                                         : "rads"),
                  two_d,
                  axes,
                  type,
                  layout,
                  unit,
                  i % 2 == 0};
        v.layout.file_type = type;
        if (two_d && !v.layout.chunk.empty()) v.layout.chunk.push_back(axes);
        variants.push_back(v);
        ++i;
      }
    }
  }
  return variants;
}

void PrintTo(const Variant& v, std::ostream* os) { *os << v.name; }

class EveryContractVariant : public ::testing::TestWithParam<Variant> {};

TEST_P(EveryContractVariant, ReadsBackExactlyAndConvertsUnits) {
  const Variant& v = GetParam();
  TempDir dir;
  const std::string path = dir.File(v.name + ".h5");
  RecordingSpec spec;
  spec.samples = 1001;  // not a multiple of any chunk: exercises the last partial block
  spec.axes = v.axes;
  spec.two_dimensional = v.two_dimensional;
  spec.units = v.units;
  spec.layout = v.layout;
  spec.temperature = v.temperature;
  if (v.axes == 3) spec.axis_names = {"x", "y", "z"};
  const std::vector<double> written = testing::WriteRecording(path, spec);

  const RecordingInfo info = InspectRecording(path);
  EXPECT_EQ(info.samples, 1001);
  EXPECT_EQ(info.axis_count, v.axes);
  EXPECT_EQ(info.two_dimensional, v.two_dimensional);
  EXPECT_EQ(info.rate_units, v.units);
  EXPECT_EQ(info.rate_dtype, v.file_type == H5T_IEEE_F32LE ? "float32" : "float64");
  EXPECT_EQ(info.sample_rate_hz, 10.0);
  EXPECT_EQ(info.instrument.value_or(""), "test gyro");
  EXPECT_EQ(info.serial.value_or(""), "SN-0001");
  EXPECT_EQ(info.start_time_utc.value_or(""), "2026-03-01T08:00:00Z");
  EXPECT_EQ(info.latitude_deg.value_or(0.0), 48.5);
  EXPECT_EQ(info.rate_chunk.empty(), v.layout.chunk.empty());
  ASSERT_EQ(info.aux.size(), v.temperature ? 1u : 0u);

  auto lock = hdf5::LockHdf5();
  RecordingReader reader(path);
  ReadOptions options;
  options.block_rows = 77;  // many small hyperslabs (rounded up to whole chunks when chunked)
  for (int a = 0; a < v.axes; ++a) {
    ReadReport report;
    const Eigen::VectorXd native = reader.ReadAxisNative(a, options, &report);
    const Eigen::VectorXd si = reader.ReadAxisRadPerSecond(a, options);
    EXPECT_GE(report.blocks_read, 2);
    ASSERT_EQ(native.size(), 1001);
    for (long long k = 0; k < 1001; ++k) {
      double expected = written[k * v.axes + a];
      // float32 storage: the file holds the nearest float, exactly representable in double.
      if (v.file_type == H5T_IEEE_F32LE)
        expected = static_cast<double>(static_cast<float>(expected));
      ASSERT_EQ(native[k], expected) << "axis " << a << " sample " << k;
      // One rounding of the product: |error| <= 0.5 ulp, tested at 1 ulp of slack.
      ASSERT_NEAR(si[k], expected * ExpectedFactor(v.units),
                  std::abs(expected * ExpectedFactor(v.units)) * 2.3e-16)
          << "axis " << a << " sample " << k;
    }
  }
  if (v.axes == 3) {
    EXPECT_EQ(reader.AxisIndex("z"), 2);
    EXPECT_EQ(reader.ReadAxisNative(reader.AxisIndex("y"))[5], reader.ReadAxisNative(1)[5]);
  }
  if (v.temperature) {
    const Eigen::VectorXd t = reader.ReadAux("temperature", options);
    EXPECT_EQ(info.aux[0].units, "degC");
    const double expected = 25.0 + 0.001 * 500;
    EXPECT_EQ(t[500], v.file_type == H5T_IEEE_F32LE
                          ? static_cast<double>(static_cast<float>(expected))
                          : expected);
  }
}

INSTANTIATE_TEST_SUITE_P(RecordingReader, EveryContractVariant, ::testing::ValuesIn(AllVariants()),
                         [](const auto& info) { return info.param.name; });

// Contract v1.1: integer counts with a scale_factor (the unit per count) read as counts times the
// factor, exactly the doubles a float64 file of those products holds (one IEEE multiplication).
TEST(RecordingReader, ReadsInt16AndInt32CountsTimesTheirScaleFactor) {
  TempDir dir;
  std::vector<double> counts;
  for (int k = 0; k < 500; ++k) counts.push_back(std::round(3000.0 * std::sin(0.37 * k * k)));
  const double scale = 0.0025;  // deg/h per count
  for (hid_t type : {H5T_STD_I16LE, H5T_STD_I32LE}) {
    const std::string path = dir.File(type == H5T_STD_I16LE ? "i16.h5" : "i32.h5");
    {
      testing::RawFile file(path);
      file.Dataset("/rate", {counts.size()}, counts, Layout{type, {}, 0, false});
      file.StringAttribute("/rate", "units", "deg/h");
      file.DoubleAttribute("/rate", "scale_factor", scale);
      file.Dataset("/aux/temperature", {counts.size()}, counts,
                   Layout{H5T_STD_U16LE, {}, 0, false});
      file.StringAttribute("/aux/temperature", "units", "degC");
      file.DoubleAttribute("/aux/temperature", "scale_factor", 0.01);
      file.DoubleAttribute("/", "sample_rate_hz", 10.0);
    }
    const RecordingInfo info = InspectRecording(path);
    EXPECT_EQ(info.rate_dtype, type == H5T_STD_I16LE ? "int16" : "int32");
    EXPECT_EQ(info.rate_scale_factor, scale);
    ASSERT_EQ(info.aux.size(), 1u);
    EXPECT_EQ(info.aux[0].dtype, "uint16");
    auto lock = hdf5::LockHdf5();
    const RecordingReader reader(path);
    const Eigen::VectorXd rate = reader.ReadAxisNative(0, ReadOptions{});
    const Eigen::VectorXd temperature = reader.ReadAux("temperature", ReadOptions{});
    for (std::size_t k = 0; k < counts.size(); ++k) {
      ASSERT_EQ(rate[k], counts[k] * scale) << k;
      // HDF5 clips the negative counts to 0 when it writes them as uint16.
      const double stored = counts[k] < 0 ? 0.0 : counts[k];
      ASSERT_EQ(temperature[k], stored * 0.01) << k;
    }
  }
}

// Without its scale_factor an integer dataset is refused (the counts' unit is unknown), by the
// reader and by validate's metadata check, naming the file and the attribute.
TEST(RecordingReader, RefusesIntegerCountsWithoutAScaleFactor) {
  TempDir dir;
  const std::string path = dir.File("counts.h5");
  {
    testing::RawFile file(path);
    file.Dataset("/rate", {100}, std::vector<double>(100, 7.0),
                 Layout{H5T_STD_I16LE, {}, 0, false});
    file.StringAttribute("/rate", "units", "deg/h");
    file.DoubleAttribute("/", "sample_rate_hz", 10.0);
  }
  try {
    InspectRecording(path);
    ADD_FAILURE() << "admitted";
  } catch (const RecordingError& e) {
    EXPECT_EQ(e.kind(), std::string(error_kind::kMissingAttribute));
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'scale_factor'"), std::string::npos) << e.what();
  }
  auto lock = hdf5::LockHdf5();
  const RecordingCheck check = CheckRecordingMetadata(path, OpenHdf5ReadOnly(path));
  EXPECT_FALSE(check.admitted());
}

TEST(RecordingReader, NamesAxesByIndexWhenTheFileGivesNoNames) {
  TempDir dir;
  RecordingSpec spec;
  spec.axes = 2;
  spec.two_dimensional = true;
  testing::WriteRecording(dir.File("a.h5"), spec);
  const RecordingInfo info = InspectRecording(dir.File("a.h5"));
  EXPECT_FALSE(info.axis_names_from_file);
  EXPECT_EQ(info.axis_names, (std::vector<std::string>{"axis0", "axis1"}));
  EXPECT_EQ(ReadAxisRadPerSecond(dir.File("a.h5"), "1")[3],
            ReadAxisRadPerSecond(dir.File("a.h5"), "axis1")[3]);
}

TEST(RecordingReader, ReadsFixedLengthAxisNamesAsNumpyWritesThem) {
  TempDir dir;
  RecordingSpec spec;
  spec.axes = 3;
  spec.two_dimensional = true;
  spec.axis_names = {"x", "y", "z"};
  spec.fixed_length_axes = true;
  testing::WriteRecording(dir.File("a.h5"), spec);
  EXPECT_EQ(InspectRecording(dir.File("a.h5")).axis_names,
            (std::vector<std::string>{"x", "y", "z"}));
}

TEST(RecordingReader, IgnoresUnknownGroupsDatasetsAndAttributes) {
  TempDir dir;
  const std::string path = dir.File("extra.h5");
  testing::WriteRecording(path, RecordingSpec{});
  // Add extras to the good file with the raw C API.
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  hid_t g = H5Gcreate2(f, "/calibration", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Gclose(g);
  hid_t aux = H5Gcreate2(f, "/aux", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  hid_t sub = H5Gcreate2(aux, "notes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Gclose(sub);
  H5Gclose(aux);
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = H5Acreate2(f, "operator", H5T_STD_I32LE, space, H5P_DEFAULT, H5P_DEFAULT);
  int value = 7;
  H5Awrite(attr, H5T_NATIVE_INT, &value);
  H5Aclose(attr);
  H5Sclose(space);
  H5Fclose(f);
  const RecordingInfo info = InspectRecording(path);
  EXPECT_EQ(info.samples, 1000);
  EXPECT_TRUE(info.aux.empty());
}

TEST(RecordingReader, BridgesShortNanRunsAndReportsThem) {
  TempDir dir;
  const std::string path = dir.File("nan.h5");
  std::vector<double> values;
  for (int k = 0; k < 200; ++k) values.push_back(testing::TestValue(k, 0));
  for (int k = 50; k < 53; ++k) values[k] = std::nan("");
  values[120] = std::nan("");
  {
    testing::RawFile file(path);
    file.Dataset("/rate", {200}, values);
    file.StringAttribute("/rate", "units", "rad/s");
    file.DoubleAttribute("/", "sample_rate_hz", 1.0);
  }
  ReadReport report;
  const Eigen::VectorXd x = ReadAxisRadPerSecond(path, "0", ReadOptions{}, &report);
  EXPECT_EQ(report.nan.bridged_samples, 4);
  EXPECT_EQ(report.nan.runs, 2);
  EXPECT_EQ(report.nan.longest_run, 3);
  // Straight line between samples 49 and 53.
  EXPECT_DOUBLE_EQ(x[51], values[49] + 0.5 * (values[53] - values[49]));
  EXPECT_DOUBLE_EQ(x[120], 0.5 * (values[119] + values[121]));
}

TEST(RecordingReader, ReadsFromSeveralThreadsUnderTheGlobalLock) {
  TempDir dir;
  std::vector<std::string> paths;
  for (int f = 0; f < 4; ++f) {
    RecordingSpec spec;
    spec.samples = 5000;
    spec.axes = 2;
    spec.two_dimensional = true;
    spec.layout = Layout{H5T_IEEE_F32LE, {700, 2}, 3, true};
    paths.push_back(dir.File("t" + std::to_string(f) + ".h5"));
    testing::WriteRecording(paths.back(), spec);
  }
  const Eigen::VectorXd expected = ReadAxisRadPerSecond(paths[0], "1");
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      hdf5::SilenceHdf5ErrorPrinter();
      for (int i = 0; i < 10; ++i) {
        const std::string& path = paths[(t + i) % 4];
        // Both styles: the self-locking free function and a reader held under the lock.
        if (i % 2 == 0) {
          if (ReadAxisRadPerSecond(path, "1") != expected) ++mismatches;
        } else {
          auto lock = hdf5::LockHdf5();
          RecordingReader reader(path);
          if (reader.ReadAxisRadPerSecond(1) != expected) ++mismatches;
        }
      }
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(mismatches.load(), 0);
}

TEST(RecordingReader, ReadsTheRealAdis16405RecordingWhenAvailable) {
  std::string path;
  for (const std::string& candidate :
       {std::string(FOGPIPE_SOURCE_DIR) + "/../shared/data/real-imu/adis16405_imu1.h5",
        std::string("/work/shared/data/real-imu/adis16405_imu1.h5")}) {
    if (std::filesystem::exists(candidate)) {
      path = candidate;
      break;
    }
  }
  if (path.empty()) GTEST_SKIP() << "shared real-imu data not present";
  const RecordingInfo info = InspectRecording(path);
  EXPECT_EQ(info.samples, 1000000);
  EXPECT_EQ(info.axis_count, 3);
  EXPECT_EQ(info.axis_names, (std::vector<std::string>{"x", "y", "z"}));
  EXPECT_EQ(info.rate_units, "deg/s");
  EXPECT_EQ(info.sample_rate_hz, 100.0);
  const Eigen::VectorXd x = ReadAxisRadPerSecond(path, "x");
  // The ADIS16405 LSB is 0.05 deg/s: every sample is a multiple of it (README of the data).
  const double lsb_rad_s = 0.05 * kPi / 180.0;
  for (long long k = 0; k < x.size(); k += 9973) {
    const double steps = x[k] / lsb_rad_s;
    ASSERT_NEAR(steps, std::round(steps), 1e-6) << k;
  }
}

}  // namespace
}  // namespace fogpipe::io
