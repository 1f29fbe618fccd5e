// Tests algorithms/method/white_noise.cpp against closed-form variances.
#include "algorithms/method/white_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

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
  EXPECT_NEAR(WhiteNoiseVariance(x) / 4.0, 1.0, 0.02);
}

TEST(WhiteNoise, SharesInverselyToMeanPeriodAndCapsAtTheImfVariance) {
  const std::vector<double> r = ShareWhiteNoise(1.0, {3.0, 6.0, 12.0}, {10.0, 10.0, 0.1});
  // Weights 1/3, 1/6, 1/12 over their sum 7/12: 4/7, 2/7, 1/7 (the last capped at 0.1).
  EXPECT_NEAR(r[0], 4.0 / 7.0, 1e-15);
  EXPECT_NEAR(r[1], 2.0 / 7.0, 1e-15);
  EXPECT_DOUBLE_EQ(r[2], 0.1);
  EXPECT_EQ(ShareWhiteNoise(0.0, {3.0}, {1.0})[0], 0.0);
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
