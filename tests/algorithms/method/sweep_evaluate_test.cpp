// Tests algorithms/method/sweep_evaluate.cpp against `fogpipe run`'s own code path (RunMethod):
// the sweep's default-rule row must be what `run` does with the same options, also when q and R
// are given explicitly (both configure their filters through ApplyFilterNoise, component.h; the
// sweep once ignored an explicit --q/--r). The grid logic itself is tested in
// tests/pipeline/graph/sweep_evaluate_test.cpp (the sweep part's tests).
#include "algorithms/method/sweep_evaluate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

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

}  // namespace
}  // namespace fogpipe::method
