// Tests of algorithms/method/sweep_evaluate: the sweep's default-rule row must be what `run` does
// with the same options (RunMethod), also when q and R are given explicitly (both configure their
// filters through ComponentFilterOptions, component.h); one Burg recursion gives every lower order;
// the best setting beats the default on a moving rate; the ranking. The grids are tested in
// sweep_grid_test.cpp.
#include "algorithms/method/sweep_evaluate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "algorithms/ar/burg.h"
#include "algorithms/common/units.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/rate_profile.h"
#include "tests/algorithms/method/moving_truth.h"

namespace fogpipe::method {
namespace {

namespace sim = fogpipe::simulation;

constexpr double kSampleRateHz = 10.0;
constexpr int kArOrder = 4;

/// 10 Hz, 300 s (3000 samples): angle random walk, a Gauss-Markov bias and a moving true rate, so
/// the EMD gives several IMFs with real dynamics. 3000 samples stay below the sweep's cap of 4096
/// time-varying Kalman steps (sweep_evaluate.cpp), so `run` and the sweep filter with the same
/// schedule and their outputs can be compared to the last bit.
sim::SimulatedRecording MovingRateRecording() {
  sim::GyroSimulatorOptions o;
  o.sample_rate_hz = kSampleRateHz;
  o.duration_s = 300.0;
  o.seed = 20261121;
  o.errors.n_rad_sqrt_s = units::DegPerSqrtHourToArw(0.05);
  o.errors.gauss_markov.push_back({units::DegPerHourToRadPerSecond(1.0), 5.0});
  std::string error;
  EXPECT_TRUE(sim::ParseRateProfile("step:100:20,sine:0.02:10", &o.input_rate, &error)) << error;
  const sim::SimulatedRecording rec = sim::SimulateGyro(o);
  EXPECT_EQ(rec.summary.termination, Termination::kSuccess) << rec.summary.message;
  return rec;
}

/// Method options with the AR order fixed to the sweep's single order, so that `run` and the
/// sweep's default row use the same AR(p) models (the sweep takes order p from one Burg
/// recursion, FitAr's fixed order runs the same recursion: OneBurgRecursionGivesEveryLowerOrder-
/// Model in the sweep part's tests).
MethodOptions FixedOrderOptions(double q, double r) {
  MethodOptions options;
  options.component.ar.fixed_order = kArOrder;
  options.component.kalman.q = q;
  options.component.kalman.r = r;
  return options;
}

const SweepPoint& DefaultRow(const SweepResult& sweep) {
  for (const SweepPoint& point : sweep.points) {
    if (point.setting.default_rule) return point;
  }
  ADD_FAILURE() << "the sweep has no default-rule row";
  return sweep.points.front();
}

/// Checks that the sweep's default row equals RunMethod's method 1 exactly: Allan table, noise
/// terms, RMS error against the truth and the per-component fit %.
void ExpectDefaultRowEqualsRun(const sim::SimulatedRecording& rec, const MethodOptions& options) {
  const MethodResult run = RunMethod(rec.rate_rad_s, kSampleRateHz, options);
  ASSERT_TRUE(HasResult(run.summary.termination)) << run.summary.message;

  SweepOptions sweep_options;
  sweep_options.method = options;
  sweep_options.grid = {{kArOrder}, {1.0}, {1.0}};
  const SweepResult sweep =
      RunSweep(rec.rate_rad_s, kSampleRateHz, sweep_options, &rec.true_rate_rad_s);
  ASSERT_EQ(sweep.summary.termination, Termination::kSuccess) << sweep.summary.message;
  const SweepPoint& row = DefaultRow(sweep);
  ASSERT_TRUE(HasResult(row.termination)) << row.message;
  ASSERT_EQ(sweep.summary.num_imfs, run.summary.num_imfs);

  // Same arithmetic on the same models: equal to the last bit, not within a tolerance.
  const allan::AllanTable& a = row.allan.allan.table;
  const allan::AllanTable& b = run.method1_allan.allan.table;
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 8u);  // 3000 samples at 10 Hz: an octave grid from 0.1 s
  EXPECT_EQ(a.tau_s, b.tau_s);
  EXPECT_EQ(a.sigma, b.sigma);
  EXPECT_EQ(a.edf, b.edf);
  const allan::NoiseTerms& s = row.allan.noise.terms;
  const allan::NoiseTerms& t = run.method1_allan.noise.terms;
  EXPECT_EQ(s.q_rad, t.q_rad);
  EXPECT_EQ(s.n_rad_sqrt_s, t.n_rad_sqrt_s);
  EXPECT_EQ(s.b_rad_s, t.b_rad_s);
  EXPECT_EQ(s.k_rad_s_sqrt_s, t.k_rad_s_sqrt_s);
  EXPECT_EQ(s.r_rad_s2, t.r_rad_s2);

