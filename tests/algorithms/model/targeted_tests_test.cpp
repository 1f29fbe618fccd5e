#include "algorithms/model/targeted_tests.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <utility>

#include "algorithms/common/units.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::model {
namespace {

StochasticModel WhiteOnly(double n_rad_sqrt_s) {
  StochasticModel m;
  m.terms = {Term::kWhite};
  m.n_rad_sqrt_s = n_rad_sqrt_s;
  return m;
}

TEST(TargetedTests, TheTrendDftIsTheDftOfALinearTrend) {
  // The closed form -n / (1 - e^{-i w}) against the FFT of t = 0 .. n - 1.
  const long n = 1000;
  const auto closed = TrendDft(n);
  const auto fft = MeanRemovedDft(Eigen::VectorXd::LinSpaced(n, 0.0, n - 1.0));
  for (long k = 1; k <= n / 2; ++k) EXPECT_NEAR(std::abs(closed[k] - fft[k]), 0.0, 1e-8 * n) << k;
}

TEST(TargetedTests, TheAuxScoreWithATrendProfiledOutIgnoresATrendInTheSeries) {
  // The partial score is invariant to adding any multiple of the nuisance to the series (exact
  // algebra of the projection).
  simulation::RandomSource rng(5);
  const long n = 4096;
  const Eigen::VectorXd x = rng.Normals(n), c = rng.Normals(n);
  const Eigen::VectorXd tilted = x + 0.01 * Eigen::VectorXd::LinSpaced(n, 0.0, n - 1.0);
  const auto weights = WhittleWeights(WhiteOnly(1.0), n, 1.0);
  const auto trend = TrendDft(n);
  EXPECT_NEAR(WhittleScoreZ(MeanRemovedDft(x), MeanRemovedDft(c), weights, &trend),
              WhittleScoreZ(MeanRemovedDft(tilted), MeanRemovedDft(c), weights, &trend), 1e-9);
}

// sqrt(mean z^2) over seeds 1..200 of the aux score of an innocent cycle (period 3000 s) against
// white noise (per-sample sd s) plus a rate random walk (per-sample step sd walk), under the true
// model, with and without the trend profiled out.
std::pair<double, double> AuxScoreRms(double s, double walk) {
  const double fs = 1.0;
  const long n = 16384;
  StochasticModel m;
  m.terms = {Term::kWhite, Term::kRateRandomWalk};
  m.n_rad_sqrt_s = s / std::sqrt(fs);
  m.k_rad_s_sqrt_s = walk * std::sqrt(fs);  // steps of sd walk per sample: K^2 tau / 3
  const auto weights = WhittleWeights(m, n, fs);
  const auto trend = TrendDft(n);
  double sum2 = 0, raw_sum2 = 0;
  const int seeds = 200;
  for (int seed = 1; seed <= seeds; ++seed) {
    simulation::RandomSource rng(seed);
    const Eigen::VectorXd white = s * rng.Normals(n), steps = walk * rng.Normals(n);
    Eigen::VectorXd x(n), channel(n);
    double level = 0;
    const double phase = rng.Uniform(0.0, 2.0 * units::kPi);
    for (long i = 0; i < n; ++i) {
      level += steps[i];
      x[i] = white[i] + level;
      channel[i] = std::sin(2.0 * units::kPi * i / (3000.0 * fs) + phase);
    }
    const auto xd = MeanRemovedDft(x), cd = MeanRemovedDft(channel);
    const double z = WhittleScoreZ(xd, cd, weights, &trend), raw = WhittleScoreZ(xd, cd, weights);
    sum2 += z * z;
    raw_sum2 += raw * raw;
  }
  return {std::sqrt(sum2 / seeds), std::sqrt(raw_sum2 / seeds)};
}

TEST(TargetedTests, TheAuxScoreOfASlowInnocentChannelIsStandardNormalUnderARateRandomWalk) {
  // Under the true model z is N(0, 1): over 200 seeds sqrt(mean z^2) is within 1 +- 0.15 (3 of
  // its standard errors, 1 / sqrt(400)). Two regimes: the random walk ruling the lowest ~10 % of
  // the band, and white noise ruling all but the lowest few bins (as on navigation-grade
  // records). Without the trend profiled out, the random walk's end-to-end leakage, common to
  // every low bin, correlates with the cycle and z scatters several times too wide.
  const auto [strong, strong_raw] = AuxScoreRms(0.01, 1e-3);
  EXPECT_NEAR(strong, 1.0, 0.15);
  EXPECT_GT(strong_raw, 3.0);
  const auto [weak, weak_raw] = AuxScoreRms(0.01, 3e-5);
  EXPECT_NEAR(weak, 1.0, 0.15);
  std::printf("aux score rms: strong walk %.3f (without the trend %.3f), weak %.3f (%.3f)\n",
              strong, strong_raw, weak, weak_raw);
}

TEST(TargetedTests, BridgeCriticalValueMatchesAndrewsSupWaldTable) {
  // Andrews (1993) Table 1, one parameter, pi_0 = 0.05: the 5 % critical value of sup-Wald (the
  // squared standardised CUSUM supremum) is 9.84. The James-James-Siegmund approximation is
  // slightly conservative; 0.1 in c is 1.6 % of c.
  EXPECT_NEAR(BridgeSupremumCritical(0.05, 0.05), std::sqrt(9.84), 0.1);
  // A wider scan costs more: the critical value grows as the margin shrinks.
  EXPECT_GT(BridgeSupremumCritical(0.05, 0.02), BridgeSupremumCritical(0.05, 0.05));
}

TEST(TargetedTests, SmoothSupremumOfAZeroLengthRangeIsTheNormalQuantile) {
  // With no parameter range, Rice's formula reduces to the marginal tail: two-sided 5 % is
  // 1.959964, one-sided 5 % is 1.644854 (to the bisection's 1e-12 and the formula's exactness).
  EXPECT_NEAR(SmoothSupremumCritical(0.05, 0.0, true), 1.959964, 1e-5);
  EXPECT_NEAR(SmoothSupremumCritical(0.05, 0.0, false), 1.644854, 1e-5);
  EXPECT_GT(SmoothSupremumCritical(0.05, 5.0, true), SmoothSupremumCritical(0.05, 0.0, true));
}

TEST(TargetedTests, StepScanInWhiteNoiseGivesTheMatchedFilterStatistic) {
  // White noise of per-sample sd s plus a step D at t_s = 0.3 T: the GLS t-statistic under the
  // white model is the two-sample t, D sqrt(n t (1 - t)) / s (closed form), up to the sampling
  // error of D_hat (sd 1 in z units) and the noise level refitted on the residual.
  const double fs = 10.0, s = 0.01;
  const long n = 60000;
  simulation::RandomSource rng(7);
  Eigen::VectorXd x = s * rng.Normals(n);
  const long k0 = static_cast<long>(0.3 * n);
  const double d = 0.5 * s;  // expected z = 0.5 sqrt(60000 * 0.21) = 56.1
  x.tail(n - k0).array() += d;
  const StochasticModel m = WhiteOnly(s / std::sqrt(fs));  // PSD level N^2 = s^2 / fs
  const TargetedTest t = ScanBiasStep(x, fs, MeanRemovedDft(x), m, ViewOptions{}, 0.05, 100.0);
  ASSERT_TRUE(t.evaluated);
  const double expected = d * std::sqrt(n * 0.3 * 0.7) / s;
  EXPECT_NEAR(t.z, expected, 3.0);
  EXPECT_NEAR(t.location, k0 / fs, 100.0);  // within 1000 samples of a 56-sigma step
  EXPECT_NEAR(t.size, d, 3.0 * s / std::sqrt(n * 0.21));
  EXPECT_LE(t.from, k0 / fs);
  EXPECT_GE(t.to, k0 / fs);
}

TEST(TargetedTests, StepScanOfPureWhiteNoiseStaysBelowItsCriticalValue) {
  // Ten seeds of white noise: the sup of the standardised bridge exceeds the 5 % value in about
  // 5 % of them; at most 2 of 10 (P ~ 0.09 under the null) is allowed.
  const double fs = 10.0, s = 0.01;
  int above = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    simulation::RandomSource rng(seed);
    const Eigen::VectorXd x = s * rng.Normals(20000);
    const TargetedTest t = ScanBiasStep(x, fs, MeanRemovedDft(x), WhiteOnly(s / std::sqrt(fs)),
                                        ViewOptions{}, 0.05, 100.0);
    ASSERT_TRUE(t.evaluated);
    above += std::abs(t.z) > t.critical;
  }
  EXPECT_LE(above, 2);
}

