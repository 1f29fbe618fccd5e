#include "algorithms/model/angle_lattice.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>

#include "algorithms/common/units.h"
#include "algorithms/model/compare.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/navigation_grade.h"
#include "hidden_effects.h"
#include "independent_records.h"

namespace fogpipe::model {
namespace {

namespace sim = fogpipe::simulation;

// A continuous record (no counter): white rate noise, a bias and a rate random walk, 1 h at
// 10 Hz, optionally stored as float32 (whose rounding is itself a lattice, of millions of levels).
Eigen::VectorXd ContinuousRate(std::uint64_t seed, bool float32) {
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0xC0DEULL);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Eigen::Index n = 36000;
  const double fs = 10.0;
  const double white = units::DegPerSqrtHourToArw(0.003 + 0.005 * uniform(g)) * std::sqrt(fs);
  const double bias = units::DegPerHourToBias(-20.0 + 40.0 * uniform(g));
  const double walk = units::DegPerHourSqrtHourToRrw(0.01) / std::sqrt(fs);
  Eigen::VectorXd rate(n);
  double wander = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    wander += walk * normal(g);
    rate[k] = bias + wander + white * normal(g);
    if (float32) rate[k] = static_cast<double>(static_cast<float>(rate[k]));
  }
  return rate;
}

// A simulated navigation-grade record (6 h, 10 Hz) of `seed` with fogpipe's undithered angle
// quantizer (`simulate --angle-quantizer`); q_arcsec > 0 sets Q (the step is Q sqrt(12)).
sim::SimulatedRecording QuantizerRecord(std::uint64_t seed, double q_arcsec) {
  sim::GyroSimulatorOptions o = testing::HiddenEffectOptions(seed, {});
  o.errors.quantization_model = sim::QuantizationModel::kAngleQuantizer;
  if (q_arcsec > 0) o.errors.q_rad = units::ArcsecToQuantization(q_arcsec);
  return sim::SimulateGyro(o);
}

// Continuous data are never taken for a counter: most increments are distinct, and even float32
// storage (a lattice of millions of levels) is refused. By construction (angle_lattice.h) the
// on-lattice fraction of continuous data is about 2 level_tolerance = 0.2 %, against 99.9 %
// required, so the false-alarm rate is nil; design seeds 4000-4099 gave 0 of 200 and so must these.
TEST(AngleLattice, ContinuousRecordsAreNeverTakenForACounter) {
  int on_lattice = 0;
  for (std::uint64_t seed = 1; seed <= 100; ++seed) {
    for (bool float32 : {false, true}) {
      const AngleLattice lattice = DetectAngleLattice(ContinuousRate(seed, float32), 10.0);
      EXPECT_TRUE(lattice.evaluated);
      on_lattice += lattice.on_lattice;
      EXPECT_FALSE(lattice.coarse);
    }
  }
  EXPECT_EQ(on_lattice, 0);
  // fogpipe's default quantization noise (white angle noise, `simulate` without
  // --angle-quantizer) is continuous too.
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const sim::SimulatedRecording record =
        sim::SimulateGyro(testing::HiddenEffectOptions(seed, {}));
    EXPECT_FALSE(DetectAngleLattice(record.rate_rad_s, 10.0).on_lattice) << seed;
  }
}

