#include "algorithms/simulation/deterministic_effects.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/units.h"

namespace fogpipe::simulation {
namespace {

TEST(BiasStepRate, IsZeroBeforeTheStepTimeAndTheSizeFromItOn) {
  const Eigen::VectorXd x = BiasStepRate({12.34, -2e-6}, 1000, 10.0);
  for (Eigen::Index k = 0; k < 1000; ++k) {
    EXPECT_EQ(x[k], k <= 123 ? 0.0 : -2e-6) << k;  // t_124 = 12.4 s is the first sample after
  }
  const Eigen::VectorXd on_grid = BiasStepRate({5.0, 1.0}, 100, 10.0);
  EXPECT_EQ(on_grid[49], 0.0);
  EXPECT_EQ(on_grid[50], 1.0);
}

TEST(WarmupRate, IsAnExponentialDecayWithTheGivenTimeConstant) {
  const Warmup w{3e-6, 600.0};
  const Eigen::VectorXd x = WarmupRate(w, 36001, 10.0);
  EXPECT_EQ(x[0], 3e-6);
  EXPECT_NEAR(x[6000] / x[0], std::exp(-1.0), 1e-15);  // t = tau
  EXPECT_NEAR(x[36000] / x[0], std::exp(-6.0), 1e-15);
  for (Eigen::Index k = 1; k < x.size(); ++k) {
    ASSERT_NEAR(x[k] / x[k - 1], std::exp(-0.1 / 600.0), 1e-14);
  }
}

TemperatureProfile Sine() {
  TemperatureProfile p;
  p.mean_degC = 25.0;
  p.peak_to_peak_degC = 8.0;
  p.period_s = 3600.0;
  p.sharpness = 0.0;
  return p;
}

TEST(TemperatureEffectRate, IsTheCoefficientTimesTheTrueTemperatureOffset) {
  const TemperatureEffect effect{2e-7, 21.0};
  const Eigen::VectorXd x = TemperatureEffectRate(effect, Sine(), 3600, 1.0);
  for (Eigen::Index k : {0, 900, 1800, 2700}) {
    const double temperature = 25.0 + 4.0 * std::sin(2.0 * units::kPi * k / 3600.0);
    EXPECT_NEAR(x[k], 2e-7 * (temperature - 21.0), 1e-19) << k;
  }
}

TEST(TemperatureRateEffectRate, IsTheCoefficientTimesTheTrueTemperatureDerivative) {
  const TemperatureRateEffect effect{-5e-4};
  const Eigen::VectorXd x = TemperatureRateEffectRate(effect, Sine(), 3600, 1.0);
  const double omega = 2.0 * units::kPi / 3600.0;
  for (Eigen::Index k : {0, 900, 1800, 2700}) {
    EXPECT_NEAR(x[k], -5e-4 * 4.0 * omega * std::cos(omega * k), 1e-19) << k;
  }
  // Zero at the temperature extremes, extreme where the temperature crosses its mean.
  EXPECT_NEAR(x[900], 0.0, 1e-19);
  EXPECT_NEAR(x.cwiseAbs().maxCoeff(), 5e-4 * 4.0 * omega, 1e-19);
}

}  // namespace
}  // namespace fogpipe::simulation