TEST(TargetedTests, GaussMarkovBumpIsFoundAtItsCorrelationTimeAndAbsentWithoutIt) {
  // Exact Allan variances (closed forms, EDF 1e6): white + bias instability + a Gauss-Markov bump
  // of Tc = 120 s. Without noise on the curve the fit recovers Tc and sigma closely and the
  // chi-square drop is large; the same curve without the bump gives z ~ 0.
  using namespace units;
  StochasticModel truth;
  truth.terms = {Term::kWhite, Term::kBiasInstability, Term::kGaussMarkov};
  truth.n_rad_sqrt_s = DegPerSqrtHourToArw(0.005);
  truth.b_rad_s = DegPerHourToBias(0.004);
  truth.gm_sigma_rad_s = DegPerHourToBias(0.2);
  truth.gm_correlation_time_s = 120.0;
  StochasticModel base = truth;
  base.terms = {Term::kWhite, Term::kBiasInstability};
  const double fs = 10.0, record = 6 * 3600.0;
  AllanData with, without;
  for (double tau = 0.1; tau <= record / 8; tau *= 2) {
    for (AllanData* a : {&with, &without}) {
      a->tau_s.push_back(tau);
      a->edf.push_back(1e6);
    }
    with.avar.push_back(ModelAllanVariance(truth, tau));
    without.avar.push_back(ModelAllanVariance(base, tau));
  }
  const TargetedTest bump = ScanGaussMarkov(with, fs, record, base, ViewOptions{}, 0.05);
  ASSERT_TRUE(bump.evaluated);
  EXPECT_GT(bump.z, 3.0 * bump.critical);
  EXPECT_NEAR(bump.location, 120.0, 0.05 * 120.0);
  EXPECT_NEAR(bump.size, truth.gm_sigma_rad_s, 0.05 * truth.gm_sigma_rad_s);
  EXPECT_LT(bump.from, 1.89 * 120.0);
  EXPECT_GT(bump.to, 1.89 * 120.0);
  const TargetedTest none = ScanGaussMarkov(without, fs, record, base, ViewOptions{}, 0.05);
  ASSERT_TRUE(none.evaluated);
  EXPECT_LT(none.z, 1.0);
  // A model that already has gauss_markov is not tested again.
  EXPECT_FALSE(ScanGaussMarkov(with, fs, record, truth, ViewOptions{}, 0.05).evaluated);
}

}  // namespace
}  // namespace fogpipe::model
