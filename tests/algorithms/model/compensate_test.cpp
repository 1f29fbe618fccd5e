#include "algorithms/model/compensate.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fogpipe::model {
namespace {

TEST(Compensate, SubtractsExactlyTheModelledEffects) {
  const double fs = 2.0;
  const long n = 4000;
  Eigen::VectorXd t(n), rate(n), temp(n);
  for (long i = 0; i < n; ++i) {
    const double s = i / fs;
    temp[i] = 20.0 + 3.0 * std::sin(2 * M_PI * s / 900.0);
    rate[i] =
        0.5 + 0.01 * (temp[i] - 20.0) + (s >= 1000.0 ? 0.2 : 0.0) + 0.3 * std::exp(-s / 100.0);
  }
  DeterministicModel m;
  m.bias_rad_s = 0.5;
  m.temperature_ref_degc = 20.0;
  m.components.push_back({Term::kTemperature, 0.0, 0.0, {0.01}, {0.0}, 0.0, "", {}, {}});
  m.components.push_back({Term::kBiasStep, 1000.0, 0.0, {0.2}, {0.0}, 0.0, "", {}, {}});
  m.components.push_back({Term::kWarmup, 100.0, 0.0, {0.3}, {0.0}, 0.0, "", {}, {}});
  CompensateOptions o;
  o.subtract_bias = true;
  const Compensation c = Compensate(rate, fs, &temp, m, o);
  ASSERT_EQ(c.summary.termination, Termination::kSuccess);
  EXPECT_EQ(c.summary.num_effects, 3);
  // Closed form in, closed form out: only rounding (the exp recurrence is re-anchored).
  EXPECT_LT(c.rate_rad_s.cwiseAbs().maxCoeff(), 1e-12);
  o.subtract_bias = false;
  EXPECT_NEAR(Compensate(rate, fs, &temp, m, o).rate_rad_s.mean(), 0.5, 1e-12);
}

TEST(Compensate, AThermalModelNeedsTheTemperature) {
  DeterministicModel m;
  m.components.push_back({Term::kTemperatureRate, 0.0, 0.0, {1.0}, {0.0}, 0.0, "", {}, {}});
  const Eigen::VectorXd rate = Eigen::VectorXd::Zero(100);
  EXPECT_EQ(Compensate(rate, 1.0, nullptr, m, {}).summary.termination,
            Termination::kInsufficientData);
}

}  // namespace
}  // namespace fogpipe::model
