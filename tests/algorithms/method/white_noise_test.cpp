// Tests algorithms/method/white_noise.cpp against closed-form variances.
#include "algorithms/method/white_noise.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <utility>
#include <vector>

#include "algorithms/emd/emd.h"
#include "algorithms/method/band_limit.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::method {
namespace {

TEST(WhiteNoise, EstimatesTheVarianceOfWhiteNoiseUnderASlowRandomWalk) {
  std::mt19937_64 rng(7);
  auto uniform = [&rng]() { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; };
  const int n = 200000;
  Eigen::VectorXd x(n);
  double walk = 0.0;
  for (int i = 0; i < n; ++i) {
    const double g = std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * M_PI * uniform());
    const double h = std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * M_PI * uniform());
    walk += 1e-3 * h;  // rate random walk: adds 1e-6 to var(diff)
    x[i] = 2.0 * g + walk;
  }
  // Truth 4. The MAD-based scale of n = 2e5 differences has relative standard error
  // ~1.36 / sqrt(n) = 0.3 % (asymptotic efficiency 37 %), so 2 % is > 6 standard errors.
  EXPECT_NEAR(EstimateWhiteNoiseLevels(x).Total() / 4.0, 1.0, 0.02);
  // Through a ForEach (here one that runs the two differences in reverse order), the same bits.
  const WhiteNoiseLevels one = EstimateWhiteNoiseLevels(x);
  const WhiteNoiseLevels two =
      EstimateWhiteNoiseLevels(x, [](int n, const std::function<void(int)>& body) {
        for (int i = n - 1; i >= 0; --i) body(i);
      });
  EXPECT_EQ(two.rate_variance, one.rate_variance);
  EXPECT_EQ(two.angle_variance, one.angle_variance);
}

// Joint white rate (u) and white angle (v) noise: x_t = sqrt(u) g_t + sqrt(v) (h_t - h_{t-1}) plus
// a slow rate random walk, over 200 records per mix (seeds apart from every other test's). Each
// estimate's mean relative error must be within 3 standard errors of the mean (the spread over
// the records / sqrt(200)) of 0; the MAD of first differences alone, the rule before, reads the
// total u + 2v as u + 3v (+40 % for v = 2u) and must fail the same check.
TEST(WhiteNoise, EstimatesWhiteRateAndWhiteAngleNoiseJointlyWithoutBias) {
  struct Mix {
    double u, v;
  };
  const int records = 200;
  const int n = 20000;
  for (const Mix& mix : {Mix{1.0, 0.5}, Mix{1.0, 2.0}, Mix{1.0, 0.0}}) {
    std::vector<double> err_u, err_v, err_total, err_first_differences;
    for (int r = 0; r < records; ++r) {
      simulation::RandomSource normal(900000 + 1000 * static_cast<int>(4 * mix.v) + r);
      Eigen::VectorXd x(n);
      double walk = 0.0, previous = normal.Normal();
      for (int i = 0; i < n; ++i) {
        const double h = normal.Normal();
        walk += 1e-3 * normal.Normal();
        x[i] = std::sqrt(mix.u) * normal.Normal() + std::sqrt(mix.v) * (h - previous) + walk;
        previous = h;
      }
      const WhiteNoiseLevels levels = EstimateWhiteNoiseLevels(x);
      const double total = mix.u + 2.0 * mix.v;
      err_u.push_back(levels.rate_variance / mix.u - 1.0);
      if (mix.v > 0.0) err_v.push_back(levels.angle_variance / mix.v - 1.0);
      err_total.push_back(levels.Total() / total - 1.0);
      // The previous rule: (1.4826 MAD(diff x))^2 / 2.
      std::vector<double> d(n - 1);
      for (int i = 0; i + 1 < n; ++i) d[i] = x[i + 1] - x[i];
      std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
      const double median = d[d.size() / 2];
      for (double& e : d) e = std::abs(e - median);
      std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
      const double mad = 1.482602218505602 * d[d.size() / 2];
      err_first_differences.push_back(0.5 * mad * mad / total - 1.0);
    }
    auto mean_and_se = [](const std::vector<double>& e) {
      double m = 0.0, s = 0.0;
      for (double v : e) m += v;
      m /= e.size();
      for (double v : e) s += (v - m) * (v - m);
      return std::make_pair(m, std::sqrt(s / (e.size() - 1) / e.size()));
    };
    const auto [mt, st] = mean_and_se(err_total);
    const auto [mf, sf] = mean_and_se(err_first_differences);
    std::printf("u %.1f v %.1f: total %+.4f +- %.4f, first differences alone %+.4f +- %.4f", mix.u,
                mix.v, mt, st, mf, sf);
    EXPECT_LT(std::abs(mt), 3.0 * st) << "v = " << mix.v;
    if (mix.v > 0.0) {
      const auto [mu, su] = mean_and_se(err_u);
      const auto [mv, sv] = mean_and_se(err_v);
      std::printf(", u %+.4f +- %.4f, v %+.4f +- %.4f", mu, su, mv, sv);
      EXPECT_LT(std::abs(mu), 3.0 * su) << "v = " << mix.v;
      EXPECT_LT(std::abs(mv), 3.0 * sv) << "v = " << mix.v;
      EXPECT_GT(std::abs(mf), 3.0 * sf) << "the previous rule must fail where v > 0";
    }
    std::printf("\n");
  }
}

