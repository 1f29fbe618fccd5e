// Tests of algorithms/method/sweep_grid and sweep_evaluate (the sweep logic; lives here because
// the sweep part owns tests/pipeline/graph/sweep_*).
#include "algorithms/method/sweep_evaluate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "algorithms/ar/burg.h"
#include "algorithms/common/units.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/rate_profile.h"

namespace fogpipe::method {
namespace {

namespace sim = fogpipe::simulation;

/// A 10 Hz gyro with angle random walk N = 0.05 deg/sqrt(h) (per-sample sigma 9.5 deg/h).
sim::GyroSimulatorOptions TenHertzWhiteNoise(double duration_s, std::uint64_t seed) {
  sim::GyroSimulatorOptions o;
  o.sample_rate_hz = 10.0;
  o.duration_s = duration_s;
  o.seed = seed;
  o.errors.n_rad_sqrt_s = units::DegPerSqrtHourToArw(0.05);
  return o;
}

TEST(SweepGrid, ParsesRangesListsAndLogSpacedScales) {
  std::vector<int> orders;
  std::string error;
  ASSERT_TRUE(ParseIntList("2:12", &orders, &error));
  EXPECT_EQ(orders.size(), 11u);
  EXPECT_EQ(orders.front(), 2);
  EXPECT_EQ(orders.back(), 12);
  ASSERT_TRUE(ParseIntList("2:8:3", &orders, &error));
  EXPECT_EQ(orders, (std::vector<int>{2, 5, 8}));
  ASSERT_TRUE(ParseIntList("6,2,4", &orders, &error));
  EXPECT_EQ(orders, (std::vector<int>{6, 2, 4}));
  EXPECT_FALSE(ParseIntList("12:2", &orders, &error));
  EXPECT_FALSE(ParseIntList("2,x", &orders, &error));

  std::vector<double> scales;
  ASSERT_TRUE(ParseScaleList("0.1,1,10", &scales, &error));
  EXPECT_EQ(scales, (std::vector<double>{0.1, 1.0, 10.0}));
  ASSERT_TRUE(ParseScaleList("0.01:100:5", &scales, &error));
  ASSERT_EQ(scales.size(), 5u);
  // Log-spaced: 0.01, 0.1, 1, 10, 100 up to rounding of pow.
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(std::log10(scales[i]), i - 2.0, 1e-12);
  EXPECT_FALSE(ParseScaleList("0:1:3", &scales, &error));
}

TEST(SweepGrid, ListsSettingsOrderMajorAndRejectsBadValues) {
  SweepGrid grid{{2, 3}, {0.1, 1.0}, {1.0, 10.0, 100.0}};
  const auto settings = GridSettings(grid);
  // Per order: the default rule, then 2 q scales x 3 R scales.
  ASSERT_EQ(settings.size(), 14u);
  EXPECT_EQ(grid.size(), 14);
  EXPECT_TRUE(settings[0].default_rule);
  EXPECT_EQ(settings[0].ar_order, 2);
  EXPECT_FALSE(settings[1].default_rule);
  EXPECT_EQ(settings[6].ar_order, 2);
  EXPECT_TRUE(settings[7].default_rule);
  EXPECT_EQ(settings[7].ar_order, 3);
  EXPECT_EQ(settings[2].r_scale, 10.0);
  EXPECT_EQ(settings[4].q_scale, 1.0);
  std::string error;
  EXPECT_TRUE(grid.IsValid(&error));
  grid.q_scales = {0.0};
  EXPECT_FALSE(grid.IsValid(&error));
}

// One Burg recursion to order P gives the models of every lower order: the order-p model of a
// recursion run to P equals a recursion run only to p (Levinson structure, Kay & Marple 1981).
// The sweep relies on this to fit each component once.
TEST(SweepEvaluate, OneBurgRecursionGivesEveryLowerOrderModel) {
  sim::GyroSimulatorOptions o = TenHertzWhiteNoise(300.0, 3);
  o.errors.gauss_markov.push_back({units::DegPerHourToRadPerSecond(1.0), 5.0});
  const Eigen::VectorXd x = sim::SimulateGyro(o).rate_rad_s;
  const ar::OrderSequence all = ar::BurgAllOrders(x, 12, x.mean());
  for (int p : {2, 6, 11}) {
    const ar::OrderSequence low = ar::BurgAllOrders(x, p, x.mean());
    // Identical arithmetic up to order p: equal to the last bit.
    EXPECT_EQ((all.phi[p - 1] - low.phi[p - 1]).cwiseAbs().maxCoeff(), 0.0) << "order " << p;
  }
}

// The sweep's acceptance test: on a recording whose true rate moves (a step, a ramp and a
// sinusoid of the rate table) the best setting of the sweep has a lower RMS error against the
// truth than `fogpipe run`'s rule (at every order) and than the hardest filtering (the smallest
// q / R, at every order): over-smoothing costs, so the optimum is a real trade-off.
TEST(SweepEvaluate, BestSettingBeatsDefaultAndHardestFilteringOnAMovingRate) {
  sim::GyroSimulatorOptions o = TenHertzWhiteNoise(1800.0, 20261121);
  o.errors.b_rad_s = units::DegPerHourToRadPerSecond(0.05);
  std::string error;
  ASSERT_TRUE(sim::ParseRateProfile(SWEEP_TEST_RATE_PROFILE, &o.input_rate, &error)) << error;
  const sim::SimulatedRecording rec = sim::SimulateGyro(o);
  ASSERT_EQ(rec.summary.termination, Termination::kSuccess) << rec.summary.message;

  SweepOptions options;
  options.grid = {{2, 4, 6, 8}, {0.01, 0.1, 1.0, 10.0}, {0.1, 1.0, 10.0, 100.0}};
  const SweepResult result =
      RunSweep(rec.rate_rad_s, o.sample_rate_hz, options, &rec.true_rate_rad_s);
  ASSERT_EQ(result.summary.termination, Termination::kSuccess) << result.summary.message;
  ASSERT_EQ(result.points.size(), 68u);
  // A setting may fail only as a diverged filter (RunSweep's check): here AR(6) at the hardest
  // q/R, whose estimate of imf9 has 36x the component's RMS; left in, its RMS error against the
  // truth was 233 deg/h, 25x the unfiltered signal's.
  for (const SweepPoint& p : result.points) {
    if (HasResult(p.termination)) continue;
    std::printf("  p=%d q=%g R=%g: %s\n", p.setting.ar_order, p.setting.q_scale, p.setting.r_scale,
                p.message.c_str());
    EXPECT_NE(p.message.find("Kalman filter diverged"), std::string::npos) << p.message;
  }
  EXPECT_GE(result.summary.settings_ok, 60);

  const std::vector<int> ranking = RankSweep(result.points, "rms_error");
  ASSERT_FALSE(ranking.empty());
  const SweepPoint& best = result.points[ranking.front()];
  double default_rms = INFINITY, hardest_rms = INFINITY, raw_rms = 0.0;
  for (const SweepPoint& p : result.points) {
    if (!HasResult(p.termination)) continue;
    if (p.setting.default_rule) default_rms = std::min(default_rms, p.rms_error);
    if (!p.setting.default_rule && p.setting.q_scale == 0.01 && p.setting.r_scale == 100.0) {
      hardest_rms = std::min(hardest_rms, p.rms_error);
    }
  }
  raw_rms = std::sqrt((rec.rate_rad_s - rec.true_rate_rad_s).array().square().mean());
  std::printf("  setting                 RMS error vs truth [deg/h]\n");
  std::printf("  raw signal              %10.4f\n", units::RadPerSecondToDegPerHour(raw_rms));
  std::printf("  best (p=%d q=%g R=%g)   %10.4f\n", best.setting.ar_order, best.setting.q_scale,
              best.setting.r_scale, units::RadPerSecondToDegPerHour(best.rms_error));
  std::printf("  run's rule (best p)     %10.4f\n", units::RadPerSecondToDegPerHour(default_rms));
  std::printf("  hardest q=0.01 R=100    %10.4f\n", units::RadPerSecondToDegPerHour(hardest_rms));
  ASSERT_TRUE(std::isfinite(default_rms) && std::isfinite(hardest_rms));
  EXPECT_LT(best.rms_error, default_rms);
  EXPECT_LT(best.rms_error, hardest_rms);
  // Filtering must help at all: the best setting beats the unfiltered signal.
  EXPECT_LT(best.rms_error, raw_rms);
  // Per-IMF fit % is reported for every component.
  EXPECT_EQ(best.fit_one_step_percent.size(),
            static_cast<std::size_t>(result.summary.num_imfs + 1));
}

TEST(SweepEvaluate, RanksFitDescendingAndNoiseTermsAscending) {
  std::vector<SweepPoint> points(3);
  for (int i = 0; i < 3; ++i) points[i].termination = Termination::kSuccess;
  points[0].fit_one_step_percent = {50.0};
  points[1].fit_one_step_percent = {90.0};
  points[2].fit_one_step_percent = {70.0};
  points[0].rms_error = 3.0;
  points[1].rms_error = NAN;
  points[2].rms_error = 1.0;
  EXPECT_EQ(RankSweep(points, "fit"), (std::vector<int>{1, 2, 0}));
  EXPECT_EQ(RankSweep(points, "rms_error"), (std::vector<int>{2, 0, 1}));
  EXPECT_THROW(CriterionValue(points[0], "nonsense"), std::invalid_argument);
}

}  // namespace
}  // namespace fogpipe::method
