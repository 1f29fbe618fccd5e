// Tests of pipeline/io/recording_writer: contract-v1 recordings and truth sidecars as `simulate`
// writes them.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "algorithms/common/units.h"
#include "algorithms/simulation/navigation_grade.h"
#include "pipeline/io/recording_writer.h"
#include "tests/pipeline/cli/simulate_test_support.h"

namespace fogpipe::io {
namespace {

using fogpipe::testing::Dims;
using fogpipe::testing::ReadAll;
using fogpipe::testing::ReadDoubleAttribute;
using fogpipe::testing::ReadStringAttribute;
using fogpipe::testing::ScratchDir;

RecordingData Sample(Eigen::Index n, Eigen::Index axes) {
  RecordingData data;
  data.sample_rate_hz = 10.0;
  data.rate_rad_s.resize(n, axes);
  for (Eigen::Index a = 0; a < axes; ++a) {
    for (Eigen::Index k = 0; k < n; ++k) data.rate_rad_s(k, a) = 1e-5 * std::sin(0.01 * k + a);
  }
  data.start_time_utc = "2026-03-01T08:00:00Z";
  data.instrument = "VG951";
  data.serial = "S-1";
  return data;
}

size_t FilesIn(const ScratchDir& dir) {
  size_t count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    (void)entry;
    ++count;
  }
  return count;
}

TEST(RecordingWriter, WritesAOneAxisContractV1FileInDegPerHour) {
  ScratchDir dir("writer1");
  RecordingData data = Sample(1000, 1);
  data.latitude_deg = 48.5;
  data.aux["temperature"] = AuxChannel{Eigen::VectorXd::LinSpaced(1000, 20.0, 30.0), "degC"};
  WriteRecording(dir / "a.h5", data);

  H5::H5File file(dir / "a.h5", H5F_ACC_RDONLY);
  EXPECT_EQ(ReadDoubleAttribute(file, "sample_rate_hz"), 10.0);
  EXPECT_EQ(ReadDoubleAttribute(file, "latitude_deg"), 48.5);
  EXPECT_EQ(ReadStringAttribute(file, "start_time_utc"), "2026-03-01T08:00:00Z");
  EXPECT_EQ(ReadStringAttribute(file, "instrument"), "VG951");
  EXPECT_EQ(ReadStringAttribute(file, "serial"), "S-1");
  H5::DataSet rate = file.openDataSet("rate");
  EXPECT_EQ(Dims(rate), std::vector<hsize_t>{1000});
  EXPECT_EQ(ReadStringAttribute(rate, "units"), "deg/h");
  EXPECT_EQ(rate.getDataType(), H5::PredType::IEEE_F64LE);
  const Eigen::VectorXd stored = ReadAll(rate);
  const Eigen::VectorXd expected = data.rate_rad_s.col(0) * units::RadPerSecondToDegPerHour(1.0);
  // One multiplication by the unit factor: at most 1 ulp apart.
  EXPECT_LT((stored - expected).cwiseAbs().maxCoeff(), 1e-15 * expected.cwiseAbs().maxCoeff());
  // Chunked, shuffled and deflated.
  H5::DSetCreatPropList plist = rate.getCreatePlist();
  EXPECT_EQ(plist.getLayout(), H5D_CHUNKED);
  EXPECT_EQ(plist.getNfilters(), 2);
  H5::DataSet temperature = file.openDataSet("aux/temperature");
  EXPECT_EQ(ReadStringAttribute(temperature, "units"), "degC");
  EXPECT_EQ(ReadAll(temperature), data.aux["temperature"].samples);
  EXPECT_FALSE(rate.attrExists("axes"));
}

TEST(RecordingWriter, WritesSeveralAxesAsNByAInFloat32WithAxisNames) {
  ScratchDir dir("writer2");
  RecordingData data = Sample(500, 3);
  data.axes = {"x", "y", "z"};
  RecordingWriterOptions options;
  options.rate_unit = units::RateUnit::kDegPerSecond;
  options.sample_type = SampleType::kFloat32;
  WriteRecording(dir / "b.h5", data, options);

  H5::H5File file(dir / "b.h5", H5F_ACC_RDONLY);
  H5::DataSet rate = file.openDataSet("rate");
  EXPECT_EQ(Dims(rate), (std::vector<hsize_t>{500, 3}));
  EXPECT_EQ(rate.getDataType(), H5::PredType::IEEE_F32LE);
  EXPECT_EQ(ReadStringAttribute(rate, "units"), "deg/s");
  const Eigen::VectorXd stored = ReadAll(rate);  // row-major: sample k, axis a at 3 k + a
  for (Eigen::Index k = 0; k < 500; k += 37) {
    for (Eigen::Index a = 0; a < 3; ++a) {
      const double expected = data.rate_rad_s(k, a) * units::kDegPerRad;
      // float32 rounding: half an ulp, 2^-24 relative.
      EXPECT_NEAR(stored[3 * k + a], expected, std::abs(expected) * 0x1.0p-24 + 1e-30);
    }
  }
  H5::Attribute axes = rate.openAttribute("axes");
  std::vector<char*> names(3);
  axes.read(axes.getStrType(), names.data());
  EXPECT_STREQ(names[0], "x");
  EXPECT_STREQ(names[2], "z");
  H5Dvlen_reclaim(axes.getStrType().getId(), axes.getSpace().getId(), H5P_DEFAULT, names.data());
}

TEST(RecordingWriter, LeavesOnlyTheFinishedFileAndReplacesAnOldOne) {
  ScratchDir dir("writer3");
  WriteRecording(dir / "c.h5", Sample(100, 1));
  WriteRecording(dir / "c.h5", Sample(200, 1));
  EXPECT_EQ(FilesIn(dir), 1u);  // no "c.h5.tmp-<pid>" left behind
  H5::H5File file(dir / "c.h5", H5F_ACC_RDONLY);
  EXPECT_EQ(Dims(file.openDataSet("rate")), std::vector<hsize_t>{200});
}

TEST(RecordingWriter, AFailedWriteThrowsNamingTheFileAndLeavesNothing) {
  ScratchDir dir("writer4");
  const std::string path = dir / "missing-folder/d.h5";
  try {
    WriteRecording(path, Sample(100, 1));
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_EQ(FilesIn(dir), 0u);
}

TEST(RecordingWriter, RejectsInconsistentData) {
  ScratchDir dir("writer5");
  RecordingData data = Sample(100, 2);
  data.axes = {"x"};
  EXPECT_THROW(WriteRecording(dir / "e.h5", data), std::invalid_argument);
  data = Sample(100, 1);
  data.aux["temperature"] = AuxChannel{Eigen::VectorXd::Zero(99), "degC"};
  EXPECT_THROW(WriteRecording(dir / "e.h5", data), std::invalid_argument);
  data = Sample(100, 1);
  data.sample_rate_hz = 0.0;
  EXPECT_THROW(WriteRecording(dir / "e.h5", data), std::invalid_argument);
  EXPECT_EQ(FilesIn(dir), 0u);
}

TEST(RecordingWriter, WritesARateGivenInTheOutputUnitAsItIsWithExtraRootAttributes) {
  ScratchDir dir("writer6");
  RecordingData data;
  data.sample_rate_hz = 100.0;
  data.rate_in_output_unit.resize(300, 2);
  for (Eigen::Index k = 0; k < 300; ++k) {
    // Values whose round trip through rad/s is not exact in the last bit.
    data.rate_in_output_unit(k, 0) = 0.1 * k + 1.0 / 3.0;
    data.rate_in_output_unit(k, 1) = -7.3e-3 * k;
  }
  data.extra_root_attributes["note"] = "made by hand";
  RecordingWriterOptions options;
  options.rate_unit = units::RateUnit::kDegPerSecond;
  WriteRecording(dir / "f.h5", data, options);

  H5::H5File file(dir / "f.h5", H5F_ACC_RDONLY);
  H5::DataSet rate = file.openDataSet("rate");
  EXPECT_EQ(ReadStringAttribute(rate, "units"), "deg/s");
  const Eigen::VectorXd stored = ReadAll(rate);
  for (Eigen::Index k = 0; k < 300; ++k) {
    ASSERT_EQ(stored[2 * k], 0.1 * k + 1.0 / 3.0) << k;
    ASSERT_EQ(stored[2 * k + 1], -7.3e-3 * k) << k;
  }
  EXPECT_EQ(ReadStringAttribute(file, "note"), "made by hand");

  data.rate_rad_s = data.rate_in_output_unit;  // both: which one is meant?
  EXPECT_THROW(WriteRecording(dir / "g.h5", data, options), std::invalid_argument);
  data.rate_rad_s.resize(0, 0);
  data.extra_root_attributes["sample_rate_hz"] = "7";  // the contract's own attribute
  EXPECT_THROW(WriteRecording(dir / "g.h5", data, options), std::invalid_argument);
  EXPECT_EQ(FilesIn(dir), 1u);
}

TEST(TruthJson, ListsEveryTermInEngineerAndSiUnits) {
  namespace sim = fogpipe::simulation;
  sim::GyroSimulatorOptions o = sim::NavigationGradeOptions(2);
  o.latitude_deg = 30.0;
  sim::AddNavigationGradeTerm(sim::Term::kBiasStep, 2, &o);
  sim::AddNavigationGradeTerm(sim::Term::kTemperature, 2, &o);
  o.duration_s = 100.0;  // keep the test quick; the truth does not depend on it
  const sim::SimulatedRecording r = sim::SimulateGyro(o);
  ASSERT_EQ(r.summary.termination, Termination::kSuccess) << r.summary.message;
  const nlohmann::json j = SimulationTruthToJson({r.truth}, {"x"});
  EXPECT_EQ(j["seed"], 2);
  EXPECT_EQ(j["num_samples"], 1000);
  // Omega_e = 7.292115e-5 rad/s is 15.0410668761 deg/h; sin 30 deg = 1/2.
  EXPECT_NEAR(j["earth_rate_deg_h"].get<double>(), 15.0410668761 / 2.0, 1e-9);
  const nlohmann::json& a = j["axes"][0];
  EXPECT_EQ(a["name"], "x");
  EXPECT_NEAR(a["white"]["n_deg_sqrt_h"].get<double>(),
              units::ArwToDegPerSqrtHour(o.errors.n_rad_sqrt_s), 1e-15);
  EXPECT_EQ(a["white"]["n_rad_sqrt_s"].get<double>(), o.errors.n_rad_sqrt_s);
  EXPECT_NEAR(a["bias_instability"]["allan_floor_deg_h"].get<double>(),
              0.664282 * a["bias_instability"]["b_deg_h"].get<double>(), 1e-8);
  EXPECT_EQ(a["bias_step"][0]["time_s"].get<double>(), o.errors.bias_steps[0].time_s);
  EXPECT_TRUE(a["temperature"].contains("coefficient_deg_h_per_degC"));
  const std::vector<std::string> terms = a["terms"];
  EXPECT_EQ(terms, (std::vector<std::string>{"white", "quantization", "bias_instability",
                                             "rate_random_walk", "temperature", "bias_step"}));
  EXPECT_FALSE(j["aux_temperature"].is_null());
}

}  // namespace
}  // namespace fogpipe::io