// The share law of step 2 on what the method models: the band-limited IMFs (band_limit.h) of pure
// white rate noise and of pure white angle noise (a differenced white noise), 8 records of 2^14
// samples each. Every component is all noise there, so the components that the law's shares
// (before the cap) say hold the first 80 % of the noise must be judged pure noise (share >=
// variance: their filters then output their mean). Applied to angle noise, the white law (1/T)
// misses that on the first component, which the test shows too. What the law does not do: the
// slowest band-limited components of a pure-noise record hold more variance than their share
// (the leakage moved down accumulates there, and cancels against the residue), so they are
// passed as signal; docs/filtering.md gives the measurements.
TEST(WhiteNoise, TheShareLawJudgesTheNoisiestComponentsOfPureNoisePureNoise) {
  for (const bool angle : {false, true}) {
    int judged = 0, expected = 0, white_law_misses = 0;
    for (int r = 0; r < 8; ++r) {
      simulation::RandomSource normal(950000 + 100 * angle + r);
      const Eigen::Index n = 1 << 14;
      Eigen::VectorXd x(n);
      double previous = normal.Normal();
      for (Eigen::Index i = 0; i < n; ++i) {
        const double h = normal.Normal();
        x[i] = angle ? h - previous : h;
        previous = h;
      }
      emd::EmdResult d = emd::Decompose(x, emd::EmdOptions());
      BandLimitImfs(BandLimitOptions(), &d);  // the components the shares are applied to
      WhiteNoiseLevels levels;
      (angle ? levels.angle_variance : levels.rate_variance) = 1.0;
      const std::vector<double> variances = ComponentVariances(d);
      const std::vector<double> periods = ComponentPeriods(d, n);
      const std::vector<double> uncapped =
          ShareWhiteNoise(levels, periods, std::vector<double>(variances.size(), 1e300));
      const std::vector<double> share = ShareWhiteNoise(levels, d, n);
      double covered = 0.0;
      for (std::size_t k = 0; k + 1 < share.size() && covered < 0.8 * levels.Total(); ++k) {
        ++expected;
        judged += share[k] >= variances[k];
        covered += uncapped[k];
      }
      WhiteNoiseLevels as_white;  // the same total under the white law (1/T)
      as_white.rate_variance = levels.Total();
      const std::vector<double> white_law = ShareWhiteNoise(as_white, periods, variances);
      white_law_misses += white_law[0] < variances[0];
    }
    std::printf(
        "%s: %d of %d components holding the first 80 %% of the noise judged pure noise; "
        "the white law misses the first component in %d of 8 records\n",
        angle ? "white angle noise" : "white rate noise", judged, expected, white_law_misses);
    EXPECT_EQ(judged, expected);
    if (angle) {
      EXPECT_GT(white_law_misses, 4);
    }
  }
}

TEST(WhiteNoise, SharesInverselyToMeanPeriodAndCapsAtTheImfVariance) {
  WhiteNoiseLevels white;
  white.rate_variance = 1.0;
  const std::vector<double> r = ShareWhiteNoise(white, {3.0, 6.0, 12.0}, {10.0, 10.0, 0.1});
  // Weights 1/3, 1/6, 1/12 over their sum 7/12: 4/7, 2/7, 1/7 (the last capped at 0.1).
  EXPECT_NEAR(r[0], 4.0 / 7.0, 1e-15);
  EXPECT_NEAR(r[1], 2.0 / 7.0, 1e-15);
  EXPECT_DOUBLE_EQ(r[2], 0.1);
  EXPECT_EQ(ShareWhiteNoise(WhiteNoiseLevels(), {3.0}, {1.0})[0], 0.0);
}

// Step 3: R is the white fraction of sigma_e^2, so R < sigma_e^2 whenever the component is not all
// noise, which is what leaves the moment match of noise_defaults.h a positive q.
TEST(WhiteNoise, TheShareRuleGivesRTheWhiteFractionOfTheInnovationVariance) {
  const FilterNoise f =
      ComponentFilterNoise(ComponentNoiseRule::kShareOfInnovation, 0.25, 1.0, 0.02);
  EXPECT_DOUBLE_EQ(f.r, 0.25 * 0.02);
  EXPECT_LT(f.q, 0.0) << "q is left to the moment match";
  EXPECT_FALSE(f.pure_noise);
  const FilterNoise g = ComponentFilterNoise(ComponentNoiseRule::kShareOfInnovation, 1.0, 1.0, 0.3);
  EXPECT_TRUE(g.pure_noise);
  EXPECT_EQ(g.q, 0.0);
  EXPECT_DOUBLE_EQ(g.r, 0.3);
  const FilterNoise h = ComponentFilterNoise(ComponentNoiseRule::kInnovationMatch, 0.25, 1.0, 0.02);
  EXPECT_DOUBLE_EQ(h.r, 0.25);
  EXPECT_FALSE(h.pure_noise);
}

TEST(WhiteNoise, NamesAndParsesEveryRule) {
  for (ComponentNoiseRule rule :
       {ComponentNoiseRule::kShareOfInnovation, ComponentNoiseRule::kInnovationMatch}) {
    ComponentNoiseRule parsed = rule == ComponentNoiseRule::kShareOfInnovation
                                    ? ComponentNoiseRule::kInnovationMatch
                                    : ComponentNoiseRule::kShareOfInnovation;
    EXPECT_TRUE(ParseComponentNoiseRule(ToString(rule), &parsed));
    EXPECT_EQ(parsed, rule);
  }
  ComponentNoiseRule unused;
  EXPECT_FALSE(ParseComponentNoiseRule("variance", &unused));
}

}  // namespace
}  // namespace fogpipe::method