// A counter's step and offset: increments c + q n, n an integer, found to rounding (the SE is
// float32's resolution, 2^-24 q) with and without dither, stored as float64 or float32, and with
// an offset (a constant subtracted after counting).
TEST(AngleLattice, TheStepAndOffsetOfACounterAreFoundToRounding) {
  for (testing::Quantizer quantizer :
       {testing::Quantizer::kDithered, testing::Quantizer::kUndithered}) {
    for (int seed = 3100; seed <= 3109; ++seed) {
      SCOPED_TRACE(seed);
      testing::IndependentRecordOptions ro;
      ro.quantizer = quantizer;
      testing::IndependentRecord record = testing::MakeIndependentRecord(seed, ro);
      const double q = record.q_rad * std::sqrt(12.0);
      const double offset = 0.3 * q;
      const AngleLattice lattice = DetectAngleLattice(record.rate_rad_s, record.fs);
      ASSERT_TRUE(lattice.on_lattice);
      EXPECT_NEAR(lattice.step_rad / q, 1.0, 1e-9);
      EXPECT_LE(std::abs(lattice.step_rad - q), 3.0 * lattice.step_se_rad);
      EXPECT_NEAR(lattice.offset_rad / q, 0.0, 1e-9);
      EXPECT_EQ(lattice.on_lattice_fraction, 1.0);
      // Stored as float32: each level is rounded by at most 2^-24 of itself, so the slope by at
      // most 2^-24 q, one SE.
      const Eigen::VectorXd stored = record.rate_rad_s.cast<float>().cast<double>();
      const AngleLattice float32 = DetectAngleLattice(stored, record.fs);
      ASSERT_TRUE(float32.on_lattice);
      EXPECT_LE(std::abs(float32.step_rad - q), 3.0 * float32.step_se_rad);
      record.rate_rad_s.array() += offset * record.fs;
      const AngleLattice shifted = DetectAngleLattice(record.rate_rad_s, record.fs);
      ASSERT_TRUE(shifted.on_lattice);
      EXPECT_NEAR(shifted.step_rad / q, 1.0, 1e-9);
      EXPECT_NEAR(shifted.offset_rad / q, 0.3, 1e-9);
    }
  }
}

// A rate quantizer much finer than the noise (a MEMS ADC's LSB) with a vibration line: on a
// lattice, and its increments are correlated by the line, but they spread over many steps, so the
// error is not called coarse.
TEST(AngleLattice, AFineRateQuantizerWithAVibrationLineIsNotCoarse) {
  std::mt19937_64 g(77);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double fs = 100.0, lsb_rad_s = units::kRadPerDeg * 0.05;
  Eigen::VectorXd rate(200000);
  for (Eigen::Index k = 0; k < rate.size(); ++k)
    rate[k] = lsb_rad_s *
              std::round((20.0 * std::sin(2.0 * units::kPi * 7.3 * k / fs) + 15.0 * normal(g)));
  const AngleLattice lattice = DetectAngleLattice(rate, fs);
  ASSERT_TRUE(lattice.on_lattice);
  EXPECT_NEAR(lattice.step_rad * fs / lsb_rad_s, 1.0, 1e-9);
  EXPECT_GT(lattice.whiteness_statistic, lattice.whiteness_critical);
  EXPECT_GT(lattice.spread_steps, 10.0);
  EXPECT_FALSE(lattice.coarse);
}

