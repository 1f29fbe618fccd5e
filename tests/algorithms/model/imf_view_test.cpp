// Tests of the IMF view (algorithms/model/imf_view.cpp) against known truth:
//   - the expected energies it derives from the measured EMD filter bank follow the white-noise
//     dyadic law of Wu & Huang (2004), E_k T_k = const, and add up to the white variance;
//   - pure white noise and the effect-free navigation-grade control flag an IMF on no more
//     records than the family-wise 5 % allows (binomial bound over seeds);
//   - a hidden sinusoid flags the IMF whose mean period matches 1 / f0;
//   - a hidden thermal effect flags the IMF of the temperature cycle through the right aux test
//     (temperature for `temperature`, its derivative for `temperature_rate`).
// Recordings from fogpipe::simulation (hidden_effects.h); the truth is read only to score.
#include "algorithms/model/imf_view.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

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
// The evaluation of `terms` on a hidden case and its IMF view.
Evaluation EvaluateWithImfView(const testing::HiddenCase& hidden,
                               const std::vector<ModelTerm>& terms) {
  CompareOptions o;
  const auto prepared = PrepareAux(hidden.input.aux, hidden.recording.rate_rad_s.size(),
                                   hidden.input.sample_rate_hz, o.views);
  Evaluation e = EvaluateModel(hidden.input, terms, o, &prepared);
  e.imf = ComputeImfView(e.deterministic.residual, hidden.input.sample_rate_hz, prepared,
                         e.stochastic.model, o.imf);
  return e;
}

Evaluated EvaluateDefault(std::uint64_t seed, const std::vector<sim::Term>& effects) {
  Evaluated out;
  out.hidden = testing::MakeHiddenCase(seed, effects);
  out.hidden.input.rate_rad_s = &out.hidden.recording.rate_rad_s;
  out.base = EvaluateWithImfView(out.hidden, DefaultTerms());
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
  double lambda = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    const ImfView v = ComputeImfView(WhiteRate(seed, n, fs), fs, {}, WhiteModel(kN), o);
    ASSERT_EQ(v.summary.termination, Termination::kSuccess);
    EXPECT_GE(v.summary.num_scored, 8);
    seeds_with_flags += v.summary.num_flagged > 0;
    for (int k = 0; k < 6; ++k) {
      sum_log[k] += std::log(v.ratio[k]);
      edf[k] = v.edf[k];
    }
    lambda = v.log_variance_ratio;
  }
  EXPECT_LE(seeds_with_flags, 1);
  // Calibration of the expected energies, IMFs 1-6 (hundreds of cycles each): the mean of
  // ln(energy / expected) over the seeds is 0 within 3 standard errors, the data's sampling error
  // sqrt(lambda 2 / nu / seeds) and the reference's sqrt(lambda 2 / nu / R) (common to all
  // seeds; the model is the truth here, so the reference's mean of ln energy is unbiased).
  for (int k = 0; k < 6; ++k) {
    const double se =
        std::sqrt(lambda * 2.0 / edf[k] * (1.0 / seeds + 1.0 / o.reference_realizations));
    EXPECT_LT(std::abs(sum_log[k] / seeds), 3.0 * se) << "imf " << k + 1;
  }
}

TEST(ImfView, AnImfWithTooMuchEnergyIsFlagged) {
  // White noise against a model with half its N: every IMF has 4x the expected energy, z =
  // ln 4 / sqrt(lambda 2 / nu (1 + 1/R)) >> critical for the well-sampled ones. The ratio is 4
  // within 4 of its predicted standard deviations log_sd (the reference's and the data's
  // sampling error; the model has no parameter error here): a false failure has probability
  // 6e-5 per IMF.
  const double fs = 10.0;
  const ImfView v =
      ComputeImfView(WhiteRate(3, 1L << 15, fs), fs, {}, WhiteModel(0.5 * kN), ImfViewOptions());
  ASSERT_EQ(v.summary.termination, Termination::kSuccess);
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(std::log(v.ratio[k] / 4.0), 0.0, 4.0 * v.log_sd[k]) << k;
    EXPECT_EQ(v.flagged[k], 1) << k;
  }
}

