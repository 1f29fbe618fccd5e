// `fogpipe allan` as a user runs it, checked against independent computations: a direct
// (moving-average, no cumulative sum) overlapping Allan deviation written here, allantools'
// published table of the real ADIS16405 recording, and allantools' tau grid.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "pipeline/io/allan_report.h"
#include "tests/pipeline/io/run_fogpipe.h"
#include "tests/pipeline/io/test_recording_files.h"

namespace fogpipe {
namespace {

using testing::Quote;
using testing::RunFogpipe;

constexpr double kPi = 3.14159265358979323846;

/// Deterministic white noise plus a slow random walk (std::mt19937_64 + Box-Muller: the same
/// numbers on every platform).
std::vector<double> Noise(int n, double white_sigma, double walk_sigma, uint64_t seed) {
  std::mt19937_64 engine(seed);
  auto uniform = [&engine] { return (static_cast<double>(engine() >> 11) + 0.5) * 0x1.0p-53; };
  std::vector<double> y(n);
  double walk = 0.0;
  for (int k = 0; k < n; ++k) {
    const double u1 = uniform(), u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    walk += walk_sigma * r * std::sin(2.0 * kPi * u2);
    y[k] = 5.0 + white_sigma * r * std::cos(2.0 * kPi * u2) + walk;
  }
  return y;
}

/// Overlapping Allan deviation straight from its definition (IEEE Std 952-1997 eq. C.2 with
/// overlapping clusters; NIST SP 1065 eq. 11): means of m consecutive samples, differences of
/// adjacent means, summed in long double. Shares no code or algebra (no cumulative sum) with
/// fogpipe::allan.
long double DirectOadev(const std::vector<double>& y, int m) {
  const int n = static_cast<int>(y.size());
  std::vector<long double> mean(n - m + 1);
  for (int k = 0; k + m <= n; ++k) {
    long double s = 0;
    for (int j = 0; j < m; ++j) s += y[k + j];
    mean[k] = s / m;
  }
  long double sum = 0;
  const int terms = n - 2 * m + 1;
  for (int k = 0; k < terms; ++k) {
    const long double d = mean[k + m] - mean[k];
    sum += d * d;
  }
  return std::sqrt(sum / (2.0L * terms));
}

std::string WriteNoiseRecording(const testing::TempDir& dir, const std::vector<double>& y,
                                const std::string& units, double rate_hz) {
  const std::string path = dir.File("noise.h5");
  testing::RawFile file(path);
  file.Dataset("/rate", {y.size(), 1}, y, {H5T_IEEE_F64LE, {512, 1}, 4, true});
  file.StringAttribute("/rate", "units", units);
  file.StringArrayAttribute("/rate", "axes", {"z"});
  file.DoubleAttribute("/", "sample_rate_hz", rate_hz);
  return path;
}

TEST(AllanCommand, JsonTableEqualsTheDefinitionOfTheOverlappingAllanDeviation) {
  testing::TempDir dir;
  const std::vector<double> y = Noise(4000, 2.0, 0.01, 7);  // deg/h
  const std::string path = WriteNoiseRecording(dir, y, "deg/h", 10.0);
  const auto r = RunFogpipe("allan " + Quote(path) + " --axis z --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["axis"], "z");
  EXPECT_EQ(j["rate_units"], "deg/h");
  EXPECT_EQ(j["samples"], 4000);
  const auto& t = j["table"];
  const std::vector<long long> m = t["m"];
  ASSERT_GE(m.size(), 10u);
  for (size_t i = 0; i < m.size(); ++i) {
    EXPECT_EQ(m[i], 1LL << i) << "octave grid";
    EXPECT_DOUBLE_EQ(t["tau_s"][i].get<double>(), m[i] / 10.0);
    EXPECT_EQ(t["count"][i].get<long long>(), 4000 - 2 * m[i] + 1);
    const double expected = static_cast<double>(DirectOadev(y, static_cast<int>(m[i])));
    // fogpipe sums a compensated cumulative sum in double; the direct form here sums in long
    // double. Both are within ~1e-13 relative of the exact value for 4000 samples (error of a
    // sum of n terms ~ n eps |terms| / |sum| with mean removed); 1e-9 leaves room and still
    // catches any formula slip (a wrong normalisation is >= 1e-4 off).
    EXPECT_NEAR(t["sigma_deg_h"][i].get<double>(), expected, 1e-9 * expected) << "m " << m[i];
    const double low = t["ci_low_deg_h"][i], high = t["ci_high_deg_h"][i];
    EXPECT_LT(low, expected);
    EXPECT_GT(high, expected);
  }
  // White noise of 2 deg/h per sample at 10 Hz: N = 2 / sqrt(10) / 60 deg/sqrt(h)
  // (sigma(tau) = N / sqrt(tau), IEEE 952 Annex C). 4000 samples give sigma(tau0) to
  // 1/sqrt(2 * 4000 / 1.3) ~ 1.3 % (EDF of white noise at m = 1); the joint fit also spreads
  // over the walk, so 10 % is a safe bound that still catches a unit slip (x 60, x 3600).
  const double n_true = 2.0 / std::sqrt(10.0) / 60.0;
  EXPECT_NEAR(j["noise_terms"]["n_deg_sqrt_h"].get<double>(), n_true, 0.1 * n_true);
}

TEST(AllanCommand, CsvOfARecordingInDegPerHourHasOneSigmaColumn) {
  testing::TempDir dir;
  const std::string path = WriteNoiseRecording(dir, Noise(3000, 2.0, 0.0, 12), "deg/h", 10.0);
  const auto csv = RunFogpipe("allan " + Quote(path) + " --csv --taus decade:5");
  ASSERT_EQ(csv.exit_code, 0) << csv.output;
  std::istringstream lines(csv.output);
  std::string line;
  std::getline(lines, line);
  std::getline(lines, line);
  EXPECT_EQ(line,
            "tau_s,m,sigma_deg_h,ci_low_deg_h,ci_high_deg_h,edf,edf_source,alpha,alpha_method,"
            "count");
}

TEST(AllanCommand, CsvAndTextCarryTheSameNumbersInTheRecordingUnitAndInDegPerHour) {
  testing::TempDir dir;
  const std::vector<double> y = Noise(3000, 0.01, 0.0, 11);  // rad/s
  const std::string path = WriteNoiseRecording(dir, y, "rad/s", 100.0);
  const auto csv = RunFogpipe("allan " + Quote(path) + " --csv --taus decade:5");
  ASSERT_EQ(csv.exit_code, 0) << csv.output;
  std::istringstream lines(csv.output);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line.rfind("# fogpipe allan: ", 0), 0u) << line;
  std::getline(lines, line);
  EXPECT_EQ(line,
            "tau_s,m,sigma_rad_s,sigma_deg_h,ci_low_deg_h,ci_high_deg_h,edf,edf_source,alpha,alpha_"
            "method,"
            "count");
  int rows = 0;
  while (std::getline(lines, line)) {
    double tau, sigma_rad_s, sigma_deg_h;
    long long m;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lld,%lf,%lf", &tau, &m, &sigma_rad_s, &sigma_deg_h),
              4)
        << line;
    const double expected = static_cast<double>(DirectOadev(y, static_cast<int>(m)));
    EXPECT_NEAR(sigma_rad_s, expected, 1e-9 * expected);
    // 1 rad/s = 180/pi * 3600 deg/h, written out here rather than taken from units.h.
    EXPECT_NEAR(sigma_deg_h, sigma_rad_s * 180.0 / kPi * 3600.0, 1e-14 * sigma_deg_h);
    ++rows;
  }
  EXPECT_GE(rows, 10);  // 5 per decade over 3 decades, deduplicated at small m
  const auto text = RunFogpipe("allan " + Quote(path));
  ASSERT_EQ(text.exit_code, 0);
  for (const char* header : {"tau [s]", "sigma [rad/s]", "sigma [deg/h]", "ci_low [deg/h]", "EDF",
                             "count", "deg/sqrt(h)", "arcsec", "deg/h/sqrt(h)", "deg/h^2"}) {
    EXPECT_NE(text.output.find(header), std::string::npos) << header << "\n" << text.output;
  }
}

/// Two axes "x" and "y" of different noise, row-major [N, 2] as the contract stores them.
std::string WriteTwoAxisRecording(const testing::TempDir& dir) {
  const std::vector<double> x = Noise(3000, 2.0, 0.0, 21), y = Noise(3000, 0.5, 0.0, 22);
  std::vector<double> both;
  for (size_t k = 0; k < x.size(); ++k) both.insert(both.end(), {x[k], y[k]});
  const std::string path = dir.File("two.h5");
  testing::RawFile file(path);
  file.Dataset("/rate", {x.size(), 2}, both, {H5T_IEEE_F64LE, {512, 2}, 4, true});
  file.StringAttribute("/rate", "units", "deg/h");
  file.StringArrayAttribute("/rate", "axes", {"x", "y"});
  file.DoubleAttribute("/", "sample_rate_hz", 10.0);
  return path;
}

TEST(AllanCommand, AxisAllLabelsEveryAxisInCsvJsonAndTextWithTheOneAxisNumbers) {
  testing::TempDir dir;
  const std::string path = WriteTwoAxisRecording(dir);
  const auto csv = RunFogpipe("allan " + Quote(path) + " --axis all --csv");
  ASSERT_EQ(csv.exit_code, 0) << csv.output;
  std::map<std::string, std::vector<std::string>> rows;  // axis -> rows without the axis
  std::istringstream lines(csv.output);
  std::string line, header;
  while (std::getline(lines, line)) {
    if (line.rfind("#", 0) == 0) continue;
    if (header.empty()) {
      header = line;
      continue;
    }
    const size_t comma = line.find(',');
    rows[line.substr(0, comma)].push_back(line.substr(comma + 1));
  }
  EXPECT_EQ(header.rfind("axis,tau_s,m,sigma_deg_h,", 0), 0u) << header;
  ASSERT_EQ(rows.size(), 2u) << csv.output;
  for (const std::string axis : {"x", "y"}) {
    const auto one = RunFogpipe("allan " + Quote(path) + " --axis " + axis + " --csv");
    ASSERT_EQ(one.exit_code, 0);
    std::vector<std::string> expected;
    std::istringstream one_lines(one.output);
    while (std::getline(one_lines, line))
      if (line.rfind("#", 0) != 0 && line.rfind("tau_s", 0) != 0) expected.push_back(line);
    EXPECT_EQ(rows[axis], expected) << axis;
  }
  EXPECT_NE(rows["x"], rows["y"]);

  const auto json = RunFogpipe("allan " + Quote(path) + " --axis all --json");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  const nlohmann::json j = nlohmann::json::parse(json.output);
  ASSERT_EQ(j["axes"].size(), 2u);
  EXPECT_EQ(j["axes"][0]["axis"], "x");
  EXPECT_EQ(j["axes"][1]["axis"], "y");
  const nlohmann::json y =
      nlohmann::json::parse(RunFogpipe("allan " + Quote(path) + " --axis 1 --json").output);
  EXPECT_EQ(j["axes"][1]["table"], y["table"]);
  EXPECT_EQ(j["axes"][1]["noise_terms"], y["noise_terms"]);

  const auto text = RunFogpipe("allan " + Quote(path) + " --axis all");
  ASSERT_EQ(text.exit_code, 0);
  const size_t x_at = text.output.find(", axis x\n"), y_at = text.output.find(", axis y\n");
  ASSERT_NE(x_at, std::string::npos) << text.output;
  ASSERT_NE(y_at, std::string::npos) << text.output;
  EXPECT_LT(x_at, y_at);
}

TEST(AllanCommand, ProgressGoesToStderrWhenAskedAndNeverToStdout) {
  testing::TempDir dir;
  const std::string path = WriteTwoAxisRecording(dir);
  const std::string args = "allan " + Quote(path) + " --axis all --csv";
  const auto plain = RunFogpipe(args);
  ASSERT_EQ(plain.exit_code, 0);
  // stderr not a terminal and not asked: nothing besides stdout.
  EXPECT_EQ(RunFogpipe(args, /*merge_stderr=*/true).output, plain.output);
  // Asked: the steps of each axis on stderr, stdout unchanged.
  EXPECT_EQ(RunFogpipe(args + " --progress").output, plain.output);
  const auto merged = RunFogpipe(args + " --progress", /*merge_stderr=*/true);
  ASSERT_EQ(merged.exit_code, 0);
  for (const std::string step : {": axis x: reading", ": axis y: oadev on the octave grid",
                                 ": axis y: noise terms and their EDF"})
    EXPECT_NE(merged.output.find("allan " + path + step), std::string::npos) << step << "\n"
                                                                             << merged.output;
}

TEST(AllanCommand, ExitCodesSeparateBadRecordingsFromUsageErrors) {
  testing::TempDir dir;
  const std::string path = WriteNoiseRecording(dir, Noise(1000, 1.0, 0.0, 3), "deg/s", 1.0);
  EXPECT_EQ(RunFogpipe("allan").exit_code, 2);
  EXPECT_EQ(RunFogpipe("allan " + Quote(path) + " --taus weekly").exit_code, 2);
  EXPECT_EQ(RunFogpipe("allan " + Quote(path) + " --taus decade:0").exit_code, 2);
  const auto axis = RunFogpipe("allan " + Quote(path) + " --axis q", true);
  EXPECT_EQ(axis.exit_code, 1);
  EXPECT_NE(axis.output.find("has no axis 'q'"), std::string::npos) << axis.output;
  const std::string text = dir.File("notes.h5");
  std::ofstream(text) << "hello";
  const auto bad = RunFogpipe("allan " + Quote(text), true);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find(text + ": is not an HDF5 file"), std::string::npos) << bad.output;
}

