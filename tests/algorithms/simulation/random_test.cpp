#include "algorithms/simulation/random.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fogpipe::simulation {
namespace {

// Tolerances below are 5 standard errors of the estimator for independent samples: with fixed
// seeds the tests are deterministic, and a correct generator lands outside with probability < 1e-6.
constexpr int kSamples = 200000;

TEST(RandomSource, SameSeedGivesIdenticalSequences) {
  RandomSource a(123);
  RandomSource b(123);
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(a.Normal(), b.Normal());
    ASSERT_EQ(a.Uniform(), b.Uniform());
  }
}

TEST(RandomSource, DifferentSeedsGiveDifferentSequences) {
  RandomSource a(123);
  RandomSource b(124);
  int equal = 0;
  for (int i = 0; i < 1000; ++i) equal += a.Normal() == b.Normal();
  EXPECT_EQ(equal, 0);
}

TEST(RandomSource, UniformIsInTheUnitIntervalWithMeanOneHalfAndVarianceOneTwelfth) {
  RandomSource rng(7);
  double sum = 0.0;
  double sum2 = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const double u = rng.Uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum2 += u * u;
  }
  const double mean = sum / kSamples;
  const double var = sum2 / kSamples - mean * mean;
  EXPECT_NEAR(mean, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / kSamples));
  // Var(u^2) for U(0,1) is 1/5 - 1/9 = 4/45.
  EXPECT_NEAR(var, 1.0 / 12.0, 5.0 * std::sqrt(4.0 / 45.0 / kSamples));
}

TEST(RandomSource, NormalsHaveStandardMomentsAndTails) {
  RandomSource rng(11);
  const Eigen::VectorXd x = rng.Normals(kSamples);
  const double mean = x.mean();
  const double var = (x.array() - mean).square().mean();
  const double kurtosis = (x.array() - mean).pow(4).mean() / (var * var);
  EXPECT_NEAR(mean, 0.0, 5.0 / std::sqrt(kSamples));
  EXPECT_NEAR(var, 1.0, 5.0 * std::sqrt(2.0 / kSamples));
  // Var of the sample kurtosis of a normal is 24 / n.
  EXPECT_NEAR(kurtosis, 3.0, 5.0 * std::sqrt(24.0 / kSamples));
  // P(|x| > 2) = erfc(2 / sqrt 2) = 0.0455003; binomial standard error.
  const double p = std::erfc(2.0 / std::sqrt(2.0));
  const double tail = (x.array().abs() > 2.0).cast<double>().mean();
  EXPECT_NEAR(tail, p, 5.0 * std::sqrt(p * (1.0 - p) / kSamples));
}

TEST(RandomSource, ConsecutiveNormalsAreUncorrelated) {
  RandomSource rng(13);
  const Eigen::VectorXd x = rng.Normals(kSamples);
  // Pairs from one polar draw are (u, v) * factor: check their product averages to zero too.
  const double lag1 = x.head(kSamples - 1).dot(x.tail(kSamples - 1)) / (kSamples - 1);
  EXPECT_NEAR(lag1, 0.0, 5.0 / std::sqrt(kSamples));
}

TEST(DeriveSeed, IsDeterministicAndSeparatesStreamsAndSeeds) {
  EXPECT_EQ(DeriveSeed(1, 2), DeriveSeed(1, 2));
  EXPECT_NE(DeriveSeed(1, 2), DeriveSeed(1, 3));
  EXPECT_NE(DeriveSeed(1, 2), DeriveSeed(2, 2));
  EXPECT_NE(DeriveSeed(1, 2), DeriveSeed(2, 1));
}

TEST(DeriveSeed, StreamsOfNeighbouringSeedsAreUncorrelated) {
  RandomSource a(DeriveSeed(0, 0));
  RandomSource b(DeriveSeed(0, 1));
  const Eigen::VectorXd x = a.Normals(kSamples);
  const Eigen::VectorXd y = b.Normals(kSamples);
  EXPECT_NEAR(x.dot(y) / kSamples, 0.0, 5.0 / std::sqrt(kSamples));
}

}  // namespace
}  // namespace fogpipe::simulation
