// Tests of algorithms/allan/model_edf.{h,cpp}: the EDF of the fitted noise model, against
// Greenhall & Riley's EDF for single power laws (an independent published algorithm, edf.h) and
// against simulation for a mixture, and where ApplyModelEdf may and may not change a table.
#include "algorithms/allan/model_edf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "algorithms/allan/allan.h"
#include "algorithms/allan/edf.h"
#include "algorithms/allan/estimate_law.h"
#include "algorithms/allan/noise_fit.h"
#include "tests/algorithms/allan/power_law_noise.h"

namespace fogpipe::allan {
namespace {

using testing::PowerLawNoise;

// At t0 = 1 s the simulator's levels are the IEEE terms' squares: white PM h -> Q^2 (AVAR 3 h /
// m^2), white FM h -> N^2 (h / m), random-walk FM h -> K^2 (h m / 3).
NoiseTerms Terms(double q2, double n2, double k2) {
  NoiseTerms t;
  t.q_rad = std::sqrt(q2), t.n_rad_sqrt_s = std::sqrt(n2), t.b_rad_s = 0.0;
  t.k_rad_s_sqrt_s = std::sqrt(k2), t.r_rad_s2 = 0.0;
  return t;
}

// One term alone: the model EDF is that term's Greenhall EDF for sampled phase. Greenhall's
// basic sum is exact (at most 100 terms); its long-record asymptotes are stated to 1-2 %
// (Greenhall & Riley 2003, Tables 2-3; edf.h: within 1.5 % of SP 1065 for white FM), so 3 %.
TEST(ModelEdf, OfOneTermEqualsGreenhallsEdfForThatNoiseType) {
  const long long n = 4096;
  struct Case {
    int alpha;
    NoiseTerms terms;
  };
  const Case cases[] = {
      {2, Terms(1.0, 0.0, 0.0)}, {0, Terms(0.0, 1.0, 0.0)}, {-2, Terms(0.0, 0.0, 1.0)}};
  for (const Case& c : cases) {
    for (long long m : {1LL, 2LL, 8LL, 64LL, 512LL, 1024LL}) {
      const long long count = DifferenceCount(Deviation::kOverlappingAllan, n, m);
      const double model = ModelOverlappingAllanEdf(c.terms, m, count, 1.0);
      const double greenhall = GreenhallEdf(c.alpha, 2, m, n + 1, true, true);
      EXPECT_NEAR(model / greenhall, 1.0, 0.03) << "alpha " << c.alpha << " m " << m << ": model "
                                                << model << ", Greenhall " << greenhall;
    }
  }
}

// One difference, D^2 / (2 tau^2) with D a centred Gaussian, is chi-square(1): EDF 1 exactly for
// every term and mixture, at short and long tau (the longest row of every octave grid).
TEST(ModelEdf, OfASingleDifferenceIsOne) {
  NoiseTerms mix = Terms(1.0, 1.0, 1e-6);
  mix.b_rad_s = 0.01;
  for (const NoiseTerms& t :
       {Terms(1.0, 0.0, 0.0), Terms(0.0, 1.0, 0.0), Terms(0.0, 0.0, 1.0), mix})
    for (long long m : {1LL, 100LL, 131072LL})
      EXPECT_NEAR(ModelOverlappingAllanEdf(t, m, 1, 1.0), 1.0, 1e-9) << m;
}

// A mixture at the crossover of white PM and white FM (both give the same Allan variance at
// m = 8): the model EDF equals the EDF of simulated records, 2 mean^2 / variance of the
// overlapping Allan variance over 2000 realisations, within 4 of its standard errors (delta
// method from the sample's second and fourth central moments). From the crossover on it differs
// from both single-law EDFs, which are all the identification can choose between (below it the
// mixture's is white PM's).
TEST(ModelEdf, OfAMixtureEqualsTheEdfOfSimulatedRecords) {
  const long long n = 2048;
  const double h_pm = 64.0 / 3.0, h_fm = 8.0;  // 3 h_pm / 64 = h_fm / 8 at m = 8
  const PowerLawNoise noise({{2, h_pm}, {0, h_fm}}, n);
  const NoiseTerms terms = Terms(h_pm, h_fm, 0.0);
  AllanOptions options;
  options.confidence_intervals = false;
  options.grid.kind = TauGridKind::kExplicit;
  options.grid.explicit_m = {4, 8, 16};
  const int realisations = 2000;
  std::vector<std::vector<double>> v(3);
  for (int r = 0; r < realisations; ++r) {
    const AllanTable t = ComputeAllan(noise.Draw(700001 + r), 1.0, options).table;
    for (int k = 0; k < 3; ++k) v[k].push_back(t.sigma[k] * t.sigma[k]);
  }
  for (int k = 0; k < 3; ++k) {
    const long long m = options.grid.explicit_m[k];
    double mean = 0.0;
    for (double x : v[k]) mean += x;
    mean /= realisations;
    double m2 = 0.0, m4 = 0.0;
    for (double x : v[k]) m2 += (x - mean) * (x - mean), m4 += std::pow(x - mean, 4);
    m2 /= realisations - 1, m4 /= realisations;
    const double simulated = 2.0 * mean * mean / m2;
    // Relative variance of the sample variance (m4 - m2^2) / (n m2^2), plus that of mean^2.
    const double rel_se = std::sqrt((m4 - m2 * m2) / (realisations * m2 * m2) +
                                    4.0 * m2 / (realisations * mean * mean));
    const long long count = DifferenceCount(Deviation::kOverlappingAllan, n, m);
    const double model = ModelOverlappingAllanEdf(terms, m, count, 1.0);
    EXPECT_NEAR(model / simulated, 1.0, 4.0 * rel_se)
        << "m " << m << ": model " << model << ", simulated " << simulated;
    const double white_pm = GreenhallEdf(2, 2, m, n + 1, true, true);
    const double white_fm = GreenhallEdf(0, 2, m, n + 1, true, true);
    std::printf("m %lld: model %.1f simulated %.1f (rel se %.3f) white PM %.1f white FM %.1f\n", m,
                model, simulated, rel_se, white_pm, white_fm);
    EXPECT_GT(std::abs(model / white_fm - 1.0), 4.0 * rel_se) << "m " << m;
    if (m >= 8) {
      EXPECT_GT(std::abs(model / white_pm - 1.0), 4.0 * rel_se) << "m " << m;
    }
  }
}

AllanTable TableOf(const Eigen::VectorXd& rate) {
  AllanOptions options;
  return ComputeAllan(rate, 1.0, options).table;
}

// Where the five-term model holds (white FM), every fitted row takes the model EDF and its
// chi-square bounds move with it; the sigma column does not change.
TEST(ModelEdf, ApplyReplacesTheRowsWhereTheFitHolds) {
  const PowerLawNoise noise({{0, 1.0}}, 1 << 14);
  const AllanTable before = TableOf(noise.Draw(11));
  AllanTable table = before;
  const NoiseFitResult fit = FitNoiseTerms(table, NoiseFitOptions());
  ASSERT_TRUE(fit.generalized);
  ASSERT_GE(fit.p_value, 1e-3);
  const int changed = ApplyModelEdf(fit, ModelEdfOptions(), &table);
  int model_rows = 0;
  for (size_t k = 0; k < table.size(); ++k) {
    EXPECT_EQ(table.sigma[k], before.sigma[k]);
    if (table.edf_source[k] != EdfSource::kModel) {
      EXPECT_EQ(table.edf[k], before.edf[k]);
      continue;
    }
    ++model_rows;
    // With few averages the bounds come from the estimate's law (estimate_law_test).
    if (FewAverages(2, table.m[k], table.count[k])) continue;
    double low = 0.0, high = 0.0;
    ConfidenceBounds(table.sigma[k], table.edf[k], 0.683, &low, &high);
    EXPECT_EQ(table.ci_low[k], low);
    EXPECT_EQ(table.ci_high[k], high);
  }
  EXPECT_EQ(changed, model_rows);
  EXPECT_GE(model_rows, static_cast<int>(table.size()) - 1);
}

// Where the model is rejected, nothing changes: white FM plus a sine the five terms cannot
// describe (a p-value far below 1e-3), and any deviation other than OADEV.
TEST(ModelEdf, ApplyLeavesTheTableAloneWhereTheModelIsRejected) {
  const long long n = 1 << 14;
  Eigen::VectorXd rate = PowerLawNoise({{0, 1.0}}, n).Draw(12);
  for (long long i = 0; i < n; ++i) rate[i] += 0.5 * std::sin(2.0 * 3.14159265358979 * i / 200.0);
  AllanTable table = TableOf(rate);
  const AllanTable before = table;
  const NoiseFitResult fit = FitNoiseTerms(table, NoiseFitOptions());
  ASSERT_FALSE(fit.p_value >= 1e-3 && fit.model_discrepancy == 0.0) << fit.p_value;
  EXPECT_EQ(ApplyModelEdf(fit, ModelEdfOptions(), &table), 0);
  EXPECT_EQ(table.edf, before.edf);

  AllanOptions hdev;
  hdev.deviation = Deviation::kOverlappingHadamard;
  AllanTable other = ComputeAllan(PowerLawNoise({{0, 1.0}}, n).Draw(13), 1.0, hdev).table;
  AllanTable oadev = TableOf(PowerLawNoise({{0, 1.0}}, n).Draw(13));
  EXPECT_EQ(ApplyModelEdf(FitNoiseTerms(oadev, NoiseFitOptions()), ModelEdfOptions(), &other), 0);
}

TEST(ModelEdf, OptionsOutsideTheirRangeAreInvalid) {
  ModelEdfOptions o;
  EXPECT_TRUE(o.IsValid(nullptr));
  o.confidence = 1.0;
  EXPECT_FALSE(o.IsValid(nullptr));
  AllanTable table;
  EXPECT_EQ(ApplyModelEdf(NoiseFitResult(), o, &table), -1);
}

}  // namespace
}  // namespace fogpipe::allan
