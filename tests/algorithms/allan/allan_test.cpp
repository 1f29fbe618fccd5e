// Tests of algorithms/allan/allan.{h,cpp}: the assembled table (sigma, noise type, EDF,
// confidence bounds) against Stable32 octave reports with confidence intervals.
#include "algorithms/allan/allan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "algorithms/allan/edf.h"
#include "algorithms/allan/phase.h"
#include "tests/algorithms/allan/reference_data.h"

namespace fogpipe::allan {
namespace {

enum class Data { kPhaseDat, kOcxo, kPink };

struct OctaveCase {
  const char* file;
  Deviation deviation;
  Data data;
};

long long Samples(Data data) {
  return data == Data::kOcxo ? testing::kOcxoSamples : data == Data::kPink ? 10000 : 1000;
}

const std::vector<OctaveCase>& OctaveCases() {
  static const std::vector<OctaveCase> cases = {
      {"phasedat/phase_dat_oadev_octave.txt", Deviation::kOverlappingAllan, Data::kPhaseDat},
      {"phasedat/phase_dat_adev_octave.txt", Deviation::kAllan, Data::kPhaseDat},
      {"phasedat/phase_dat_hdev_octave.txt", Deviation::kHadamard, Data::kPhaseDat},
      {"phasedat/phase_dat_ohdev_octave.txt", Deviation::kOverlappingHadamard, Data::kPhaseDat},
      {"ocxo/oadev_octave.txt", Deviation::kOverlappingAllan, Data::kOcxo},
      {"ocxo/adev_octave.txt", Deviation::kAllan, Data::kOcxo},
      {"ocxo/hdev_octave.txt", Deviation::kHadamard, Data::kOcxo},
      {"ocxo/ohdev_octave.txt", Deviation::kOverlappingHadamard, Data::kOcxo},
      // Simulated flicker FM (allantools tests/pink_frequency): the "bias instability" case.
      {"pink/s32_oadev_octave.txt", Deviation::kOverlappingAllan, Data::kPink},
  };
  return cases;
}

AllanTable Compute(const OctaveCase& c, NoiseIdRule rule = NoiseIdRule::kStable32) {
  static const Eigen::VectorXd phasedat = testing::PhaseDatFrequency();
  static const Eigen::VectorXd ocxo = testing::OcxoFractionalFrequency();
  static const Eigen::VectorXd pink = testing::ReadColumn("pink/pink_frequency.txt");
  AllanOptions options;
  options.deviation = c.deviation;
  options.noise_id = rule;
  options.sampled_phase_edf = rule != NoiseIdRule::kStable32;  // Stable32's convention (allan.h)
  const Eigen::VectorXd& y = c.data == Data::kOcxo ? ocxo : c.data == Data::kPink ? pink : phasedat;
  EXPECT_EQ(y.size(), Samples(c.data));
  const AllanResult result = ComputeAllan(y, 1.0, options);
  EXPECT_EQ(result.summary.termination, Termination::kSuccess) << result.summary.message;
  return result.table;
}

// Stable32 (1.53/1.60) computes its Min/Max Sigma from Greenhall's EDF for the noise type in its
// Alpha column and an approximate inverse chi-square (A. Wallin, "Fun with chi-squared", 2020,
// and github.com/aewallin/allantools/issues/101: differences at the 1e-3 level); we use the exact
// quantile. Requirement: bounds within 2 % of Stable32's.
// The OCXO octave reports were run on f / f_mean rather than f / 1e7 - 1, which moves Sigma by up
// to 5e-4 relative against the all-tau reports (checked to 1e-4 in deviation_test): inside 2 %.
//
// With the noise type taken from Stable32's Alpha column, the EDF + chi-square part is checked on
// every row, including those with only 4 averages.
TEST(ComputeAllan, BoundsMatchStable32GivenStable32sNoiseType) {
  for (const OctaveCase& c : OctaveCases()) {
    const auto rows = testing::ReadStable32Report(c.file);
    ASSERT_GE(rows.size(), 8u) << c.file;
    const AllanTable t = Compute(c);
    ASSERT_GE(t.size(), rows.size()) << c.file;
    for (size_t k = 0; k < rows.size(); ++k) {
      ASSERT_EQ(t.m[k], rows[k].m) << c.file;
      const double edf = GreenhallEdf(rows[k].alpha, DifferenceOrder(c.deviation), t.m[k],
                                      Samples(c.data) + 1, IsOverlapping(c.deviation));
      double low = 0.0, high = 0.0;
      ConfidenceBounds(t.sigma[k], edf, 0.683, &low, &high);
      EXPECT_NEAR(low, rows[k].min_sigma, 0.02 * rows[k].min_sigma) << c.file << " m=" << t.m[k];
      EXPECT_NEAR(high, rows[k].max_sigma, 0.02 * rows[k].max_sigma) << c.file << " m=" << t.m[k];
    }
  }
}

// End to end with the Stable32 rule (noise_id.h): every Alpha of the PHASE.DAT, OCXO and
// flicker-FM reports, including the 21 rows with fewer than 30 averages, and both bounds within
// 2 % on every row.
TEST(ComputeAllan, Stable32RuleReproducesStable32sNoiseTypesAndBoundsOnEveryRow) {
  int rows_checked = 0;
  for (const OctaveCase& c : OctaveCases()) {
    const auto rows = testing::ReadStable32Report(c.file);
    const AllanTable t = Compute(c, NoiseIdRule::kStable32);
    for (size_t k = 0; k < rows.size(); ++k) {
      ++rows_checked;
      EXPECT_EQ(t.alpha[k], rows[k].alpha)
          << c.file << " m=" << t.m[k] << " method " << ToString(t.alpha_method[k]);
      EXPECT_NEAR(t.ci_low[k], rows[k].min_sigma, 0.02 * rows[k].min_sigma)
          << c.file << " m=" << t.m[k] << " edf=" << t.edf[k];
      EXPECT_NEAR(t.ci_high[k], rows[k].max_sigma, 0.02 * rows[k].max_sigma)
          << c.file << " m=" << t.m[k] << " edf=" << t.edf[k];
    }
  }
  EXPECT_EQ(rows_checked, 94);
}

// The default (calibrated) rule differs from Stable32's only where its measured coverage is
// better (docs/allan-statistics.md): where the lag-1 method decided alone, the types equal
// Stable32's; the other rows are printed with both intervals.
TEST(ComputeAllan, CalibratedRuleAgreesWithStable32WhereTheLag1MethodDecides) {
  int lag1 = 0, other = 0, differ = 0;
  for (const OctaveCase& c : OctaveCases()) {
    const auto rows = testing::ReadStable32Report(c.file);
    const AllanTable t = Compute(c, NoiseIdRule::kCalibrated);
    for (size_t k = 0; k < rows.size(); ++k) {
      if (t.alpha_method[k] == NoiseIdMethod::kLag1Autocorrelation) {
        ++lag1;
        EXPECT_EQ(t.alpha[k], rows[k].alpha) << c.file << " m=" << t.m[k];
        continue;
      }
      ++other;
      if (t.alpha[k] == rows[k].alpha) continue;
      ++differ;
      std::cout << "  " << c.file << " m=" << t.m[k] << ": " << t.alpha[k] << " by "
                << ToString(t.alpha_method[k]) << ", Stable32 " << rows[k].alpha << "; ["
                << t.ci_low[k] << ", " << t.ci_high[k] << "] vs [" << rows[k].min_sigma << ", "
                << rows[k].max_sigma << "]\n";
    }
  }
  std::cout << "  " << lag1 << " rows by lag-1, " << other << " by other methods, " << differ
            << " of them with another type than Stable32's\n";
  EXPECT_EQ(lag1 + other, 94);
  // Of the 73 rows with >= 30 averages; R(n) or the carry rule decide the rest.
  EXPECT_GE(lag1, 65);
}

TEST(ComputeAllan, ReportsInvalidOptionsAndShortInput) {
  AllanOptions options;
  options.confidence = 1.5;
  EXPECT_EQ(ComputeAllan(Eigen::VectorXd::Ones(100), 1.0, options).summary.termination,
            Termination::kInvalidOptions);
  EXPECT_EQ(ComputeAllan(Eigen::VectorXd::Ones(100), 0.0, AllanOptions()).summary.termination,
            Termination::kInvalidOptions);
  EXPECT_EQ(ComputeAllan(Eigen::VectorXd::Ones(1), 1.0, AllanOptions()).summary.termination,
            Termination::kInsufficientData);
  Eigen::VectorXd bad = Eigen::VectorXd::Ones(100);
  bad[3] = std::nan("");
  EXPECT_EQ(ComputeAllan(bad, 1.0, AllanOptions()).summary.termination,
            Termination::kNumericalFailure);
}

TEST(ComputeAllan, TauIsTheAveragingFactorOverTheSampleRate) {
  AllanOptions options;
  options.confidence_intervals = false;
  const AllanResult r = ComputeAllan(testing::Nbs1000Point(), 100.0, options);
  ASSERT_EQ(r.table.size(), 9u);  // m = 1 .. 256 <= 1000 / 2
  for (size_t k = 0; k < r.table.size(); ++k)
    EXPECT_DOUBLE_EQ(r.table.tau_s[k], static_cast<double>(r.table.m[k]) / 100.0);
  EXPECT_TRUE(std::isnan(r.table.ci_low[0]));
}

// A caller computing many tables (the sweep) passes one phase buffer to every call: each table
// must equal the one computed with a fresh buffer, whatever the buffer held before (a longer or a
// shorter record's phase), and a buffer of the right size must be reused, not reallocated.
TEST(ComputeAllan, AReusedPhaseBufferGivesTheSameTableAndKeepsItsMemory) {
  const Eigen::VectorXd y = testing::Nbs1000Point();
  const Eigen::VectorXd shorter = y.head(700);
  Eigen::VectorXd phase;
  for (const Eigen::VectorXd* rate : {&y, &shorter, &y}) {
    const AllanResult fresh = ComputeAllan(*rate, 10.0, AllanOptions());
    const AllanResult reused = ComputeAllan(*rate, 10.0, AllanOptions(), &phase);
    EXPECT_EQ(reused.table.sigma, fresh.table.sigma);
    EXPECT_EQ(reused.table.edf, fresh.table.edf);
    EXPECT_EQ(reused.table.ci_low, fresh.table.ci_low);
    EXPECT_EQ(reused.table.alpha, fresh.table.alpha);
    EXPECT_EQ(phase, MeanRemovedPhase(*rate));
  }
  const double* memory = phase.data();
  ComputeAllan(y, 10.0, AllanOptions(), &phase);
  EXPECT_EQ(phase.data(), memory);
}

// ---- MDEV, TDEV and TOTDEV against Stable32's octave reports ----------------------------------

/// The Keysight 53230A counter noise-floor record (white PM, allantools tests/
/// Keysight53230A_ti_noise_floor): 55 688 phase points in s, tau0 = 1 s, as rate samples. Not
/// committed (0.9 MB); read from the shared copy beside the clone. Empty if absent.
Eigen::VectorXd SharedTicFrequency() {
  for (const std::string& dir :
       {std::string(FOGPIPE_SOURCE_DIR) + "/../shared/data/allan-reference",
        std::string("/work/shared/data/allan-reference")}) {
    std::ifstream in(dir + "/tic53230a/tic_phase.txt");
    if (!in) continue;
    std::vector<double> x;
    std::string line;
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#') x.push_back(std::stod(line));
    Eigen::VectorXd y(static_cast<Eigen::Index>(x.size()) - 1);
    for (Eigen::Index i = 0; i < y.size(); ++i) y[i] = x[i + 1] - x[i];
    return y;
  }
  return Eigen::VectorXd();
}

std::vector<testing::Stable32Row> SharedTicReport(const std::string& name) {
  for (const std::string& dir :
       {std::string(FOGPIPE_SOURCE_DIR) + "/../shared/data/allan-reference",
        std::string("/work/shared/data/allan-reference")}) {
    const std::string path = dir + "/tic53230a/" + name;
    if (std::ifstream(path)) return testing::ReadStable32ReportAt(path);
  }
  return {};
}

struct NewKindCase {
  const char* file;
  Deviation deviation;
  enum Source { kPhaseDat, kOcxo, kTic } source;
};

const std::vector<NewKindCase>& CommittedNewKindCases() {
  static const std::vector<NewKindCase> cases = {
      {"phasedat/phase_dat_mdev_octave.txt", Deviation::kModifiedAllan, NewKindCase::kPhaseDat},
      {"phasedat/phase_dat_tdev_octave.txt", Deviation::kTime, NewKindCase::kPhaseDat},
      {"phasedat/phase_dat_totdev_octave.txt", Deviation::kTotal, NewKindCase::kPhaseDat},
      {"ocxo/mdev_octave.txt", Deviation::kModifiedAllan, NewKindCase::kOcxo},
      {"ocxo/tdev_octave.txt", Deviation::kTime, NewKindCase::kOcxo},
      {"ocxo/totdev_octave.txt", Deviation::kTotal, NewKindCase::kOcxo},
  };
  return cases;
}

const std::vector<NewKindCase>& CounterNewKindCases() {
  static const std::vector<NewKindCase> cases = {
      {"tic_mdev.txt", Deviation::kModifiedAllan, NewKindCase::kTic},
      {"tic_tdev.txt", Deviation::kTime, NewKindCase::kTic},
      {"tic_totdev.txt", Deviation::kTotal, NewKindCase::kTic},
  };
  return cases;
}

/// The report's rows and our table for one case; false when the data are absent.
bool ComputeNewKind(const NewKindCase& c, std::vector<testing::Stable32Row>* rows,
                    AllanTable* table, long long* n) {
  static const Eigen::VectorXd phasedat = testing::PhaseDatFrequency();
  static const Eigen::VectorXd ocxo = testing::OcxoFractionalFrequency();
  static const Eigen::VectorXd tic = SharedTicFrequency();
  const Eigen::VectorXd& y = c.source == NewKindCase::kOcxo  ? ocxo
                             : c.source == NewKindCase::kTic ? tic
                                                             : phasedat;
  *rows =
      c.source == NewKindCase::kTic ? SharedTicReport(c.file) : testing::ReadStable32Report(c.file);
  if (y.size() == 0 || rows->empty()) return false;
  AllanOptions options;
  options.deviation = c.deviation;
  options.noise_id = NoiseIdRule::kStable32;
  options.sampled_phase_edf = false;  // Stable32's EDF convention (allan.h)
  const AllanResult result = ComputeAllan(y, 1.0, options);
  EXPECT_EQ(result.summary.termination, Termination::kSuccess) << result.summary.message;
  *table = result.table;
  *n = y.size();
  return true;
}

// Sigma to Stable32's 5 printed digits (1e-4 relative, as in deviation_test), the "#" column,
// and, with the noise type of Stable32's Alpha column, both bounds within 2 % on every row:
// MDEV / TDEV by Greenhall's F = 1 EDF, TOTDEV by SP 1065's fits (edf.h).
// The OCXO octave reports were run on other input (their header: Average = 1.000000e+00, i.e.
// f / f_mean): their Sigma differs from the all-tau reports of the same record by up to 1.3e-3
// (MDEV) and 1.2 % (TOTDEV at m = 512; 5e-4 for OADEV, see above). Recomputing TOTDEV from
// f / f_mean in double does not reproduce it (5.133e-12 against 5.1857e-12 at m = 512), so the
// cause is not established. Their Sigma is not
// compared (the all-tau reports check it to 1e-4 in deviation_test), and every report's bounds
// are compared as our ratio bound / sigma times Stable32's Sigma, which isolates EDF and
// chi-square from that difference (for PHASE.DAT and the counter, whose Sigma agrees to 1e-4,
// this changes nothing).
void ExpectStable32RowsGivenItsNoiseType(const NewKindCase& c) {
  std::vector<testing::Stable32Row> rows;
  AllanTable t;
  long long n = 0;
  ASSERT_TRUE(ComputeNewKind(c, &rows, &t, &n)) << c.file;
  ASSERT_GE(rows.size(), 8u) << c.file;
  ASSERT_GE(t.size(), rows.size()) << c.file;
  for (size_t k = 0; k < rows.size(); ++k) {
    ASSERT_EQ(t.m[k], rows[k].m) << c.file;
    EXPECT_EQ(t.count[k], rows[k].count) << c.file << " m=" << t.m[k];
    if (c.source != NewKindCase::kOcxo) {
      EXPECT_NEAR(t.sigma[k], rows[k].sigma, 1e-4 * rows[k].sigma) << c.file << " m=" << t.m[k];
    }
    const double edf = DeviationEdf(c.deviation, rows[k].alpha, t.m[k], n);
    double low = 0.0, high = 0.0;
    ConfidenceBounds(rows[k].sigma, edf, 0.683, &low, &high);
    EXPECT_NEAR(low, rows[k].min_sigma, 0.02 * rows[k].min_sigma)
        << c.file << " m=" << t.m[k] << " edf=" << edf;
    EXPECT_NEAR(high, rows[k].max_sigma, 0.02 * rows[k].max_sigma)
        << c.file << " m=" << t.m[k] << " edf=" << edf;
  }
}

// With the Stable32 noise-identification rule: where our type equals Stable32's Alpha, both
// bounds within 2 %; rows where the types differ are printed and counted.
void ExpectStable32RowsWithOurNoiseType(const NewKindCase& c, int* agree, int* differ) {
  std::vector<testing::Stable32Row> rows;
  AllanTable t;
  long long n = 0;
  ASSERT_TRUE(ComputeNewKind(c, &rows, &t, &n)) << c.file;
  for (size_t k = 0; k < rows.size(); ++k) {
    if (n / t.m[k] >= 30) {
      EXPECT_EQ(t.alpha[k], rows[k].alpha) << c.file << " m=" << t.m[k];
    }
    if (t.alpha[k] != rows[k].alpha) {
      ++*differ;
      std::cout << "  type differs: " << c.file << " m=" << t.m[k] << " ours " << t.alpha[k]
                << " Stable32 " << rows[k].alpha << ": bounds [" << t.ci_low[k] << ", "
                << t.ci_high[k] << "] vs [" << rows[k].min_sigma << ", " << rows[k].max_sigma
                << "]\n";
      continue;
    }
    ++*agree;
    const double scale = rows[k].sigma / t.sigma[k];  // see above: bounds at Stable32's Sigma
    EXPECT_NEAR(t.ci_low[k] * scale, rows[k].min_sigma, 0.02 * rows[k].min_sigma)
        << c.file << " m=" << t.m[k] << " edf=" << t.edf[k];
    EXPECT_NEAR(t.ci_high[k] * scale, rows[k].max_sigma, 0.02 * rows[k].max_sigma)
        << c.file << " m=" << t.m[k] << " edf=" << t.edf[k];
  }
}

TEST(ComputeAllan, ModifiedTimeAndTotalMatchStable32GivenStable32sNoiseType) {
  for (const NewKindCase& c : CommittedNewKindCases()) ExpectStable32RowsGivenItsNoiseType(c);
}

TEST(ComputeAllan, ModifiedTimeAndTotalMatchStable32sTypesAndBoundsWithTheStable32Rule) {
  int agree = 0, differ = 0;
  for (const NewKindCase& c : CommittedNewKindCases())
    ExpectStable32RowsWithOurNoiseType(c, &agree, &differ);
  EXPECT_EQ(differ, 0);
  std::cout << "  " << agree << " rows with Stable32's noise type, " << differ << " with another\n";
  EXPECT_EQ(agree + differ, 65);  // 8 + 8 + 9 + 13 + 13 + 14 rows
}

// The counter's white-PM noise floor: the regime MDEV and TOTDEV's phase-noise EDFs are for.
TEST(ComputeAllan, ModifiedTimeAndTotalMatchStable32OnTheCounterNoiseFloorRecord) {
  if (SharedTicFrequency().size() == 0 || SharedTicReport("tic_mdev.txt").empty())
    GTEST_SKIP() << "shared allan-reference/tic53230a not present";
  int agree = 0, differ = 0;
  for (const NewKindCase& c : CounterNewKindCases()) {
    ExpectStable32RowsGivenItsNoiseType(c);
    ExpectStable32RowsWithOurNoiseType(c, &agree, &differ);
  }
  std::cout << "  " << agree << " rows with Stable32's noise type, " << differ << " with another\n";
}

}  // namespace
}  // namespace fogpipe::allan
