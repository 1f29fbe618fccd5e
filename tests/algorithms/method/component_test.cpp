// Tests of algorithms/method/component.cpp: the divergence check shared by `run` and the sweep.
#include "algorithms/method/component.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/algorithms/kalman/simulate_ar.h"

namespace fogpipe::method {
namespace {

// The threshold is on the RMS ratio, i.e. on the square root of the mean-square ratio: 10x RMS is
// 100x the variance. Below it nothing is reported; above it the ratio is named.
TEST(FilterDiverged, FlagsOnlyEstimatesAboveTenTimesTheComponentsRms) {
  std::string message;
  EXPECT_FALSE(FilterDiverged(99.0, 1.0, &message));
  EXPECT_TRUE(message.empty());
  EXPECT_FALSE(FilterDiverged(100.0, 1.0, &message));
  EXPECT_TRUE(FilterDiverged(1.0e6, 2.5e-3, &message));  // RMS ratio 2e4
  EXPECT_NE(message.find("diverged"), std::string::npos) << message;
  EXPECT_NE(message.find("2e+04"), std::string::npos) << message;
  EXPECT_TRUE(FilterDiverged(std::nan(""), 1.0, &message) == false);  // no result, no verdict
  EXPECT_FALSE(FilterDiverged(1.0, 0.0, &message));  // a constant component: nothing to compare
}

// The premise: a working filter on a model fitted to its component estimates it with less
// variance than the component has (var(x^) = var(x) - P <= var(z)). An AR(2) observed in white
// noise at three signal-to-noise ratios, through ModelComponent (BIC order, the default noise
// rule): the estimate's RMS is at most the component's, far below the 10x threshold, and nothing
// is flagged.
TEST(ModelComponent, AWorkingFilterEstimatesWithLessVarianceThanItsComponent) {
  Eigen::VectorXd phi(2);
  phi << 1.6, -0.8;
  for (double r : {0.01, 1.0, 100.0}) {
    const kalman::testing::ArSimulation sim =
        kalman::testing::SimulateArPlusNoise(phi, 1.0, r, 20000, 41);
    const ComponentModel c = ModelComponent(sim.z, r, ComponentOptions());
    ASSERT_TRUE(c.ok()) << c.message();
    const double estimate_ms = (c.Output().array() - c.fit.model.mean).square().mean();
    const double component_var = (sim.z.array() - sim.z.mean()).square().mean();
    EXPECT_LE(std::sqrt(estimate_ms / component_var), 1.0) << "R " << r;
  }
}

}  // namespace
}  // namespace fogpipe::method