// The coarse test over seeds (independent_records.h: Q in [0.05, 0.2] arcsec, N in [0.003, 0.008]
// deg/sqrt(h), 6 h at 10 Hz; the angle noise per sample over the step, sigma/q, is 0.1-0.7).
// Design seeds 3000-3039 (AngleLatticeStudy; docs/compare.md): dithered, coarse on 0 of 40
// (statistic 8-35 against 63.7, a chi-square(19)'s range); undithered, coarse on all 24 records
// with sigma/q <= 0.315 and on none of the 16 with sigma/q >= 0.343; the default model
// inconsistent on 17, every one of them coarse. CI seeds 3100-3139:
//   dithered: the test's level is 1e-6, so P(any of 40 coarse) = 4e-5 for a calibrated
//     statistic: none may be;
//   undithered, sigma/q <= 0.25 (design: 20 of 20 coarse, the statistic 349-727, 5-11x its
//     critical value): every one coarse;
//   undithered, sigma/q >= 0.45 (the rounding error of Gaussian noise of that sd is uniform to
//     within e^{-2 pi^2 0.45^2} = 2 %: white; design 0 of 8): none coarse;
//   every record the default model finds inconsistent is coarse (design 17 of 17), and its
//   verdict names the coarse angle quantization with the step; no dithered verdict does.
TEST(AngleLattice, UnditheredCountersBelowAThirdOfAStepAreCoarseAndDitheredOnesNever) {
  int dithered_coarse = 0, dithered_named = 0;
  int below = 0, below_coarse = 0, above = 0, above_coarse = 0;
  int inconsistent = 0, inconsistent_coarse = 0, named = 0;
  std::string report;
  for (testing::Quantizer quantizer :
       {testing::Quantizer::kDithered, testing::Quantizer::kUndithered}) {
    for (int seed = 3100; seed <= 3139; ++seed) {
      testing::IndependentRecordOptions ro;
      ro.quantizer = quantizer;
      const testing::IndependentRecord record = testing::MakeIndependentRecord(seed, ro);
      const CompareResult result = Compare(record.Input(), DefaultTerms(), CompareOptions());
      ASSERT_TRUE(HasResult(result.summary.termination));
      const AngleLattice& lattice = result.angle_lattice;
      const double q = record.q_rad * std::sqrt(12.0);
      const double ratio = record.n_rad_sqrt_s / std::sqrt(record.fs) / q;
      EXPECT_TRUE(lattice.on_lattice) << seed;
      if (quantizer == testing::Quantizer::kDithered) {
        dithered_coarse += lattice.coarse;
        dithered_named += result.verdict.coarse_angle_quantization;
        continue;
      }
      report += "seed " + std::to_string(seed) + " sigma/q " + std::to_string(ratio) +
                " statistic " + std::to_string(lattice.whiteness_statistic) + " coarse " +
                std::to_string(lattice.coarse) + ": " + result.verdict.text + "\n";
      if (ratio <= 0.25) {
        ++below;
        below_coarse += lattice.coarse;
      }
      if (ratio >= 0.45) {
        ++above;
        above_coarse += lattice.coarse;
      }
      if (!result.base.views.consistent) {
        ++inconsistent;
        inconsistent_coarse += lattice.coarse;
        const bool names =
            result.verdict.coarse_angle_quantization &&
            result.verdict.text.find("coarse angle quantization") != std::string::npos;
        named += names || result.verdict.consistent_with_suggestion;
      }
    }
  }
  std::printf(
      "dithered: coarse %d of 40, named %d; undithered: sigma/q <= 0.25 coarse %d of %d, >= 0.45 "
      "coarse %d of %d, inconsistent %d, of them coarse %d and named %d\n",
      dithered_coarse, dithered_named, below_coarse, below, above_coarse, above, inconsistent,
      inconsistent_coarse, named);
  EXPECT_EQ(dithered_coarse, 0);
  EXPECT_EQ(dithered_named, 0);
  EXPECT_GT(below, 0);
  EXPECT_EQ(below_coarse, below) << report;
  EXPECT_EQ(above_coarse, 0) << report;
  EXPECT_GT(inconsistent, 0);
  EXPECT_EQ(inconsistent_coarse, inconsistent) << report;
  EXPECT_EQ(named, inconsistent) << report;
}