TEST(ImfView, EffectFreeNavigationGradeRecordsAreFlaggedAtMostAtTheNominalRate) {
  // Calibration of the whole view (energy and aux tests of every scored IMF, Holm at 5 % per
  // record) on effect-free recordings (N, Q, B, K; the aux temperature cycles but does not act
  // on the rate), analysed with the fitted default model as compare does. If the per-record rate
  // were exactly 5 %, P(>= 5 flagged records of 40) = 4.8 % (binomial): more than 4 fails the
  // test. Seeds 1001-1040 are disjoint from the development seeds 1-200 (0 of 200 flagged).
  const int seeds = 40;
  int seeds_with_flags = 0;
  for (std::uint64_t seed = 1001; seed < 1001 + seeds; ++seed) {
    const Evaluated e = EvaluateDefault(seed, {});
    ASSERT_EQ(e.base.imf.summary.termination, Termination::kSuccess);
    seeds_with_flags += e.base.imf.summary.num_flagged > 0;
  }
  EXPECT_LE(seeds_with_flags, 4);
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

// Seeds on which a record with a vibration band (1.5 Hz, damping 2 %, peak 10x the white floor;
// hidden_effects.h AddNarrowBand) has an IMF flagged, analysed with the default model and with the
// default model + narrow_band.
struct BandFlags {
  int without_band_term = 0, with_band_term = 0;
};
BandFlags SeedsFlaggedWithABand(std::uint64_t first, std::uint64_t last) {
  BandFlags flags;
  for (std::uint64_t seed = first; seed <= last; ++seed) {
    testing::HiddenCase c = testing::MakeHiddenCase(seed, {});
    testing::AddNarrowBand(1.5, 0.02, 10.0, seed, &c);
    c.input.rate_rad_s = &c.recording.rate_rad_s;
    std::vector<ModelTerm> terms = DefaultTerms();
    const Evaluation without = EvaluateWithImfView(c, terms);
    terms.push_back(Term::kNarrowBand);
    const Evaluation with = EvaluateWithImfView(c, terms);
    EXPECT_EQ(with.imf.summary.termination, Termination::kSuccess);
    EXPECT_EQ(with.stochastic.model.bands.size(), 1u) << "seed " << seed;
    flags.without_band_term += without.imf.summary.num_flagged > 0;
    flags.with_band_term += with.imf.summary.num_flagged > 0;
  }
  return flags;
}

TEST(ImfView, AModelWithTheVibrationBandIsNotFlaggedForIt) {
  // The reference realizations carry the model's narrow bands (SimulateNarrowBand, block-averaged
  // like the residual). Without them the band's IMFs were flagged against a reference that lacks
  // it, however well the band was fitted: with the narrow_band term in the model, 17 of 20 design
  // seeds (750-769) and 9 of 10 test seeds (770-779) had an IMF flagged; now 0 and 0. With the
  // band in the model the view must be flagged at most at its nominal rate, 5 % per record
  // (Holm): P(>= 3 of 10) = 1.2 % (binomial), so at most 2 of the 10 test seeds. (Without the term
  // the view flags the misfit band on 9 of 20 and 3 of 10: the residual is decimated 4x to 2.5 Hz
  // by block means, which attenuate and alias the 1.5 Hz band; the frequency view is the one that
  // finds it.)
  const BandFlags flags = SeedsFlaggedWithABand(770, 779);
  EXPECT_LE(flags.with_band_term, 2);
}

TEST(ImfView, DISABLED_VibrationBandDesignSeeds) {
  const BandFlags flags = SeedsFlaggedWithABand(750, 769);
  std::printf("design seeds 750-769: flagged without the term %d / 20, with it %d / 20\n",
              flags.without_band_term, flags.with_band_term);
}

// Counts the seeds on which an IMF within a factor 2 of the temperature period is flagged by the
// aux test of the channel's value (derivative = false) or of its derivative.
int SeedsFlaggedOnTheThermalImf(const std::vector<std::uint64_t>& seeds, sim::Term effect,
                                bool derivative) {
  int found = 0;
  for (std::uint64_t seed : seeds) {
    const Evaluated e = EvaluateDefault(seed, {effect});
    const ImfView& v = e.base.imf;
    EXPECT_EQ(v.summary.termination, Termination::kSuccess);
    EXPECT_EQ(v.aux_names.size(), 1u);
    if (v.aux_names.size() != 1u) continue;
    const double period = e.hidden.recording.truth.options.temperature->period_s;
    const std::vector<double>& z = derivative ? v.aux_z_derivative[0] : v.aux_z[0];
    bool ok = false;
    for (int k = 0; k < v.summary.num_imfs; ++k)
      ok = ok || (v.flagged[k] && std::abs(std::log(v.mean_period_s[k] / period)) < std::log(2.0) &&
                  std::abs(z[k]) > v.aux_critical);
    found += ok;
  }
  return found;
}

TEST(ImfView, AHiddenThermalEffectFlagsTheImfOfTheCycleThroughTheTemperatureTest) {
  // The cycle (1-2 h) completes only 3-6 times in 6 h: the slow IMF and the temperature share
  // ~10-60 independent values (n_eff), which limits the power. Measured on the development seeds
  // 1-40: 25 of 40 (62 %) flag an IMF within a factor 2 of the period through the temperature
  // test. On the disjoint seeds 101-110 at least 3 of 10: at a true rate of 62 %, fewer has
  // probability 0.9 % (binomial).
  std::vector<std::uint64_t> seeds;
  for (std::uint64_t s = 101; s <= 110; ++s) seeds.push_back(s);
  EXPECT_GE(SeedsFlaggedOnTheThermalImf(seeds, sim::Term::kTemperature, false), 3);
}

TEST(ImfView, AHiddenTemperatureRateEffectFlagsTheImfOfTheCycleThroughTheDerivativeTest) {
  // As above for the Shupe term (bias proportional to dT/dt), through the test of the smoothed
  // derivative: 18 of 40 (45 %) on the development seeds 1-40. On seeds 101-110 at least 2 of 10:
  // at 45 %, fewer has probability 2.3 %.
  std::vector<std::uint64_t> seeds;
  for (std::uint64_t s = 101; s <= 110; ++s) seeds.push_back(s);
  EXPECT_GE(SeedsFlaggedOnTheThermalImf(seeds, sim::Term::kTemperatureRate, true), 2);
}

TEST(ImfView, ComputeIsDeterministicAndInvalidOptionsAreReported) {
  const double fs = 10.0;
  const Eigen::VectorXd x = WhiteRate(5, 20000, fs);
  const ImfView a = ComputeImfView(x, fs, {}, WhiteModel(kN), ImfViewOptions());
  const ImfView b = ComputeImfView(x, fs, {}, WhiteModel(kN), ImfViewOptions());
  EXPECT_EQ(a.energy, b.energy) << "same input + options -> same numbers";
  EXPECT_EQ(a.expected_energy.size(), b.expected_energy.size());
  for (size_t k = 0; k < a.expected_energy.size(); ++k) {
    if (std::isfinite(a.expected_energy[k])) {
      EXPECT_EQ(a.expected_energy[k], b.expected_energy[k]);
    }
  }
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
