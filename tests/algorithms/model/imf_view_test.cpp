// Tests of the IMF view (algorithms/model/imf_view.cpp) against known truth:
//   - the expected energies it derives from the measured EMD filter bank follow the white-noise
//     dyadic law of Wu & Huang (2004), E_k T_k = const, and add up to the white variance;
//   - pure white noise and the effect-free navigation-grade control flag no IMF, over seeds;
//   - a hidden sinusoid flags the IMF whose mean period matches 1 / f0;
//   - a hidden thermal effect flags the IMF of the temperature cycle, and that IMF correlates with
//     the aux temperature.
// Recordings from fogpipe::simulation (hidden_effects.h); the truth is read only to score.
#include "algorithms/model/imf_view.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/units.h"
#include "algorithms/model/compare.h"
#include "algorithms/simulation/random.h"
#include "hidden_effects.h"

namespace fogpipe::model {
namespace {

namespace sim = fogpipe::simulation;

// Navigation-grade white noise: N = 0.005 deg/sqrt(h) at 10 Hz.
const double kN = 0.005 * units::kRadPerDeg / 60.0;  // rad/sqrt(s)

Eigen::VectorXd WhiteRate(std::uint64_t seed, long n, double fs) {
  sim::RandomSource rng(seed);
  return rng.Normals(n) * (kN * std::sqrt(fs));
}

StochasticModel WhiteModel(double n_rad_sqrt_s) {
  StochasticModel m;
  m.terms = {Term::kWhite};
  m.n_rad_sqrt_s = n_rad_sqrt_s;
  return m;
}

// The base model's evaluation and IMF view, as Compare() computes them.
struct Evaluated {
  Evaluation base;
  testing::HiddenCase hidden;
};
Evaluated EvaluateDefault(std::uint64_t seed, const std::vector<sim::Term>& effects) {
  Evaluated out;
  out.hidden = testing::MakeHiddenCase(seed, effects);
  out.hidden.input.rate_rad_s = &out.hidden.recording.rate_rad_s;
  CompareOptions o;
  const auto prepared = PrepareAux(out.hidden.input.aux, out.hidden.recording.rate_rad_s.size(),
                                   out.hidden.input.sample_rate_hz, o.views);
  out.base = EvaluateModel(out.hidden.input, DefaultTerms(), o, &prepared);
  out.base.imf = ComputeImfView(out.base.deterministic.residual, out.hidden.input.sample_rate_hz,
                                prepared, out.base.stochastic.model, o.imf);
  return out;
}

// Index of the IMF whose mean period is closest (in log) to period_s.
int ClosestImf(const ImfView& v, double period_s) {
  int best = 0;
  for (int k = 1; k < static_cast<int>(v.mean_period_s.size()); ++k)
    if (std::abs(std::log(v.mean_period_s[k] / period_s)) <
        std::abs(std::log(v.mean_period_s[best] / period_s)))
      best = k;
  return best;
}

TEST(ImfView, ExpectedEnergiesFollowTheWhiteNoiseDyadicLaw) {
  const double fs = 10.0;
  const Eigen::VectorXd x = WhiteRate(7, 1L << 15, fs);
  const ImfView v = ComputeImfView(x, fs, {}, WhiteModel(kN), ImfViewOptions());
  ASSERT_EQ(v.summary.termination, Termination::kSuccess) << v.summary.message;
  ASSERT_GE(v.summary.num_imfs, 8);
  // Wu & Huang (2004): ln E_k + ln T_k = const, i.e. slope -1 of ln E against ln T. The same band
  // as the EMD's own white-noise test (tests/algorithms/emd): [-1.15, -0.85], fitted over IMFs
  // 2 .. K-2 (IMF 1 and the last ones deviate, as in Wu & Huang's Fig. 2).
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int count = 0;
  for (int k = 1; k + 2 < v.summary.num_imfs; ++k) {
    const double lx = std::log(v.mean_period_s[k]), ly = std::log(v.expected_energy[k]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly, ++count;
  }
  const double slope = (count * sxy - sx * sy) / (count * sxx - sx * sx);
  EXPECT_GT(slope, -1.15);
  EXPECT_LT(slope, -0.85);
}

TEST(ImfView, PureWhiteNoiseFlagsNoImfOverSeeds) {
  // 6 h at 10 Hz (decimated 4x inside). alpha = 5 % family-wise: over 8 seeds at most one
  // seed may flag something (P(>= 2 of 8) <= 6 % even at the full 5 %).
  const double fs = 10.0;
  const long n = 6 * 3600 * 10;
  const ImfViewOptions o;
  const int seeds = 8;
  int seeds_with_flags = 0;
  std::vector<double> sum_log(6, 0.0), edf(6, 0.0);
  for (int seed = 1; seed <= seeds; ++seed) {
    const ImfView v = ComputeImfView(WhiteRate(seed, n, fs), fs, {}, WhiteModel(kN), o);
    ASSERT_EQ(v.summary.termination, Termination::kSuccess);
    EXPECT_GE(v.summary.num_scored, 8);
    seeds_with_flags += v.summary.num_flagged > 0;
    for (int k = 0; k < 6; ++k) {
      sum_log[k] += std::log(v.ratio[k]);
      edf[k] = v.edf[k];
    }
  }
  EXPECT_LE(seeds_with_flags, 1);
  // Calibration of the expected energies, IMFs 1-6 (hundreds of cycles each): the mean of
  // ln(energy / expected) over the seeds is 0 within 3 standard errors, the data's sampling error
  // sqrt(2 / nu / seeds) and the reference's sqrt(2 / nu / R) (common to all seeds).
  for (int k = 0; k < 6; ++k) {
    const double se = std::sqrt(2.0 / edf[k] * (1.0 / seeds + 1.0 / o.reference_realizations));
    EXPECT_LT(std::abs(sum_log[k] / seeds), 3.0 * se) << "imf " << k + 1;
  }
}

TEST(ImfView, AnImfWithTooMuchEnergyIsFlagged) {
  // White noise against a model with half its N: every IMF has 4x the expected energy, z =
  // ln 4 / sqrt(2 / nu (1 + 1/R) + c^2) ~ 9 > critical for the well-sampled ones. The ratio is 4
  // within the reference's and the data's sampling error (nu > 2000 for IMFs 1-5: < 5 %) and the
  // mode-mixing scatter c = 0.15: 4 exp(+-0.16) -> [3.4, 4.7].
  const double fs = 10.0;
  const ImfView v =
      ComputeImfView(WhiteRate(3, 1L << 15, fs), fs, {}, WhiteModel(0.5 * kN), ImfViewOptions());
  ASSERT_EQ(v.summary.termination, Termination::kSuccess);
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(std::log(v.ratio[k] / 4.0), 0.0, 0.16) << k;
    EXPECT_EQ(v.flagged[k], 1) << k;
  }
}

TEST(ImfView, TheNavigationGradeControlRarelyFlagsAnImf) {
  // Effect-free recordings (N, Q, B, K; aux temperature innocent), the default model. Measured
  // on the development seeds 1-20: 3 of 20 flag an IMF, always one of the lowest scored IMFs
  // (periods 1000-2700 s), where flicker and random-walk energy scatter most (one of the three
  // models is not consistent anyway). Over these 10 disjoint seeds at most 2 (1.5 expected).
  int seeds_with_flags = 0;
  for (std::uint64_t seed = 201; seed <= 210; ++seed) {
    const Evaluated e = EvaluateDefault(seed, {});
    ASSERT_EQ(e.base.imf.summary.termination, Termination::kSuccess);
    seeds_with_flags += e.base.imf.summary.num_flagged > 0;
  }
  EXPECT_LE(seeds_with_flags, 2);
}

TEST(ImfView, AHiddenSinusoidFlagsTheImfOfItsPeriod) {
  for (std::uint64_t seed : {101, 102}) {
    const Evaluated e = EvaluateDefault(seed, {sim::Term::kSinusoid});
    const ImfView& v = e.base.imf;
    ASSERT_EQ(v.summary.termination, Termination::kSuccess);
    const double period = 1.0 / e.hidden.recording.truth.options.errors.sinusoids[0].frequency_hz;
    const int k = ClosestImf(v, period);
    EXPECT_EQ(v.flagged[k], 1) << "seed " << seed << " period " << period << " imf " << k + 1
                               << " z " << v.z[k];
    // EMD's IMFs are an octave apart: the matching IMF's mean period within a factor 1.5.
    EXPECT_LT(std::abs(std::log(v.mean_period_s[k] / period)), std::log(1.5));
  }
}

TEST(ImfView, AHiddenThermalEffectFlagsTheImfOfTheCycleThatFollowsTemperature) {
  // The cycle (1-2 h) completes only 3-6 times in 6 h, so its IMF has ~10 degrees of freedom and
  // mode mixing may share the effect between two neighbouring IMFs: we ask for a flagged IMF
  // within a factor 2 of the temperature period that follows the temperature, |r| > 0.6 (noise
  // gives r with standard error ~ 1 / sqrt(nu) ~ 0.3), in at least 3 of 4 seeds.
  int found = 0;
  for (std::uint64_t seed : {101, 102, 201, 202}) {
    const Evaluated e = EvaluateDefault(seed, {sim::Term::kTemperature});
    const ImfView& v = e.base.imf;
    ASSERT_EQ(v.summary.termination, Termination::kSuccess);
    ASSERT_EQ(v.aux_names.size(), 1u);
    const double period = e.hidden.recording.truth.options.temperature->period_s;
    bool ok = false;
    for (int k = 0; k < v.summary.num_imfs; ++k)
      ok = ok || (v.flagged[k] && std::abs(std::log(v.mean_period_s[k] / period)) < std::log(2.0) &&
                  std::abs(v.aux_r[0][k]) > 0.6);
    found += ok;
  }
  EXPECT_GE(found, 3);
}

TEST(ImfView, ComputeIsDeterministicAndInvalidOptionsAreReported) {
  const double fs = 10.0;
  const Eigen::VectorXd x = WhiteRate(5, 20000, fs);
  const ImfView a = ComputeImfView(x, fs, {}, WhiteModel(kN), ImfViewOptions());
  const ImfView b = ComputeImfView(x, fs, {}, WhiteModel(kN), ImfViewOptions());
  EXPECT_EQ(a.energy, b.energy) << "same input + options -> same numbers";
  EXPECT_EQ(a.expected_energy.size(), b.expected_energy.size());
  for (size_t k = 0; k < a.expected_energy.size(); ++k)
    if (std::isfinite(a.expected_energy[k])) EXPECT_EQ(a.expected_energy[k], b.expected_energy[k]);
  ImfViewOptions bad;
  bad.reference_realizations = 0;
  EXPECT_EQ(ComputeImfView(x, fs, {}, WhiteModel(kN), bad).summary.termination,
            Termination::kInvalidOptions);
  EXPECT_EQ(
      ComputeImfView(x.head(10), fs, {}, WhiteModel(kN), ImfViewOptions()).summary.termination,
      Termination::kInsufficientData);
}

}  // namespace
}  // namespace fogpipe::model