  // The filtered output itself, through the RMS error against the truth (the sweep keeps no
  // series): the sweep's formula applied to run's method-1 output.
  const Eigen::Index dropped = run.preprocessed.summary.dropped_samples;
  const Eigen::Index n = run.method1.size();
  const Eigen::ArrayXd error = (run.method1.array() + run.preprocessed.mean_removed) -
                               rec.true_rate_rad_s.segment(dropped, n).array();
  EXPECT_EQ(row.rms_error, std::sqrt(error.square().mean()));

  ASSERT_EQ(row.fit_one_step_percent.size(), run.components.size());
  for (std::size_t k = 0; k < run.components.size(); ++k) {
    EXPECT_EQ(row.fit_one_step_percent[k], run.components[k].fit.diagnostics.fit_one_step_percent)
        << ComponentName(static_cast<int>(k), run.summary.num_imfs);
  }
}

TEST(SweepEvaluate, DefaultRowEqualsRunWithTheNoiseRule) {
  ExpectDefaultRowEqualsRun(MovingRateRecording(), FixedOrderOptions(-1.0, -1.0));
}

TEST(SweepEvaluate, DefaultRowEqualsRunWithExplicitQAndR) {
  const sim::SimulatedRecording rec = MovingRateRecording();
  // q and R far from what the rule picks (R about the per-sample white variance, q small), so a
  // sweep that fell back to the rule would differ; checked first on `run` itself.
  const double sigma_w = units::DegPerSqrtHourToArw(0.05) * std::sqrt(kSampleRateHz);
  const MethodOptions explicit_options =
      FixedOrderOptions(1e-4 * sigma_w * sigma_w, sigma_w * sigma_w);
  const MethodResult rule = RunMethod(rec.rate_rad_s, kSampleRateHz, FixedOrderOptions(-1, -1));
  const MethodResult given = RunMethod(rec.rate_rad_s, kSampleRateHz, explicit_options);
  ASSERT_TRUE(HasResult(rule.summary.termination)) << rule.summary.message;
  ASSERT_TRUE(HasResult(given.summary.termination)) << given.summary.message;
  ASSERT_NE(rule.method1_allan.allan.table.sigma, given.method1_allan.allan.table.sigma);
  ASSERT_NE(rule.method1, given.method1);
  ExpectDefaultRowEqualsRun(rec, explicit_options);
}

// The default grid (11 AR orders x 3 q scales x 3 R scales, plus each order's default rule, as in
// the README) on the moving-truth records of one seed: no setting may fail. High orders on the
// slowest IMFs have coefficients that are not stationary once rounded to double, or constant-gain
// loops that grow, or transients that dwarf the component; each such component runs at the
// highest lower order that works (ar_order_used says which), as `run` does. The fallback must be
// exercised, or the test would not test it.
TEST(SweepEvaluate, NoSettingOfTheDefaultGridFailsOnMovingTruthRecords) {
  SweepOptions options;  // the default grid
  int settings = 0, lowered = 0;
  for (const testing::MovingTruthRecord& r : testing::MovingTruthGrid({101})) {
    const SweepResult sweep = RunSweep(r.rate_rad_s, r.sample_rate_hz, options, &r.true_rate_rad_s);
    ASSERT_EQ(sweep.summary.termination, Termination::kSuccess) << sweep.summary.message;
    for (const SweepPoint& point : sweep.points) {
      ++settings;
      EXPECT_TRUE(HasResult(point.termination))
          << r.scenario << " N " << r.n_deg_sqrt_h << " AR(" << point.setting.ar_order << ") q x"
          << point.setting.q_scale << " R x" << point.setting.r_scale << ": " << point.message;
      EXPECT_TRUE(std::isfinite(point.rms_error));
      ASSERT_EQ(point.ar_order_used.size(), point.fit_one_step_percent.size());
      for (int used : point.ar_order_used) {
        EXPECT_LE(used, point.setting.ar_order);
        if (used > 0 && used < point.setting.ar_order) {
          ++lowered;
          break;
        }
      }
    }
  }
  std::printf("%d settings, %d with some component at a lower order than asked\n", settings,
              lowered);
  EXPECT_GT(lowered, 0);
}

/// A step, a ramp and a sinusoid of the input rate (deg/h): the truth moves within the record.
constexpr const char* kMovingRateProfile = "step:300:20,ramp:900:1200:0.05,sine:0.005:10";

/// A 10 Hz gyro with angle random walk N = 0.05 deg/sqrt(h) (per-sample sigma 9.5 deg/h).
sim::GyroSimulatorOptions TenHertzWhiteNoise(double duration_s, std::uint64_t seed) {
  sim::GyroSimulatorOptions o;
  o.sample_rate_hz = 10.0;
  o.duration_s = duration_s;
  o.seed = seed;
  o.errors.n_rad_sqrt_s = units::DegPerSqrtHourToArw(0.05);
  return o;
}

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
  ASSERT_TRUE(sim::ParseRateProfile(kMovingRateProfile, &o.input_rate, &error)) << error;
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
