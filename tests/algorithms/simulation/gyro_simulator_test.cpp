#include "algorithms/simulation/gyro_simulator.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/units.h"
#include "algorithms/simulation/navigation_grade.h"

namespace fogpipe::simulation {
namespace {

GyroSimulatorOptions Small() {
  GyroSimulatorOptions o;
  o.sample_rate_hz = 10.0;
  o.duration_s = 2000.0;
  o.seed = 77;
  o.errors.n_rad_sqrt_s = units::DegPerSqrtHourToArw(0.005);
  o.errors.b_rad_s = units::DegPerHourToBias(0.004);
  o.errors.k_rad_s_sqrt_s = units::DegPerHourSqrtHourToRrw(0.005);
  o.errors.q_rad = units::ArcsecToQuantization(0.1);
  o.errors.bias_rad_s = units::DegPerHourToBias(0.02);
  TemperatureProfile t;
  t.period_s = 1000.0;
  o.temperature = t;
  return o;
}

TEST(SimulateGyro, ProducesTheRequestedSampleCountAndChannels) {
  const SimulatedRecording r = SimulateGyro(Small());
  ASSERT_EQ(r.summary.termination, Termination::kSuccess) << r.summary.message;
  EXPECT_EQ(r.rate_rad_s.size(), 20000);
  EXPECT_EQ(r.temperature_degC.size(), 20000);
  EXPECT_EQ(r.true_rate_rad_s.size(), 20000);
  EXPECT_EQ(r.truth.num_samples, 20000);
  EXPECT_EQ(r.truth.terms, (std::vector<Term>{Term::kWhite, Term::kQuantization,
                                              Term::kBiasInstability, Term::kRateRandomWalk}));
}

TEST(SimulateGyro, InvalidOptionsAreReportedAsDataNotExceptions) {
  GyroSimulatorOptions o = Small();
  o.errors.temperature = TemperatureEffect{1e-7, 25.0};
  o.temperature.reset();
  SimulatedRecording r = SimulateGyro(o);
  EXPECT_EQ(r.summary.termination, Termination::kInvalidOptions);
  EXPECT_NE(r.summary.message.find("temperature"), std::string::npos);
  EXPECT_EQ(r.rate_rad_s.size(), 0);

  o = Small();
  o.errors.sinusoids.push_back({6.0, 1e-6, 0.0});  // above Nyquist at 10 Hz
  EXPECT_EQ(SimulateGyro(o).summary.termination, Termination::kInvalidOptions);
  o = Small();
  o.errors.n_rad_sqrt_s = -1.0;
  EXPECT_EQ(SimulateGyro(o).summary.termination, Termination::kInvalidOptions);
  o = Small();
  o.duration_s = 0.1;
  EXPECT_EQ(SimulateGyro(o).summary.termination, Termination::kInvalidOptions);
}

TEST(SimulateGyro, SameSeedIsBitIdenticalAndOtherSeedsOrAxesDiffer) {
  const SimulatedRecording a = SimulateGyro(Small());
  const SimulatedRecording b = SimulateGyro(Small());
  EXPECT_EQ(a.rate_rad_s, b.rate_rad_s);
  EXPECT_EQ(a.temperature_degC, b.temperature_degC);
  GyroSimulatorOptions o = Small();
  o.seed = 78;
  EXPECT_NE(SimulateGyro(o).rate_rad_s, a.rate_rad_s);
  o = Small();
  o.axis = 1;
  const SimulatedRecording other_axis = SimulateGyro(o);
  EXPECT_NE(other_axis.rate_rad_s, a.rate_rad_s);
  // One chamber for all axes of a file.
  EXPECT_EQ(other_axis.temperature_degC, a.temperature_degC);
}

TEST(SimulateGyro, AddingAnEffectLeavesTheOtherTermsRealisationUntouched) {
  // Every term has its own stream: the difference is exactly the added effect.
  GyroSimulatorOptions with = Small();
  with.errors.sinusoids.push_back({0.02, 3e-8, 0.4});
  with.errors.bias_steps.push_back({1000.0, 5e-8});
  with.errors.gauss_markov.push_back({2e-8, 50.0});
  const SimulatedRecording base = SimulateGyro(Small());
  const SimulatedRecording added = SimulateGyro(with);
  GyroSimulatorOptions only = with;
  only.errors = GyroErrorModel{};
  only.errors.sinusoids = with.errors.sinusoids;
  only.errors.bias_steps = with.errors.bias_steps;
  only.errors.gauss_markov = with.errors.gauss_markov;
  const SimulatedRecording effect = SimulateGyro(only);
  const double scale = base.rate_rad_s.cwiseAbs().maxCoeff();
  // Only the order of floating-point additions differs: a few eps of the largest term.
  EXPECT_LT((added.rate_rad_s - base.rate_rad_s - effect.rate_rad_s).cwiseAbs().maxCoeff(),
            1e-14 * scale);
}

TEST(SimulateGyro, TheTrueRateIsTheInputProfilePlusTheEarthRateProjection) {
  GyroSimulatorOptions o;
  o.sample_rate_hz = 1.0;
  o.duration_s = 100.0;
  o.latitude_deg = 30.0;  // sin 30 deg = 1/2
  std::string error;
  ASSERT_TRUE(ParseRateProfile("step:50:10", &o.input_rate, &error));
  const SimulatedRecording r = SimulateGyro(o);
  ASSERT_EQ(r.summary.termination, Termination::kSuccess);
  EXPECT_NEAR(r.truth.earth_rate_rad_s, 0.5 * kEarthRotationRateRadS, 1e-19);
  EXPECT_NEAR(r.true_rate_rad_s[10], 0.5 * kEarthRotationRateRadS, 1e-19);
  EXPECT_NEAR(r.true_rate_rad_s[60],
              0.5 * kEarthRotationRateRadS + units::DegPerHourToRadPerSecond(10.0), 1e-19);
  // No error terms: a perfect gyro.
  EXPECT_EQ(r.rate_rad_s, r.true_rate_rad_s);
  EXPECT_EQ(r.temperature_degC.size(), 0);
}

TEST(SimulateGyro, ThermalEffectsFollowTheTrueTemperatureNotTheNoisyChannel) {
  GyroSimulatorOptions o;
  o.sample_rate_hz = 10.0;
  o.duration_s = 3000.0;
  TemperatureProfile t;
  t.period_s = 1500.0;
  t.noise_std_degC = 0.005;
  o.temperature = t;
  o.errors.temperature = TemperatureEffect{3e-8, 25.0};
  o.errors.temperature_rate = TemperatureRateEffect{2e-6};
  const SimulatedRecording r = SimulateGyro(o);
  ASSERT_EQ(r.summary.termination, Termination::kSuccess);
  const Eigen::Index n = r.rate_rad_s.size();
  const Eigen::VectorXd true_t = SampleTrueTemperature(t, n, 10.0);
  const Eigen::VectorXd expected =
      (true_t.array() - 25.0) * 3e-8 + SampleTrueTemperatureRate(t, n, 10.0).array() * 2e-6;
  EXPECT_LT((r.rate_rad_s - expected).cwiseAbs().maxCoeff(), 1e-20);
  // The recorded channel is the true temperature plus white sensor noise of 0.005 degC.
  const Eigen::VectorXd noise = r.temperature_degC - true_t;
  const double var = noise.squaredNorm() / n;
  EXPECT_NEAR(var / (0.005 * 0.005), 1.0, 5.0 * std::sqrt(2.0 / n));
}

TEST(SimulateGyro, WithAnAngleQuantizerTheOutputAngleStaysOnItsGrid) {
  GyroSimulatorOptions o = Small();
  o.errors.quantization_model = QuantizationModel::kAngleQuantizer;
  o.latitude_deg = 45.0;
  const SimulatedRecording r = SimulateGyro(o);
  ASSERT_EQ(r.summary.termination, Termination::kSuccess);
  const double step = o.errors.q_rad * std::sqrt(12.0);
  double angle = 0.0;
  double worst = 0.0;
  for (Eigen::Index k = 0; k < r.rate_rad_s.size(); ++k) {
    angle += r.rate_rad_s[k] / o.sample_rate_hz;
    worst = std::max(worst, std::abs(angle / step - std::round(angle / step)));
  }
  EXPECT_LT(worst, 1e-6);  // the test's own summation error over 2e4 samples, in steps
}

TEST(SimulateGyro, TheFullNavigationGradeRecordHasTheWhiteNoiseLevelAtShortTau) {
  // At tau = 0.1 s the Allan variance of the navigation profile is N^2 / tau + 3 Q^2 / tau^2 plus
  // negligible B, K terms; the per-sample variance of first differences of the rate is, for the
  // white and quantization terms alone, 2 N^2 fs + 6 Q^2 fs^2 (differencing w_k and the second
  // difference of the angle noise). B and K add < 0.1 % at these levels.
  const GyroSimulatorOptions o = NavigationGradeOptions(5);
  const SimulatedRecording r = SimulateGyro(o);
  ASSERT_EQ(r.summary.termination, Termination::kSuccess);
  const Eigen::Index n = r.rate_rad_s.size();
  ASSERT_EQ(n, 216000);
  const Eigen::VectorXd d = r.rate_rad_s.tail(n - 1) - r.rate_rad_s.head(n - 1);
  const double fs = o.sample_rate_hz;
  const double n2 = o.errors.n_rad_sqrt_s * o.errors.n_rad_sqrt_s;
  const double q2 = o.errors.q_rad * o.errors.q_rad;
  const double expected = 2.0 * n2 * fs + 6.0 * q2 * fs * fs;
  // Differences are correlated at lag 1 and 2 (|rho| <= 2/3); Var of the mean square <= 5 x the
  // independent value 2 / n.
  EXPECT_NEAR(d.squaredNorm() / (n - 1) / expected, 1.0, 5.0 * std::sqrt(10.0 / n) + 1e-3);
}

}  // namespace
}  // namespace fogpipe::simulation
