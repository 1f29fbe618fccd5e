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

// RMS of a component's filter output about its model mean, over the component's RMS: the ratio
// FilterDiverged judges.
double RmsRatio(const ComponentModel& c, const Eigen::VectorXd& x) {
  const double estimate_ms = (c.Output().array() - c.fit.model.mean).square().mean();
  return std::sqrt(estimate_ms / (x.array() - x.mean()).square().mean());
}

// When the filter on BIC's order diverges (README, Known limitations: ill-conditioned high orders
// of slow IMFs), ModelComponent tries BIC's next best order below it (the best BIC among the lower
// orders) and records why in order_note. Divergence is provoked here with a threshold between the
// RMS ratios of the two orders' filters, computed independently with fixed orders; the result is
// the lower order's fit and filter, exactly.
TEST(ModelComponent, AFilterThatDivergesGivesWayToBICsNextOrder) {
  Eigen::VectorXd phi(3);
  phi << 1.2, -0.5, 0.1;
  int cases = 0;
  for (double r : {0.01, 1.0, 100.0}) {
    const kalman::testing::ArSimulation sim =
        kalman::testing::SimulateArPlusNoise(phi, 1.0, r, 20000, 43);
    const ComponentModel bic = ModelComponent(sim.z, r, ComponentOptions());
    ASSERT_TRUE(bic.ok()) << bic.message();
    EXPECT_TRUE(bic.order_note.empty());
    const int p0 = bic.fit.model.order;
    if (p0 < 2) continue;
    ComponentOptions lower = ComponentOptions();
    lower.ar.max_order = p0 - 1;
    const ComponentModel next = ModelComponent(sim.z, r, lower);  // BIC's best below p0
    ASSERT_TRUE(next.ok()) << next.message();
    const double ratio0 = RmsRatio(bic, sim.z), ratio1 = RmsRatio(next, sim.z);
    if (!(ratio1 < ratio0)) continue;  // the provocation needs the lower order to be calmer
    ComponentOptions provoked = ComponentOptions();
    provoked.diverged_rms_ratio = 0.5 * (ratio0 + ratio1);
    const ComponentModel c = ModelComponent(sim.z, r, provoked);
    ASSERT_TRUE(c.ok()) << c.message();
    EXPECT_EQ(c.fit.model.order, next.fit.model.order) << "R " << r;
    EXPECT_EQ((c.Output() - next.Output()).cwiseAbs().maxCoeff(), 0.0) << "R " << r;
    EXPECT_EQ(c.order_note.find("AR(" + std::to_string(p0) + ") diverged"), 0u) << c.order_note;
    ++cases;
  }
  EXPECT_GT(cases, 0) << "no noise level gave a calmer lower order";
}

// With every filter counted as diverged (threshold 0), the orders are given up one after the other
// down to AR(1), whose filter fails the component: no output, and the message names every
// rejected order.
TEST(ModelComponent, WhenEveryOrderDivergesTheComponentFailsNamingThemAll) {
  Eigen::VectorXd phi(2);
  phi << 1.6, -0.8;
  const kalman::testing::ArSimulation sim =
      kalman::testing::SimulateArPlusNoise(phi, 1.0, 1.0, 20000, 47);
  const ComponentModel bic = ModelComponent(sim.z, 1.0, ComponentOptions());
  ASSERT_TRUE(bic.ok()) << bic.message();
  ComponentOptions options;
  options.diverged_rms_ratio = 0.0;
  const ComponentModel c = ModelComponent(sim.z, 1.0, options);
  EXPECT_FALSE(c.ok());
  EXPECT_EQ(c.fit.model.order, 1);
  EXPECT_EQ(c.kalman.filtered.size(), 0);
  for (int p = bic.fit.model.order; p >= 2; --p)
    EXPECT_NE(c.order_note.find("AR(" + std::to_string(p) + ") diverged"), std::string::npos)
        << c.order_note;
  EXPECT_NE(c.message().find("diverged"), std::string::npos) << c.message();
}

}  // namespace
}  // namespace fogpipe::method
