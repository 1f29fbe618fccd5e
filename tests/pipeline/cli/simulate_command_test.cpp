// Runs the real `fogpipe simulate` binary and checks what it wrote with the HDF5 C++ API and
// nlohmann::json, against the simulator library called directly (the CLI adds nothing numerical
// but the unit conversion) and against the documented rules of the profiles, options and truth
// sidecar (pipeline/cli/simulate_command.cpp, algorithms/simulation/navigation_grade.h).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "algorithms/common/units.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/navigation_grade.h"
#include "pipeline/io/recording_writer.h"
#include "simulate_test_support.h"

namespace fogpipe {
namespace {

using testing::Dims;
using testing::ReadAll;
using testing::ReadDoubleAttribute;
using testing::ReadStringAttribute;
using testing::ScratchDir;

// Runs `fogpipe simulate <args>` quietly; returns its exit code.
int Simulate(const std::string& args) {
  const std::string command = std::string(FOGPIPE_BINARY) + " simulate " + args + " 2>/dev/null";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

double DegH(double rad_s) { return units::RadPerSecondToDegPerHour(rad_s); }

TEST(SimulateCommand, PaperProfileWritesTheSimulatorsOutputAndItsTruth) {
  ScratchDir dir("simulate1");
  ASSERT_EQ(Simulate("--profile paper --seed 5 -o " + dir / "p.h5"), 0);
  H5::H5File file(dir / "p.h5", H5F_ACC_RDONLY);
  EXPECT_EQ(ReadDoubleAttribute(file, "sample_rate_hz"), 1.0);
  EXPECT_EQ(ReadStringAttribute(file, "serial"), "SIM-5");
  H5::DataSet rate = file.openDataSet("rate");
  EXPECT_EQ(Dims(rate), std::vector<hsize_t>{3600});
  EXPECT_EQ(ReadStringAttribute(rate, "units"), "deg/h");
  EXPECT_FALSE(file.nameExists("aux"));  // the paper's gyro sat at room temperature

  // Same numbers as the library for the same seed, up to the deg/h conversion (1 ulp).
  const simulation::SimulatedRecording r = simulation::SimulateGyro(simulation::PaperOptions(5));
  const Eigen::VectorXd expected = r.rate_rad_s * DegH(1.0);
  EXPECT_LT((ReadAll(rate) - expected).cwiseAbs().maxCoeff(),
            1e-15 * expected.cwiseAbs().maxCoeff());

  const nlohmann::json truth = ReadJson(dir / "p.h5.truth.json");
  EXPECT_EQ(truth["seed"], 5);
  EXPECT_EQ(truth["profile"], "paper");
  EXPECT_EQ(truth["recording"], "p.h5");
  const double n = truth["axes"][0]["white"]["n_deg_sqrt_h"];
  EXPECT_TRUE(n >= 0.003 && n <= 0.008) << n;
}

TEST(SimulateCommand, FilesModeWritesKRecordingsWithConsecutiveSeeds) {
  ScratchDir dir("simulate2");
  ASSERT_EQ(Simulate("--profile paper --files 3 --seed 10 --duration-s 100 -o " + dir / "camp"), 0);
  for (int i = 0; i < 3; ++i) {
    const std::string path = dir / ("camp/sim_00" + std::to_string(i) + ".h5");
    H5::H5File file(path, H5F_ACC_RDONLY);
    EXPECT_EQ(ReadStringAttribute(file, "serial"), "SIM-" + std::to_string(10 + i));
    EXPECT_EQ(ReadJson(path + ".truth.json")["seed"], 10 + i);
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "camp/sim_003.h5"));
}

TEST(SimulateCommand, ExplicitEffectsAndRateProfileHaveTheirExactShapeInTheFile) {
  // No noise terms: the file holds bias + step + warm-up + the rate-table input, exactly.
  ScratchDir dir("simulate3");
  ASSERT_EQ(Simulate("--duration-s 200 --sample-rate-hz 1 --bias-deg-h 0.5 --bias-step 100:5 "
                     "--warmup 2:50 --rate-profile step:150:3 -o " +
                     dir / "e.h5"),
            0);
  H5::H5File file(dir / "e.h5", H5F_ACC_RDONLY);
  const Eigen::VectorXd x = ReadAll(file.openDataSet("rate"));
  ASSERT_EQ(x.size(), 200);
  for (Eigen::Index k = 0; k < 200; ++k) {
    const double expected =
        0.5 + (k >= 100 ? 5.0 : 0.0) + 2.0 * std::exp(-k / 50.0) + (k >= 150 ? 3.0 : 0.0);
    // Each term makes one round trip deg/h -> rad/s -> deg/h: a few ulp of 10 deg/h.
    ASSERT_NEAR(x[k], expected, 1e-13) << k;
  }
  const nlohmann::json truth = ReadJson(dir / "e.h5.truth.json");
  EXPECT_NEAR(truth["axes"][0]["bias_step"][0]["size_deg_h"].get<double>(), 5.0, 1e-13);
  EXPECT_NEAR(truth["axes"][0]["warmup"]["time_constant_s"].get<double>(), 50.0, 0.0);
  EXPECT_EQ(truth["input_rate"][0]["kind"], "step");
}

TEST(SimulateCommand, SineAndThermalOptionsAreInEngineerUnits) {
  // --sine F:AMP:PHASE_DEG and --temperature-coef DEG_H_PER_DEGC with no noise: the file holds
  // 2 sin(2 pi 0.05 t + 90 deg) + 0.3 (T_true - 25) deg/h, T_true from the sidecar's profile.
  ScratchDir dir("simulate9");
  ASSERT_EQ(Simulate("--duration-s 600 --sample-rate-hz 2 --sine 0.05:2:90 --gm 0.01:30 "
                     "--temperature-coef 0.3 --temperature-pp-degc 10 --temperature-period-s 400 "
                     "-o " +
                     dir / "s.h5"),
            0);
  const nlohmann::json truth = ReadJson(dir / "s.h5.truth.json");
  const nlohmann::json& axis = truth["axes"][0];
  EXPECT_NEAR(axis["sinusoid"][0]["amplitude_deg_h"].get<double>(), 2.0, 1e-14);
  EXPECT_NEAR(axis["sinusoid"][0]["phase_rad"].get<double>(), units::kPi / 2.0, 1e-15);
  EXPECT_NEAR(axis["gauss_markov"][0]["sigma_deg_h"].get<double>(), 0.01, 1e-16);
  EXPECT_EQ(axis["gauss_markov"][0]["correlation_time_s"].get<double>(), 30.0);
  EXPECT_NEAR(axis["temperature"]["coefficient_deg_h_per_degC"].get<double>(), 0.3, 1e-15);
  EXPECT_EQ(axis["temperature"]["reference_degC"].get<double>(), 25.0);
  EXPECT_EQ(truth["aux_temperature"]["peak_to_peak_degC"].get<double>(), 10.0);

  // Rebuild the deterministic part independently of the simulator, from the sidecar alone, and
  // check that what is left is the Gauss-Markov term with its stationary spread.
  const nlohmann::json& t = truth["aux_temperature"];
  H5::H5File file(dir / "s.h5", H5F_ACC_RDONLY);
  const Eigen::VectorXd x = ReadAll(file.openDataSet("rate"));
  const Eigen::VectorXd temperature = ReadAll(file.openDataSet("aux/temperature"));
  ASSERT_EQ(x.size(), 1200);
  Eigen::VectorXd residual(x.size());
  double worst_temperature = 0.0;
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    const double time = k / 2.0;
    const double theta = 2.0 * units::kPi * time / 400.0 + t["phase_rad"].get<double>();
    const double s = t["sharpness"].get<double>();
    const double t_true = 25.0 + 5.0 * std::tanh(s * std::sin(theta)) / std::tanh(s);
    worst_temperature = std::max(worst_temperature, std::abs(temperature[k] - t_true));
    residual[k] = x[k] - 2.0 * std::sin(2.0 * units::kPi * 0.05 * time + units::kPi / 2) -
                  0.3 * (t_true - 25);
  }
  // Sensor noise 0.005 degC: 1200 samples stay within 6 sigma.
  EXPECT_LT(worst_temperature, 0.03);
  // What is left is the Gauss-Markov term alone, Gaussian with sigma = 0.01 deg/h: every sample
  // lies within 6 sigma (P(exceed) < 1200 x 2e-9), and with n (1 - phi^2) / (1 + phi^2) ~ 20
  // effective samples (phi = exp(-0.5 / 30)) its mean square is ~ sigma^2 chi^2_20 / 20, so
  // P(RMS < 0.2 sigma) = P(chi^2_20 < 0.8) < 1e-10. A wrong deterministic part (a 2 deg/h sine or
  // 1.5 deg/h of thermal bias) would break the first bound by far.
  EXPECT_LT(residual.cwiseAbs().maxCoeff(), 0.06);
  EXPECT_GT(std::sqrt(residual.squaredNorm() / residual.size()), 0.002);
}

TEST(SimulateCommand, TheTrueRateRebuiltFromTheSidecarIsWhatAPerfectGyroReads) {
  ScratchDir dir("simulate8");
  ASSERT_EQ(Simulate("--duration-s 300 --latitude-deg 30 "
                     "--rate-profile step:60:10,ramp:120:180:0.5,sine:0.02:4:30 -o " +
                     dir / "t.h5"),
            0);
  const Eigen::VectorXd truth = io::TrueRateFromTruth(ReadJson(dir / "t.h5.truth.json"));
  H5::H5File file(dir / "t.h5", H5F_ACC_RDONLY);
  const Eigen::VectorXd x = ReadAll(file.openDataSet("rate")) / DegH(1.0);  // no error terms
  ASSERT_EQ(truth.size(), 3000);
  // The file went through rad/s -> deg/h -> rad/s and the text through 17 digits: a few ulp of the
  // largest value (~50 deg/h = 2.4e-4 rad/s).
  EXPECT_LT((truth - x).cwiseAbs().maxCoeff(), 1e-18);
  EXPECT_NEAR(truth[0],
              0.5 * simulation::kEarthRotationRateRadS +
                  units::DegPerHourToRadPerSecond(4.0 * std::sin(30.0 * units::kRadPerDeg)),
              1e-18);
}

TEST(SimulateCommand, NavProfileHasTheCyclingTemperatureChannelAndMultiAxisFloat32) {
  ScratchDir dir("simulate4");
  ASSERT_EQ(Simulate("--profile nav --seed 3 --duration-s 7200 --axes 3 --units rad/s "
                     "--dtype float32 --add temperature_rate -o " +
                     dir / "n.h5"),
            0);
  H5::H5File file(dir / "n.h5", H5F_ACC_RDONLY);
  H5::DataSet rate = file.openDataSet("rate");
  EXPECT_EQ(Dims(rate), (std::vector<hsize_t>{72000, 3}));
  EXPECT_EQ(rate.getDataType(), H5::PredType::IEEE_F32LE);
  EXPECT_EQ(ReadStringAttribute(rate, "units"), "rad/s");
  H5::DataSet temperature = file.openDataSet("aux/temperature");
  EXPECT_EQ(ReadStringAttribute(temperature, "units"), "degC");
  const Eigen::VectorXd t = ReadAll(temperature);
  const nlohmann::json truth = ReadJson(dir / "n.h5.truth.json");
  const double pp = truth["aux_temperature"]["peak_to_peak_degC"];
  const double period = truth["aux_temperature"]["period_s"];
  EXPECT_TRUE(pp >= 6.0 && pp <= 12.0);
  EXPECT_TRUE(period >= 3600.0 && period <= 7200.0);
  // 7200 s covers at least one period, so the channel spans the p-p, plus at most the sensor
  // noise extremes (0.005 degC x ~5 sigma on each side over 72000 samples).
  EXPECT_NEAR(t.maxCoeff() - t.minCoeff(), pp, 0.06);
  ASSERT_EQ(truth["axes"].size(), 3u);
  EXPECT_EQ(truth["axes"][2]["name"], "z");
  EXPECT_TRUE(truth["axes"][0].contains("temperature_rate"));
}

TEST(SimulateCommand, AddDrawsANavigationGradeEffectFromTheSeed) {
  ScratchDir dir("simulate5");
  ASSERT_EQ(Simulate("--profile nav --seed 8 --duration-s 600 --add bias_step --add sinusoid "
                     "-o " +
                     dir / "a.h5"),
            0);
  const nlohmann::json truth = ReadJson(dir / "a.h5.truth.json");
  const nlohmann::json& axis = truth["axes"][0];
  const double floor = axis["bias_instability"]["allan_floor_deg_h"];
  const double step = std::abs(axis["bias_step"][0]["size_deg_h"].get<double>()) / floor;
  EXPECT_TRUE(step >= 5.0 && step <= 10.0) << step;
  const double time = axis["bias_step"][0]["time_s"];
  EXPECT_TRUE(time >= 120.0 && time <= 480.0) << time;  // middle 60 % of 600 s
  EXPECT_EQ(axis["sinusoid"].size(), 1u);
}

TEST(SimulateCommand, BadOptionsExitWithCode2AndWriteNothing) {
  ScratchDir dir("simulate6");
  EXPECT_EQ(Simulate("--add wobble -o " + dir / "x.h5"), 2);
  EXPECT_EQ(Simulate("--sine 0.1 -o " + dir / "x.h5"), 2);
  EXPECT_EQ(Simulate("--gm 0.01:0 -o " + dir / "x.h5"), 2);
  EXPECT_EQ(Simulate("--sine 20:1 -o " + dir / "x.h5"), 2);  // above Nyquist at 10 Hz
  EXPECT_EQ(Simulate("--rate-profile ramp:5 -o " + dir / "x.h5"), 2);
  EXPECT_EQ(Simulate("--no-temperature --temperature-coef 0.1 -o " + dir / "x.h5"), 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "x.h5"));
  EXPECT_NE(Simulate("--units furlongs -o " + dir / "x.h5"), 0);  // rejected by CLI11
  EXPECT_NE(Simulate(""), 0);                                     // -o is required
}

TEST(SimulateCommand, AnUnwritableTargetFailsWithCode1) {
  ScratchDir dir("simulate7");
  EXPECT_EQ(Simulate("--duration-s 10 -o " + dir / "no/such/folder/x.h5"), 1);
}

}  // namespace
}  // namespace fogpipe
