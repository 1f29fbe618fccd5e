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

}  // namespace
}  // namespace fogpipe::method