// Every kind of --deviation on one small recording (deg/s at 10 Hz): the kind's name and the units
// in each output, the IEEE terms only on the Allan tables, and TDEV = tau MDEV / sqrt(3) across
// the two unit systems (deg/s -> rad/s by pi / 180, written out here).
TEST(AllanCommand, EveryDeviationKindCarriesItsNameAndUnitsInTextCsvAndJson) {
  testing::TempDir dir;
  const std::string path = WriteNoiseRecording(dir, Noise(2000, 0.5, 0.001, 17), "deg/s", 10.0);
  std::vector<double> mdev_deg_s;
  for (const std::string kind : {"oadev", "adev", "mdev", "tdev", "ohdev", "hdev", "totdev"}) {
    const bool angle = kind == "tdev";
    const bool allan = kind == "oadev" || kind == "adev";
    const std::string primary = angle ? "sigma_rad" : "sigma_deg_s";
    const std::string eng = angle ? "arcsec" : "deg_h";
    const auto json = RunFogpipe("allan " + Quote(path) + " --deviation " + kind + " --json");
    ASSERT_EQ(json.exit_code, 0) << kind << "\n" << json.output;
    const nlohmann::json j = nlohmann::json::parse(json.output);
    EXPECT_EQ(j["deviation"], kind);
    EXPECT_EQ(j["deviation_units"], angle ? "rad" : "deg/s");
    const auto& t = j["table"];
    for (const std::string& key :
         {std::string("tau_s"), primary, "sigma_" + eng, "ci_low_" + eng, "ci_high_" + eng,
          std::string("edf"), std::string("edf_source"), std::string("alpha"),
          std::string("alpha_method"), std::string("count")})
      ASSERT_TRUE(t.contains(key)) << kind << " lacks " << key;
    ASSERT_GE(t["tau_s"].size(), 8u) << kind;
    for (size_t i = 0; i < t["tau_s"].size(); ++i) {
      const double sigma = t["sigma_" + eng][i], low = t["ci_low_" + eng][i],
                   high = t["ci_high_" + eng][i];
      EXPECT_GT(sigma, 0.0) << kind;
      EXPECT_LT(low, sigma) << kind << " row " << i;
      EXPECT_GT(high, sigma) << kind << " row " << i;
    }
    EXPECT_EQ(j["noise_terms"].is_object(), allan) << kind;
    if (!allan) {
      EXPECT_EQ(j["noise_fit"]["termination"], "not_fitted") << kind;
    }
    if (kind == "mdev") mdev_deg_s = t["sigma_deg_s"].get<std::vector<double>>();
    if (angle) {
      ASSERT_EQ(mdev_deg_s.size(), t["tau_s"].size());
      for (size_t i = 0; i < mdev_deg_s.size(); ++i) {
        const double tau = t["tau_s"][i];
        const double expected = tau * mdev_deg_s[i] * kPi / 180.0 / std::sqrt(3.0);
        EXPECT_NEAR(t["sigma_rad"][i].get<double>(), expected, 1e-12 * expected);
        EXPECT_NEAR(t["sigma_arcsec"][i].get<double>(), expected * 180.0 / kPi * 3600.0,
                    1e-12 * expected * 206264.8);
      }
    }
    const auto csv = RunFogpipe("allan " + Quote(path) + " --deviation " + kind + " --csv");
    ASSERT_EQ(csv.exit_code, 0) << csv.output;
    EXPECT_NE(csv.output.find(", " + kind + ", octave taus"), std::string::npos) << csv.output;
    EXPECT_NE(csv.output.find("tau_s,m," + primary + ",sigma_" + eng + ",ci_low_" + eng +
                              ",ci_high_" + eng + ",edf,edf_source,alpha,alpha_method,count\n"),
              std::string::npos)
        << csv.output;
    const auto text = RunFogpipe("allan " + Quote(path) + " --deviation " + kind);
    ASSERT_EQ(text.exit_code, 0) << text.output;
    EXPECT_NE(text.output.find("  " + kind + " on the octave grid"), std::string::npos)
        << text.output;
    EXPECT_EQ(text.output.find("noise types: alpha equals the fitted model's dominant term") !=
                  std::string::npos,
              allan)
        << text.output;
    EXPECT_EQ(j.contains("model_alpha"), allan) << kind;
    const std::string unit_header = angle ? "sigma [arcsec]" : "sigma [deg/h]";
    EXPECT_NE(text.output.find(unit_header), std::string::npos) << text.output;
    EXPECT_NE(text.output.find(angle ? "sigma [rad]" : "sigma [deg/s]"), std::string::npos);
    EXPECT_EQ(text.output.find("Noise terms: not fitted") == std::string::npos, allan)
        << text.output;
  }
  const auto bad = RunFogpipe("allan " + Quote(path) + " --deviation theoh", true);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("oadev, adev, mdev, tdev, ohdev, hdev, totdev"), std::string::npos)
      << bad.output;
  const auto help = RunFogpipe("allan --help");
  for (const char* word : {"--deviation", "mdev:", "tdev:", "totdev:", "ohdev:", "hdev:", "adev:",
                           "oadev:", "arcsec", "deg/h", "--deviation TEXT=oadev"})
    EXPECT_NE(help.output.find(word), std::string::npos) << word << "\n" << help.output;
}

