#include "algorithms/ar/autocorrelation.h"

#include <gtest/gtest.h>

#include "tests/algorithms/ar/ar_test_support.h"

namespace fogpipe::ar {
namespace {

TEST(LaggedProducts, EqualTheNaiveDoubleLoopAcrossBlockBoundaries) {
  const Eigen::VectorXd x = testing::WhiteNoise(5000, 1.0, 51);  // 3 blocks of 2048
  const int max_lag = 25;
  const Eigen::VectorXd c = LaggedProducts(x, max_lag);
  for (int k = 0; k <= max_lag; ++k) {
    double naive = 0.0;
    for (Eigen::Index t = 0; t + k < x.size(); ++t) naive += x(t) * x(t + k);
    // Different summation order only: rounding ~ eps * sum |x_t x_{t+k}| ~ 1e-16 * 5000.
    EXPECT_NEAR(c(k), naive, 1e-11) << "lag " << k;
  }
}

TEST(LaggedProducts, LagsBeyondTheRecordAreZero) {
  Eigen::VectorXd x(3);
  x << 1.0, 2.0, 3.0;
  const Eigen::VectorXd c = LaggedProducts(x, 4);
  EXPECT_DOUBLE_EQ(c(0), 14.0);
  EXPECT_DOUBLE_EQ(c(1), 8.0);
  EXPECT_DOUBLE_EQ(c(2), 3.0);
  EXPECT_DOUBLE_EQ(c(3), 0.0);
  EXPECT_DOUBLE_EQ(c(4), 0.0);
}

}  // namespace
}  // namespace fogpipe::ar
