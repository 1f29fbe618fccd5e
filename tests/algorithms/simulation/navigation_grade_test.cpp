#include "algorithms/simulation/navigation_grade.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/units.h"
#include "algorithms/simulation/gyro_simulator.h"

namespace fogpipe::simulation {
namespace {

using namespace fogpipe::units;

constexpr int kSeeds = 50;

TEST(NavigationGrade, DrawsEveryLevelInsideTheIssueRanges) {
  for (std::uint64_t seed = 0; seed < kSeeds; ++seed) {
    const GyroSimulatorOptions o = NavigationGradeOptions(seed);
    SCOPED_TRACE(seed);
    EXPECT_EQ(o.duration_s, 6.0 * 3600.0);
    EXPECT_EQ(o.sample_rate_hz, 10.0);
    EXPECT_EQ(o.seed, seed);
    const double n = ArwToDegPerSqrtHour(o.errors.n_rad_sqrt_s);
    const double b = BiasToDegPerHour(o.errors.b_rad_s);
    const double k = RrwToDegPerHourSqrtHour(o.errors.k_rad_s_sqrt_s);
    const double q = QuantizationToArcsec(o.errors.q_rad);
    EXPECT_TRUE(n >= 0.003 && n <= 0.008) << n;
    EXPECT_TRUE(b >= 0.002 && b <= 0.006) << b;
    EXPECT_TRUE(k >= 0.002 && k <= 0.010) << k;
    EXPECT_TRUE(q >= 0.05 && q <= 0.2) << q;
    EXPECT_EQ(o.errors.r_rad_s2, 0.0);
    ASSERT_TRUE(o.temperature.has_value());
    EXPECT_TRUE(o.temperature->peak_to_peak_degC >= 6.0 &&
                o.temperature->peak_to_peak_degC <= 12.0);
    EXPECT_TRUE(o.temperature->period_s >= 3600.0 && o.temperature->period_s <= 7200.0);
    // The channel exists but does not touch the rate.
    EXPECT_FALSE(o.errors.temperature || o.errors.temperature_rate);
    std::string error;
    EXPECT_TRUE(o.IsValid(&error)) << error;
  }
}

TEST(NavigationGrade, SeedsGiveDifferentLevels) {
  EXPECT_NE(NavigationGradeOptions(1).errors.n_rad_sqrt_s,
            NavigationGradeOptions(2).errors.n_rad_sqrt_s);
}

TEST(NavigationGrade, PaperProfileIsOneHourAtOneHertzWithTheSameLevels) {
  const GyroSimulatorOptions paper = PaperOptions(3);
  EXPECT_EQ(paper.duration_s, 3600.0);
  EXPECT_EQ(paper.sample_rate_hz, 1.0);
  EXPECT_FALSE(paper.temperature.has_value());
  EXPECT_EQ(paper.errors.b_rad_s, NavigationGradeOptions(3).errors.b_rad_s);
}

// PaperDriftOptions: PaperOptions plus B and K at the paper's Table 5 raw ratios to N.
TEST(NavigationGrade, PaperDriftProfileSetsBAndKAtTheTable5RatiosToN) {
  for (std::uint64_t seed = 0; seed < kSeeds; ++seed) {
    SCOPED_TRACE(seed);
    const GyroSimulatorOptions paper = PaperOptions(seed);
    const GyroSimulatorOptions o = PaperDriftOptions(seed);
    EXPECT_EQ(o.duration_s, 3600.0);
    EXPECT_EQ(o.sample_rate_hz, 1.0);
    EXPECT_EQ(o.seed, seed);
    EXPECT_FALSE(o.temperature.has_value());
    EXPECT_EQ(o.errors.n_rad_sqrt_s, paper.errors.n_rad_sqrt_s);
    EXPECT_EQ(o.errors.q_rad, paper.errors.q_rad);
    EXPECT_EQ(o.errors.bias_rad_s, paper.errors.bias_rad_s);
    EXPECT_EQ(o.errors.r_rad_s2, 0.0);
    const double n = ArwToDegPerSqrtHour(o.errors.n_rad_sqrt_s);
    const double k_over_n = RrwToDegPerHourSqrtHour(o.errors.k_rad_s_sqrt_s) / n;
    const double b_over_n = BiasToDegPerHour(o.errors.b_rad_s) / n;
    // Table 5 raw rows: K/N = 350.1 (VG941) .. 410.6 (VG951), B/N = 4.99 .. 7.07.
    EXPECT_TRUE(k_over_n >= 350.0 && k_over_n <= 411.0) << k_over_n;
    EXPECT_TRUE(b_over_n >= 4.99 && b_over_n <= 7.07) << b_over_n;
    std::string error;
    EXPECT_TRUE(o.IsValid(&error)) << error;
  }
  EXPECT_NE(PaperDriftOptions(1).errors.k_rad_s_sqrt_s, PaperDriftOptions(2).errors.k_rad_s_sqrt_s);
}

// With K/N ~ 380 per hour the Allan terms cross at tau = sqrt(3) N / K ~ 15 s (IEEE Std 952-1997
// C.1, C.4: N^2 / tau = K^2 tau / 3), so the white floor rules at 1 s and the rate random walk
// rules the long taus: check it on the simulated record with non-overlapping cluster averages.
TEST(NavigationGrade, PaperDriftRecordIsWhiteAtOneSecondAndRandomWalkAtLongTau) {
  const GyroSimulatorOptions o = PaperDriftOptions(7);
  const SimulatedRecording rec = SimulateGyro(o);
  ASSERT_EQ(rec.summary.termination, Termination::kSuccess) << rec.summary.message;
  const Eigen::VectorXd& x = rec.rate_rad_s;
  auto avar = [&x](int m) {  // non-overlapped Allan variance at tau = m s (1 Hz)
    const int clusters = static_cast<int>(x.size()) / m;
    double sum = 0.0;
    for (int c = 0; c + 1 < clusters; ++c) {
      const double d = x.segment((c + 1) * m, m).mean() - x.segment(c * m, m).mean();
      sum += d * d;
    }
    return sum / (2.0 * (clusters - 1));
  };
  const double n2 = o.errors.n_rad_sqrt_s * o.errors.n_rad_sqrt_s;
  const double k2 = o.errors.k_rad_s_sqrt_s * o.errors.k_rad_s_sqrt_s;
  const double q2 = o.errors.q_rad * o.errors.q_rad;
  // tau = 1 s: white + quantization (3 Q^2 / tau^2, comparable to N^2 at this grade) + K^2 / 3.
  // 3599 clusters: relative sd of the estimate ~ sqrt(2 / 3598) = 2.4 %; the bias-instability
  // floor (2 ln 2 / pi) B^2 adds < 1 % (B = 5..7 N deg/h vs N 60 deg/h per sqrt(Hz)); 10 % covers
  // 4 sigma plus that.
  EXPECT_NEAR(avar(1) / (n2 + 3.0 * q2 + k2 / 3.0), 1.0, 0.10);
  // tau = 300 s: 11 clusters, about 6 degrees of freedom for random walk (NIST SP 1065 Table 5),
  // so a 95 % interval of x0.21..x2.4 (chi-square / 6); the white and quantization terms are ~1 %.
  const double ratio = avar(300) / (n2 / 300.0 + 3.0 * q2 / 9e4 + k2 * 300.0 / 3.0);
  EXPECT_TRUE(ratio > 0.2 && ratio < 3.0) << ratio;
}

TEST(NavigationGrade, BiasInstabilityFloorIsPoint664B) {
  EXPECT_NEAR(BiasInstabilityFloor(1.0), 0.6643, 1e-4);  // IEEE Std 952-1997 C.3
}

TEST(NavigationGrade, HiddenEffectsAreSizedAgainstTheBiasInstabilityFloor) {
  for (std::uint64_t seed = 0; seed < kSeeds; ++seed) {
    SCOPED_TRACE(seed);
    GyroSimulatorOptions o = NavigationGradeOptions(seed);
    const GyroErrorModel base = o.errors;
    for (Term term : AllTerms()) {
      if (KindOf(term) == TermKind::kDeterministic || term == Term::kSinusoid ||
          term == Term::kGaussMarkov || term == Term::kRateRamp) {
        AddNavigationGradeTerm(term, seed, &o);
      }
    }
    const double f = BiasInstabilityFloor(o.errors.b_rad_s);
    const GyroErrorModel& e = o.errors;
    // Base levels are untouched by adding effects.
    EXPECT_EQ(e.n_rad_sqrt_s, base.n_rad_sqrt_s);
    EXPECT_EQ(e.b_rad_s, base.b_rad_s);
    ASSERT_EQ(e.sinusoids.size(), 1u);
    const double w_peak = 0.725 * e.sinusoids[0].amplitude_rad_s / f;
    EXPECT_TRUE(w_peak >= 3.0 && w_peak <= 6.0) << w_peak;
    EXPECT_TRUE(e.sinusoids[0].frequency_hz >= 1.0 / 300.0 && e.sinusoids[0].frequency_hz <= 0.05);
    ASSERT_EQ(e.gauss_markov.size(), 1u);
    EXPECT_TRUE(e.gauss_markov[0].sigma_rad_s / f >= 3.0 &&
                e.gauss_markov[0].sigma_rad_s / f <= 5.0);
    EXPECT_TRUE(e.gauss_markov[0].correlation_time_s >= 30.0 &&
                e.gauss_markov[0].correlation_time_s <= 300.0);
    ASSERT_EQ(e.bias_steps.size(), 1u);
    const double step = std::abs(e.bias_steps[0].size_rad_s) / f;
    EXPECT_TRUE(step >= 5.0 && step <= 10.0) << step;
    EXPECT_TRUE(e.bias_steps[0].time_s >= 0.2 * o.duration_s &&
                e.bias_steps[0].time_s <= 0.8 * o.duration_s);
    ASSERT_TRUE(e.warmup.has_value());
    EXPECT_TRUE(std::abs(e.warmup->amplitude_rad_s) / f >= 10.0 &&
                std::abs(e.warmup->amplitude_rad_s) / f <= 20.0);
    EXPECT_TRUE(e.warmup->time_constant_s >= 300.0 && e.warmup->time_constant_s <= 1200.0);
    ASSERT_TRUE(e.temperature.has_value());
    const double thermal =
        std::abs(e.temperature->coefficient_rad_s_per_degC) * o.temperature->peak_to_peak_degC / 2;
    EXPECT_TRUE(thermal / f >= 4.0 && thermal / f <= 8.0) << thermal / f;
    EXPECT_EQ(e.temperature->reference_degC, o.temperature->mean_degC);
    ASSERT_TRUE(e.temperature_rate.has_value());
    const double shupe = std::abs(e.temperature_rate->coefficient_rad_s_per_degC_per_s) *
                         MaxAbsTemperatureRate(*o.temperature);
    EXPECT_TRUE(shupe / f >= 4.0 && shupe / f <= 8.0) << shupe / f;
    const double ramp = std::abs(e.r_rad_s2) * (o.duration_s / 10.0) / std::sqrt(2.0) / f;
    EXPECT_TRUE(ramp >= 3.0 && ramp <= 6.0) << ramp;
  }
}

TEST(NavigationGrade, AddingATermTwiceGivesTwoDifferentComponents) {
  GyroSimulatorOptions o = NavigationGradeOptions(9);
  AddNavigationGradeTerm(Term::kSinusoid, 9, &o);
  AddNavigationGradeTerm(Term::kSinusoid, 9, &o);
  ASSERT_EQ(o.errors.sinusoids.size(), 2u);
  EXPECT_NE(o.errors.sinusoids[0].frequency_hz, o.errors.sinusoids[1].frequency_hz);
  // And the same again for the same seed.
  GyroSimulatorOptions again = NavigationGradeOptions(9);
  AddNavigationGradeTerm(Term::kSinusoid, 9, &again);
  EXPECT_EQ(again.errors.sinusoids[0].frequency_hz, o.errors.sinusoids[0].frequency_hz);
}

TEST(NavigationGrade, ThermalTermsBringTheirTemperatureChannelToThePaperProfile) {
  GyroSimulatorOptions o = PaperOptions(4);
  AddNavigationGradeTerm(Term::kTemperatureRate, 4, &o);
  ASSERT_TRUE(o.temperature.has_value());
  std::string error;
  EXPECT_TRUE(o.IsValid(&error)) << error;
}

}  // namespace
}  // namespace fogpipe::simulation