// allantools 2024.06 oadev(taus="log10") on 1e6 frequency samples at 100 Hz: the tau column of
// adis16405_imu1_gyro_x_oadev_allantools.csv times 100 (the grid depends only on N, not on the
// data). Lets this test run where the shared data is absent.
TEST(AllanCommand, Log10GridIsAllantoolsGrid) {
  const std::vector<long long> allantools_first = {1,  2,  3,  4,  5,  7,  8,  10,  13,  17,
                                                   21, 27, 34, 42, 54, 68, 86, 108, 137, 173};
  const std::vector<long long> m = allan::AllantoolsLog10Factors(1000000, 500000);
  ASSERT_EQ(m.size(), 54u);
  EXPECT_EQ(std::vector<long long>(m.begin(), m.begin() + 20), allantools_first);
  EXPECT_EQ(m.back(), 495354);  // tau 4953.54 s, the table's last row
}

std::string SharedRealImuDir() {
  for (const std::string& dir : {std::string(FOGPIPE_SOURCE_DIR) + "/../shared/data/real-imu",
                                 std::string("/work/shared/data/real-imu")}) {
    if (std::filesystem::exists(dir + "/adis16405_imu1.h5")) return dir;
  }
  return "";
}

TEST(AllanCommand, AgreesWithAllantoolsOnTheRealAdis16405RecordingToItsPrintedDigits) {
  const std::string dir = SharedRealImuDir();
  if (dir.empty()) GTEST_SKIP() << "shared real-imu data not present (../shared/data/real-imu)";
  const auto r =
      RunFogpipe("allan " + Quote(dir + "/adis16405_imu1.h5") + " --axis x --taus log10 --csv");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream reference(dir + "/adis16405_imu1_gyro_x_oadev_allantools.csv");
  std::vector<std::pair<double, double>> expected;  // tau_s, oadev deg/s
  std::string line;
  while (std::getline(reference, line)) {
    double tau, sigma;
    if (line.empty() || line[0] == '#') continue;
    if (std::sscanf(line.c_str(), "%lf,%lf", &tau, &sigma) == 2) expected.push_back({tau, sigma});
  }
  ASSERT_EQ(expected.size(), 54u);
  std::istringstream lines(r.output);
  size_t row = 0;
  while (std::getline(lines, line)) {
    double tau, sigma;
    long long m;
    if (line.empty() || line[0] == '#' || line[0] == 't') continue;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lld,%lf", &tau, &m, &sigma), 3) << line;
    ASSERT_LT(row, expected.size());
    // allantools printed 6 significant digits: a value v is known to +-0.5 in its 6th digit,
    // i.e. to 5e-6 relative at worst; 1e-5 relative (the README's stated agreement) covers that.
    EXPECT_NEAR(tau, expected[row].first, 1e-5 * expected[row].first) << "row " << row;
    EXPECT_NEAR(sigma, expected[row].second, 1e-5 * expected[row].second) << "tau " << tau;
    ++row;
  }
  EXPECT_EQ(row, expected.size());
}

}  // namespace
}  // namespace fogpipe
