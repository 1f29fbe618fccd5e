// Tests of algorithms/method/component.cpp: the divergence check shared by `run` and the sweep.
#include "algorithms/method/component.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "algorithms/ar/reflection.h"
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

// The smoothed estimate is judged against the component itself (kSmoothedRmsBound), the filtered
// one against ten times it: the same estimate, 1.01x the component's RMS, is a working filter's
// output (a causal filter's gain matrix is not symmetric, so it may exceed 1x) and a broken-down
// smoother's.
TEST(FilterBrokeDown, JudgesASmoothedEstimateAgainstTheComponentItself) {
  Eigen::VectorXd z(4);
  z << 1.0, -1.0, 1.0, -1.0;
  kalman::ArKalmanResult result;
  result.summary.termination = Termination::kSuccess;
  result.filtered = 1.01 * z;
  std::string message;
  EXPECT_FALSE(FilterBrokeDown(result, 0.0, 1.0, &message)) << message;
  result.smoothed = 1.01 * z;
  EXPECT_TRUE(FilterBrokeDown(result, 0.0, 1.0, &message));
  EXPECT_EQ(message.find("smoother diverged"), 0u) << message;
  result.smoothed = 0.999 * z;
  message.clear();
  EXPECT_FALSE(FilterBrokeDown(result, 0.0, 1.0, &message)) << message;
}

// The bound's premise, over random models: an exact smoother's estimate is a symmetric shrinkage
// of the component (eigenvalues in [0, 1)), so its RMS about the mean never exceeds the
// component's. 120 cases (seeds 5000+): stationary AR(1..8) from reflection coefficients drawn in
// (-0.99, 0.99), q/R from 1e-6 to 1e4 (both given explicitly), signal far above and far below the
// noise, through FilterAr with the smoother and the paper's start. None may exceed the bound, and
// the ratio must stay below 1 up to the steady-state switch's 3.5e-9.
TEST(FilterBrokeDown, AnExactSmootherNeverExceedsItsComponent) {
  std::mt19937_64 rng(5000);
  std::uniform_real_distribution<double> kappa_draw(-0.99, 0.99), log_ratio(-6.0, 4.0);
  std::uniform_int_distribution<int> order_draw(1, 8);
  double worst = 0.0;
  for (int c = 0; c < 120; ++c) {
    const int p = order_draw(rng);
    Eigen::VectorXd kappa(p);
    for (int i = 0; i < p; ++i) kappa[i] = kappa_draw(rng);
    const Eigen::VectorXd phi = ar::StepUp(kappa);
    const double q = std::pow(10.0, log_ratio(rng)), r = 1.0;
    const kalman::testing::ArSimulation sim =
        kalman::testing::SimulateArPlusNoise(phi, q, r, 4000, 5000 + c);
    kalman::ArKalmanOptions o;
    o.q = q;
    o.r = r;
    o.mean = sim.z.mean();
    o.smooth = true;
    o.smoother_model_check = false;  // the smoother's own output
    const kalman::ArKalmanResult res = kalman::FilterAr(sim.z, phi, -1, -1, o);
    ASSERT_TRUE(HasResult(res.summary.termination)) << res.summary.message;
    const double variance = (sim.z.array() - o.mean).square().mean();
    const double ratio = std::sqrt((res.smoothed.array() - o.mean).square().mean() / variance);
    worst = std::max(worst, ratio);
    std::string message;
    EXPECT_FALSE(FilterBrokeDown(res, o.mean, variance, &message))
        << message << " case " << c << " AR(" << p << ") q/R " << q;
    EXPECT_LE(ratio, 1.0 + 3.5e-9) << "case " << c;
  }
  RecordProperty("worst_smoothed_rms_ratio", std::to_string(worst));
}

// The smoother's model check is measured for the share rule's own q and R on EMD components only
// (docs/filtering.md, "S5"): scaled, explicit or innovation-matched q and R leave it off.
TEST(ComponentFilterOptions, TurnsTheSmoothersModelCheckOnOnlyForTheShareRulesOwnQAndR) {
  ar::ArModel model;
  model.phi = Eigen::VectorXd::Constant(1, 0.9);
  model.innovation_variance = 1.0;
  double r = 0.0;
  ComponentOptions options;
  EXPECT_TRUE(ComponentFilterOptions(options, 0.5, 2.0, model, &r).smoother_model_check);
  ComponentOptions scaled = options;
  scaled.kalman.q_scale = 10.0;
  EXPECT_FALSE(ComponentFilterOptions(scaled, 0.5, 2.0, model, &r).smoother_model_check);
  ComponentOptions explicit_q = options;
  explicit_q.kalman.q = 0.1;
  EXPECT_FALSE(ComponentFilterOptions(explicit_q, 0.5, 2.0, model, &r).smoother_model_check);
  ComponentOptions innovation = options;
  innovation.noise_rule = ComponentNoiseRule::kInnovationMatch;
  EXPECT_FALSE(ComponentFilterOptions(innovation, 0.5, 2.0, model, &r).smoother_model_check);
}

}  // namespace
}  // namespace fogpipe::method