// `simulate --profile nav --angle-quantizer --q-arcsec 2` (6 h, 10 Hz, no effect): a step of
// 2 sqrt(12) = 6.93 arcsec against an angle noise of 0.1-0.2 arcsec per sample. Design seeds
// 3000-3019: coarse 20 of 20, the default model inconsistent on 20 (error 112-984), the verdict
// `unexplained` on 19 and `inconsistent: suggestion narrow_band` fixing the frequency view only on
// one. CI seeds 3100-3104: the step to rounding, coarse, and the verdict names it.
TEST(AngleLattice, FogpipesUnditheredQuantizerIsACoarseCounterThatTheVerdictNames) {
  for (int seed = 3100; seed <= 3104; ++seed) {
    SCOPED_TRACE(seed);
    const sim::SimulatedRecording record = QuantizerRecord(seed, 2.0);
    CompareInput input;
    input.rate_rad_s = &record.rate_rad_s;
    input.sample_rate_hz = record.truth.options.sample_rate_hz;
    const CompareResult result = Compare(input, DefaultTerms(), CompareOptions());
    ASSERT_TRUE(HasResult(result.summary.termination));
    const AngleLattice& lattice = result.angle_lattice;
    ASSERT_TRUE(lattice.on_lattice);
    EXPECT_NEAR(lattice.step_rad * units::kArcsecPerRad / (2.0 * std::sqrt(12.0)), 1.0, 1e-9);
    EXPECT_TRUE(lattice.coarse) << lattice.message;
    EXPECT_FALSE(result.base.views.consistent);
    EXPECT_TRUE(result.verdict.coarse_angle_quantization) << result.verdict.text;
    EXPECT_NE(result.verdict.text.find("step 6.928 arcsec"), std::string::npos)
        << result.verdict.text;
  }
}

// The verdict's wording: the cause first in "unexplained", a note behind another suggestion that
// leaves failures, the flag alone behind angle_quantizer (the suggestion names it), nothing when
// another suggestion makes the model consistent or the counter is not coarse.
TEST(NameCoarseQuantization, NamesTheCounterOnlyWhereNoSuggestionMakesTheModelConsistent) {
  AngleLattice lattice;
  lattice.on_lattice = lattice.coarse = true;
  lattice.step_rad = units::ArcsecToQuantization(2.0 * std::sqrt(12.0));
  Verdict unexplained;
  unexplained.status = "unexplained";
  unexplained.text = "unexplained: no catalog term makes any failing view (time) pass; failing: x";
  NameCoarseQuantization(lattice, &unexplained);
  EXPECT_TRUE(unexplained.coarse_angle_quantization);
  EXPECT_EQ(unexplained.text.find("unexplained: coarse angle quantization (an undithered angle "
                                  "counter, step 6.928 arcsec"),
            0u)
      << unexplained.text;
  EXPECT_NE(unexplained.text.find("; no catalog term makes any failing view (time) pass"),
            std::string::npos);
  Verdict partial;
  partial.status = "inconsistent";
  partial.text = "inconsistent: suggestion narrow_band (fixes frequency; still failing: y)";
  NameCoarseQuantization(lattice, &partial);
  EXPECT_TRUE(partial.coarse_angle_quantization);
  EXPECT_EQ(partial.text.find("inconsistent: suggestion narrow_band"), 0u);
  EXPECT_NE(partial.text.find("undithered angle counter (step 6.928 arcsec)"), std::string::npos);
  Verdict fixed = partial;
  fixed.coarse_angle_quantization = false;
  fixed.consistent_with_suggestion = true;
  fixed.text = "inconsistent: suggestion sinusoid (makes the model consistent)";
  NameCoarseQuantization(lattice, &fixed);
  EXPECT_FALSE(fixed.coarse_angle_quantization);
  EXPECT_EQ(fixed.text, "inconsistent: suggestion sinusoid (makes the model consistent)");
  Verdict suggested;
  suggested.status = "inconsistent";
  suggested.suggestion = ModelTerm(Term::kAngleQuantizer);
  suggested.text = "inconsistent: suggestion angle_quantizer (step 6.928 arcsec) (fixes time)";
  const std::string text = suggested.text;
  NameCoarseQuantization(lattice, &suggested);
  EXPECT_TRUE(suggested.coarse_angle_quantization);
  EXPECT_EQ(suggested.text, text);
  Verdict consistent;
  NameCoarseQuantization(lattice, &consistent);
  EXPECT_EQ(consistent.text, "consistent");
  lattice.coarse = false;
  Verdict white = unexplained;
  white.coarse_angle_quantization = false;
  white.text = "unexplained: z";
  NameCoarseQuantization(lattice, &white);
  EXPECT_FALSE(white.coarse_angle_quantization);
  EXPECT_EQ(white.text, "unexplained: z");
}

