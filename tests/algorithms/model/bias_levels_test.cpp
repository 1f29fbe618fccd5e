// Tests of algorithms/model/bias_levels.cpp and the proof of the bias_levels term in
// `fogpipe compare` on hidden-effect recordings (hidden_effects.h).
#include "algorithms/model/bias_levels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <random>
#include <string>

#include "algorithms/common/units.h"
#include "algorithms/model/compare.h"
#include "hidden_effects.h"

namespace fogpipe::model {
namespace {

double DegH(double rad_s) { return units::RadPerSecondToDegPerHour(rad_s); }

// White noise with three steps: the fit finds them and leaves no level in its residual.
TEST(FitDeterministic, ThreeStepsInWhiteNoiseAreFittedAndRemoved) {
  const double fs = 10.0, sigma = 1.0;
  const long n = 36000;
  std::mt19937_64 g(7);
  std::normal_distribution<double> e(0.0, sigma);
  Eigen::VectorXd x(n);
  const std::vector<double> times = {600.0, 1700.0, 2900.0}, sizes = {0.3, -0.5, 0.4};
  for (long i = 0; i < n; ++i) {
    x[i] = e(g);
    for (size_t j = 0; j < times.size(); ++j) x[i] += i / fs >= times[j] ? sizes[j] : 0.0;
  }
  const DeterministicFit f = FitDeterministic(x, fs, nullptr, {Term::kBiasLevels}, {});
  ASSERT_EQ(f.model.components.size(), 1u);
  const auto& c = f.model.components[0];
  ASSERT_EQ(c.step_times_s.size(), 3u);
  for (size_t j = 0; j < 3; ++j) {
    EXPECT_NEAR(c.step_times_s[j], times[j], 20.0);
    EXPECT_NEAR(c.coefficients[j], sizes[j], 0.1);
  }
  EXPECT_TRUE(SegmentLevels(f.residual, fs, {}).step_index.empty());
}

// The proof on hidden-effect recordings (hidden_effects.h: navigation grade, 6 h at 10 Hz):
// `steps` adds 3-5 bias steps (AddBiasSteps), `telegraph` random telegraph switching of mean
// dwell 300 s (AddTelegraph), both sized to a peak Allan signature drawn in [3, 5] times the
// noise floor; `control` is effect-free with three innocent aux channels (AddInnocentAux);
// `gm` carries a true Gauss-Markov term (hidden_effects.h sizes) and no steps.
// Criteria per seed: inconsistent before; bias_levels the first suggestion; its step count the
// truth's; every step time within 19.4 S / D^2 + 1/fs of the truth and every size within
// max(10 %, 3 SE); consistent with it. 19.4 is the 99 % quantile of |argmax (W(u) - |u| / 2)|,
// the law of a change-point estimate in noise of long-run level S (s per S / D^2; Hinkley 1970;
// Yao 1987), computed by simulating the two-sided drifted Brownian motion (4000 draws, step
// 0.02). S = tau sigma_A^2(tau) of the truth's noise at the localisation scale tau = 19.4 N^2 /
// D^2 (N^2 for white noise alone; bias instability and rate random walk add to it there).
struct LevelsProof {
  bool inconsistent_before = false, first_is_levels = false, k_right = false, params_right = false,
       consistent_after = false, levels_suggested = false;
  int k_true = 0, k_fit = 0;
  std::string first, verdict, worst, detail;
};

// The study's override of the signature (FOGPIPE_LEVELS_SIGNATURE; 0: drawn).
double g_signature_override = 0;

double SignatureK(int seed) {
  if (g_signature_override > 0) return g_signature_override;
  // k in [3, 5], its own stream (independent of the effect's draws).
  std::mt19937_64 g(static_cast<std::uint64_t>(seed) * 0x9E3779B97F4A7C15ULL + 0x51C0ULL);
  return 3.0 + 2.0 * static_cast<double>(g() >> 11) * 0x1.0p-53;
}

LevelsProof ScoreLevels(const std::string& kind, int seed) {
  auto c = kind == "gm" ? testing::MakeHiddenCase(seed, {simulation::Term::kGaussMarkov})
                        : testing::MakeHiddenCase(seed, {});
  testing::BiasLevels truth;
  if (kind == "steps") truth = testing::AddBiasSteps(SignatureK(seed), seed, &c);
  if (kind == "telegraph") truth = testing::AddTelegraph(SignatureK(seed), 300.0, seed, &c);
  if (kind == "control") testing::AddInnocentAux(seed, &c);
  const CompareResult r = Compare(c.input, DefaultTerms(), {});
  LevelsProof p;
  p.inconsistent_before = !r.base.views.consistent;
  p.first = r.verdict.suggestion ? ToString(*r.verdict.suggestion) : "-";
  p.verdict = r.verdict.text;
  p.first_is_levels = r.verdict.suggestion && *r.verdict.suggestion == Term::kBiasLevels;
  p.consistent_after = p.first_is_levels && r.verdict.consistent_with_suggestion;
  p.k_true = static_cast<int>(truth.step_time_s.size());
  for (const auto& s : r.suggestions) p.levels_suggested |= s.term == Term::kBiasLevels;
  if (!p.first_is_levels) return p;
  const auto& ps = r.suggestions.front().parameters;
  p.k_fit = static_cast<int>(ps.front().value);
  p.k_right = p.k_fit == p.k_true;
  if (!p.k_right) return p;
  const double n2 = std::pow(c.recording.truth.options.errors.n_rad_sqrt_s, 2);
  const double fs = c.input.sample_rate_hz;
  p.params_right = true;
  double worst = 0;
  for (int j = 0; j < p.k_true; ++j) {
    const Parameter& t = ps[1 + 2 * j];
    const Parameter& d = ps[2 + 2 * j];
    const double d_true = truth.step_size_rad_s[j];
    // The noise's level near the step over the localisation scale itself: tau sigma_A^2(tau) of
    // the truth's noise (N^2 for white noise alone) at tau = 19.4 N^2 / D^2.
    const double scale_s = 19.4 * n2 / (d_true * d_true);
    const double level2 =
        scale_s *
        std::pow(testing::NoiseAllanDeviation(c.recording.truth.options.errors, scale_s), 2);
    const double time_tolerance = 19.4 * level2 / (d_true * d_true) + 1.0 / fs;
    const double size_tolerance = std::max(0.1 * std::abs(DegH(d_true)), 3.0 * d.standard_error);
    const double e = std::max(std::abs(t.value - truth.step_time_s[j]) / time_tolerance,
                              std::abs(d.value - DegH(d_true)) / size_tolerance);
    worst = std::max(worst, e);
    char b[160];
    std::snprintf(b, sizeof b, " [t %.2f D %.2f]",
                  std::abs(t.value - truth.step_time_s[j]) / time_tolerance,
                  std::abs(d.value - DegH(d_true)) / size_tolerance);
    p.detail += b;
  }
  p.params_right = worst < 1.0;
  p.worst = std::to_string(worst);
  return p;
}

std::string Row(const LevelsProof& p) {
  char b[200];
  std::snprintf(b, sizeof b, "incons %d first %d (%s) k %d/%d params %d (worst %s) after %d",
                p.inconsistent_before, p.first_is_levels, p.first.c_str(), p.k_fit, p.k_true,
                p.params_right, p.worst.c_str(), p.consistent_after);
  return b;
}

// White noise alone: the segmentation (modified BIC) chooses no step in at least 19 of 20
// records (its false-alarm rate per record is that of a ~5 % test or less; seeds 1-20).
TEST(SegmentLevels, FindsNoLevelsInWhiteNoise) {
  int with_steps = 0;
  for (int seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 g(static_cast<std::uint64_t>(seed));
    std::normal_distribution<double> e(0.0, 1.0);
    Eigen::VectorXd x(36000);
    for (long i = 0; i < x.size(); ++i) x[i] = e(g);
    with_steps += SegmentLevels(x, 10.0, {}).step_index.empty() ? 0 : 1;
  }
  EXPECT_LE(with_steps, 1);
}

TEST(DescribeLevels, ReadsTwoAlternatingLevelsAsTelegraphSwitching) {
  const double record_s = 3600;
  const std::vector<double> se(6, 0.01);
  const LevelsReading r = DescribeLevels({0.0, 1.0, 0.02, 1.01, -0.01, 1.0}, se, record_s);
  EXPECT_TRUE(r.telegraph_like);
  EXPECT_EQ(r.num_levels, 2);
  EXPECT_DOUBLE_EQ(r.mean_dwell_s, record_s / 6);
  EXPECT_DOUBLE_EQ(r.gm_correlation_time_s, record_s / 12);
  // Half the separation of the group means (3.01 / 3 and 0.01 / 3).
  EXPECT_NEAR(r.half_separation_rad_s, 0.5 * (3.01 / 3 - 0.01 / 3), 1e-12);
  // Two alternating levels over five dwells: too few switches to call it telegraph.
  EXPECT_FALSE(DescribeLevels({0.0, 1.0, 0.0, 1.0, 0.0}, se, record_s).telegraph_like);
  // Three distinct levels (a staircase) are not a telegraph process.
  const LevelsReading s = DescribeLevels({0.0, 1.0, 2.0, 3.0}, {0.01, 0.01, 0.01, 0.01}, record_s);
  EXPECT_FALSE(s.telegraph_like);
  EXPECT_EQ(s.num_levels, 4);
}

// CI seeds (never tuned on; the design seeds are in docs/compare.md): steps 121-125. Thresholds:
// the 5 % binomial lower bound of 5 draws at the design rates over seeds 1-20 (inconsistent and
// first 19/20 -> 4; consistent after 18/20 -> 3; k right 14/20 -> 2; parameters right 11/20 ->
// 1).
TEST(CompareBiasLevels, SeveralBiasStepsAreFoundCountedEstimatedAndFixed) {
  int counts[5] = {0, 0, 0, 0, 0};
  std::string report;
  for (int seed = 121; seed <= 125; ++seed) {
    const LevelsProof p = ScoreLevels("steps", seed);
    counts[0] += p.inconsistent_before;
    counts[1] += p.first_is_levels;
    counts[2] += p.k_right;
    counts[3] += p.params_right;
    counts[4] += p.consistent_after;
    report += "seed " + std::to_string(seed) + ": " + Row(p) + " | " + p.verdict + "\n";
  }
  EXPECT_GE(counts[0], 4) << report;
  EXPECT_GE(counts[1], 4) << report;
  EXPECT_GE(counts[2], 2) << report;
  EXPECT_GE(counts[3], 1) << report;
  EXPECT_GE(counts[4], 3) << report;
  std::cout << report;
}

// Controls: effect-free records with three innocent aux channels (CI seeds 241-250; design
// 201-240 in docs/compare.md): bias_levels suggested in at most 10 % (1 of 10); records with a
// true Gauss-Markov term and no step (CI seeds 141-145): bias_levels never first.
TEST(CompareBiasLevels, IsRarelySuggestedWithoutLevelsAndNeverBeforeGaussMarkov) {
  int suggested = 0, first_on_gm = 0;
  std::string report;
  for (int seed = 241; seed <= 250; ++seed) {
    const LevelsProof p = ScoreLevels("control", seed);
    suggested += p.levels_suggested;
    report += "control seed " + std::to_string(seed) + ": " + p.verdict + "\n";
  }
  for (int seed = 141; seed <= 145; ++seed) {
    const LevelsProof p = ScoreLevels("gm", seed);
    first_on_gm += p.first_is_levels;
    report += "gm seed " + std::to_string(seed) + ": " + p.verdict + "\n";
  }
  EXPECT_LE(suggested, 1) << report;
  EXPECT_EQ(first_on_gm, 0) << report;
}

// Random telegraph switching at a peak Allan signature of 3-5 times the floor and a mean dwell
// of 300 s (CI seeds 121-125): over design seeds 1-20 the levels test found no levels in any
// (the separation is ~1-2 sigma of a 10 s mean) and gauss_markov, whose spectrum it has, was
// suggested on 15. The output must say that the record cannot tell them apart, not guess.
TEST(CompareBiasLevels, TelegraphSwitchingItCannotResolveIsSaidToBeIndistinguishable) {
  for (int seed = 121; seed <= 125; ++seed) {
    auto c = testing::MakeHiddenCase(seed, {});
    testing::AddTelegraph(SignatureK(seed), 300.0, seed, &c);
    const CompareResult r = Compare(c.input, DefaultTerms(), {});
    for (const Suggestion& s : r.suggestions) {
      if (s.term == Term::kGaussMarkov && r.base.views.time.levels_ratio <= 1.0) {
        EXPECT_NE(s.evidence.find("cannot tell them apart"), std::string::npos)
            << "seed " << seed << ": " << s.evidence;
      }
    }
  }
}

TEST(BiasLevelsStudy, DISABLED_PassCountsOverSeeds) {
  const char* seeds = std::getenv("FOGPIPE_LEVELS_SEEDS");
  const char* kind = std::getenv("FOGPIPE_LEVELS_KIND");
  ASSERT_TRUE(seeds && kind);
  int seed0 = 0, seed1 = 0;
  ASSERT_EQ(std::sscanf(seeds, "%d-%d", &seed0, &seed1), 2);
  if (const char* k = std::getenv("FOGPIPE_LEVELS_SIGNATURE")) g_signature_override = std::atof(k);
  int counts[6] = {0, 0, 0, 0, 0, 0};
  for (int seed = seed0; seed <= seed1; ++seed) {
    const LevelsProof p = ScoreLevels(kind, seed);
    counts[0] += p.inconsistent_before;
    counts[1] += p.first_is_levels;
    counts[2] += p.k_right;
    counts[3] += p.params_right;
    counts[4] += p.consistent_after;
    counts[5] += p.levels_suggested;
    std::printf("PROOF %s seed %d: %s | %s |%s\n", kind, seed, Row(p).c_str(), p.verdict.c_str(),
                p.detail.c_str());
  }
  std::printf(
      "TOTAL %s %s: inconsistent %d first %d k %d params %d consistent_after %d "
      "levels_suggested %d of %d\n",
      kind, seeds, counts[0], counts[1], counts[2], counts[3], counts[4], counts[5],
      seed1 - seed0 + 1);
}

}  // namespace
}  // namespace fogpipe::model