// The seed study behind the tests (not run by ctest):
//   FOGPIPE_LATTICE_CASE=undithered FOGPIPE_STUDY_SEEDS=3000-3039 FOGPIPE_LATTICE_COMPARE=1
//   model_angle_lattice_test --gtest_also_run_disabled_tests --gtest_filter='*Study*'
// FOGPIPE_LATTICE_CASE: continuous (ContinuousRate), dithered, undithered (independent_records.h),
// simulated (fogpipe's quantizer, navigation-grade draws), simulated_q2 (Q 2 arcsec);
// FOGPIPE_LATTICE_COMPARE=1 also prints the default model's verdict.
TEST(AngleLatticeStudy, DISABLED_DetectionOverSeeds) {
  const char* kind_env = std::getenv("FOGPIPE_LATTICE_CASE");
  const char* seeds = std::getenv("FOGPIPE_STUDY_SEEDS");
  const std::string kind = kind_env ? kind_env : "undithered";
  int seed0 = 3000, seed1 = 3039;
  if (seeds) std::sscanf(seeds, "%d-%d", &seed0, &seed1);
  const bool run_compare = std::getenv("FOGPIPE_LATTICE_COMPARE") != nullptr;
  for (int seed = seed0; seed <= seed1; ++seed) {
    Eigen::VectorXd rate;
    CompareInput input;
    double q_true = 0, noise_per_sample = 0;
    testing::IndependentRecord record;
    sim::SimulatedRecording simulated;
    if (kind == "continuous") {
      int on = 0;
      for (bool float32 : {false, true})
        on += DetectAngleLattice(ContinuousRate(static_cast<std::uint64_t>(seed), float32), 10.0)
                  .on_lattice;
      std::printf("LATTICE continuous seed %d | on_lattice (double, float32) %d of 2\n", seed, on);
      continue;
    }
    if (kind == "dithered" || kind == "undithered") {
      testing::IndependentRecordOptions ro;
      ro.quantizer =
          kind == "dithered" ? testing::Quantizer::kDithered : testing::Quantizer::kUndithered;
      record = testing::MakeIndependentRecord(seed, ro);
      input = record.Input();
      q_true = record.q_rad * std::sqrt(12.0);
      noise_per_sample = record.n_rad_sqrt_s / std::sqrt(record.fs);
    } else {
      simulated = QuantizerRecord(seed, kind == "simulated_q2" ? 2.0 : 0.0);
      input.rate_rad_s = &simulated.rate_rad_s;
      input.sample_rate_hz = 10.0;
      q_true = simulated.truth.options.errors.q_rad * std::sqrt(12.0);
      noise_per_sample = simulated.truth.options.errors.n_rad_sqrt_s / std::sqrt(10.0);
    }
    const AngleLattice lattice = DetectAngleLattice(*input.rate_rad_s, input.sample_rate_hz);
    std::printf(
        "LATTICE %s seed %d | sigma/q %.3f q_true %.5g arcsec | on %d frac %.5f levels %d q %.5g "
        "(se %.2g) rel_err %.2e | spread %.3f r1 %.3f Q %.1f crit %.1f coarse %d",
        kind.c_str(), seed, noise_per_sample / q_true, q_true * units::kArcsecPerRad,
        lattice.on_lattice, lattice.on_lattice_fraction, lattice.levels,
        lattice.step_rad * units::kArcsecPerRad, lattice.step_se_rad * units::kArcsecPerRad,
        lattice.step_rad / q_true - 1.0, lattice.spread_steps, lattice.lag1_correlation,
        lattice.whiteness_statistic, lattice.whiteness_critical, lattice.coarse);
    if (run_compare) {
      const CompareResult result = Compare(input, DefaultTerms(), CompareOptions());
      std::printf(" | error %.3g %s", result.base.views.error, result.verdict.text.c_str());
    }
    std::printf("\n");
    std::fflush(stdout);
  }
}

}  // namespace
}  // namespace fogpipe::model
