#include "algorithms/ar/diagnostics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/ar/fit_ar.h"
#include "tests/algorithms/ar/ar_test_support.h"

namespace fogpipe::ar {
namespace {

ArModel Model(std::initializer_list<double> coefficients, double mean = 0.0) {
  Eigen::VectorXd phi(coefficients.size());
  int i = 0;
  for (double c : coefficients) phi(i++) = c;
  return MakeArModel(phi, 1.0, mean, 1000);
}

// AR(1): ||y - yhat||^2 -> N sigma^2 and ||y - mean||^2 -> N sigma^2 / (1 - phi^2), so the one-step
// fit tends to 100 (1 - sqrt(1 - phi^2)) = 56.411 for phi = 0.9. Sampling error: the energy ratio
// has relative sd ~ sqrt(2 (1 + phi^2) / ((1 - phi^2) N)) = 4.4e-3 at N = 1e6, i.e. ~0.1 in fit %;
// 0.5 is five of those.
TEST(Diagnostics, OneStepFitOfAnAr1MatchesItsClosedForm) {
  const double phi = 0.9;
  const Eigen::VectorXd x =
      testing::SimulateAr(Eigen::VectorXd::Constant(1, phi), 1.0, 1000000, 81);
  const ArDiagnostics d = ComputeDiagnostics(x, Model({phi}));
  EXPECT_NEAR(d.fit_one_step_percent, 100.0 * (1.0 - std::sqrt(1.0 - phi * phi)), 0.5);
  EXPECT_NEAR(d.residual_variance, 1.0, 5.0 * std::sqrt(2.0 / 1e6));  // chi2: sd = sqrt(2/N)
}

// A noise-free signal that obeys the model exactly is reproduced by both predictors. The cosine
// obeys x_t = 2 cos(w) x_{t-1} - x_{t-2}; the free run accumulates rounding linearly in t
// (~1e-16 * 4000 per sample), hence 1e-9 on a percentage.
TEST(Diagnostics, ANoiseFreeSignalThatObeysTheModelFitsOneHundredPercentBothWays) {
  const double w = 0.05;
  Eigen::VectorXd x(4000);
  for (Eigen::Index t = 0; t < x.size(); ++t) x(t) = 3.0 + std::cos(w * t + 0.2);
  const ArDiagnostics d = ComputeDiagnostics(x, Model({2.0 * std::cos(w), -1.0}, 3.0));
  EXPECT_NEAR(d.fit_one_step_percent, 100.0, 1e-9);
  EXPECT_NEAR(d.fit_simulation_percent, 100.0, 1e-9);
}

// Free run of a noise-driven stationary AR(1): the response to the initial state decays within a
// few samples, so ||y - yhat|| = ||y - mean|| up to O(1/N) and the fit is ~0 (here N = 1e5).
TEST(Diagnostics, SimulationFitOfANoiseDrivenProcessIsAboutZero) {
  const Eigen::VectorXd x = testing::SimulateAr(Eigen::VectorXd::Constant(1, 0.5), 1.0, 100000, 82);
  const ArDiagnostics d = ComputeDiagnostics(x, Model({0.5}, x.mean()));
  EXPECT_NEAR(d.fit_simulation_percent, 0.0, 0.01);
}

TEST(Diagnostics, AnExplodingSimulationGivesMinusInfinity) {
  const Eigen::VectorXd x = testing::WhiteNoise(200000, 1.0, 83);
  const ArDiagnostics d = ComputeDiagnostics(x, Model({1.5}));
  EXPECT_TRUE(std::isinf(d.fit_simulation_percent));
  EXPECT_LT(d.fit_simulation_percent, 0.0);
}

// The sweep scores every AR order with OneStepFitPercent and SimulationFitPercents (the free runs
// of one order over all components side by side, no Ljung-Box); its numbers must be the ones `run`
// reports through ComputeDiagnostics, to the last bit, whatever a job's neighbours: here a
// stationary AR(2) fitted exactly, a poor AR(1) whose free run decays to 0 within the first block,
// an exploding model (its lane overflows while the others go on), orders 1-12 of a Burg-like set,
// each on three different series (so one order fills several lanes), and a record that is not a
// multiple of the block length.
TEST(Diagnostics, FitPercentsAloneEqualTheFullDiagnosticsToTheLastBit) {
  const std::vector<Eigen::VectorXd> series = {
      testing::SimulateAr(Eigen::Vector2d(1.2, -0.5), 1.0, 50001, 84),
      testing::SimulateAr(Eigen::Vector2d(0.9, -0.2), 2.0, 50001, 85),
      testing::SimulateAr(Eigen::Vector2d(1.5, -0.6), 0.5, 50001, 86)};
  std::vector<ArModel> models;
  std::vector<int> series_of;
  for (int s = 0; s < 3; ++s) {
    const Eigen::VectorXd& x = series[s];
    for (const ArModel& m : {Model({1.2, -0.5}, x.mean()), Model({0.3}), Model({1.5})})
      models.push_back(m), series_of.push_back(s);
    // Orders beyond the compiled ones (fixed_order::kMaxWideFixedOrder) take the runtime-order
    // lanes, whose state is on the heap.
    for (int p = 1; p <= 16; ++p) {
      Eigen::VectorXd phi = Eigen::VectorXd::Zero(p);
      phi(0) = 1.2 - 0.1 * s;
      if (p > 1) phi(1) = -0.5;
      for (int i = 2; i < p; ++i) phi(i) = 0.01 / i;
      models.push_back(MakeArModel(phi, 1.0, x.mean(), x.size()));
      series_of.push_back(s);
    }
  }
  // Once computing the centred energy themselves, once given it (as the sweep shares it between
  // the two fits of an order).
  std::vector<SimulationFitJob> jobs, jobs_given;
  for (std::size_t k = 0; k < models.size(); ++k) {
    const Eigen::VectorXd& x = series[series_of[k]];
    jobs.push_back({x.data(), x.size(), &models[k]});
    jobs_given.push_back({x.data(), x.size(), &models[k], CenteredTailEnergy(x, models[k].order)});
  }
  const std::vector<double> simulation = SimulationFitPercents(jobs);
  const std::vector<double> simulation_given = SimulationFitPercents(jobs_given);
  ASSERT_EQ(simulation.size(), models.size());
  ASSERT_EQ(simulation_given.size(), models.size());
  for (std::size_t k = 0; k < models.size(); ++k) {
    const Eigen::VectorXd& x = series[series_of[k]];
    const ArDiagnostics d = ComputeDiagnostics(x, models[k]);
    EXPECT_EQ(OneStepFitPercent(x, models[k]), d.fit_one_step_percent) << "model " << k;
    EXPECT_EQ(OneStepFitPercent(x, models[k], CenteredTailEnergy(x, models[k].order)),
              d.fit_one_step_percent)
        << "model " << k;
    EXPECT_EQ(simulation[k], d.fit_simulation_percent) << "model " << k;
    EXPECT_EQ(simulation_given[k], d.fit_simulation_percent) << "model " << k;
  }
}

// A stable model's free run decays to 0 and is then continued as exactly 0 (its subnormal tail is
// flushed, see SimulationFitPercents). Closed form: AR(1) with phi = 0.5 and mean 0 from x_0 = 1
// has the free run s_t = 0.5^t; the error energy is sum_t (x_t - 0.5^t)^2 over t = 1..n-1, which
// the flush cannot change by more than ~1e-300 (0.5^t < 2.2e-308 from t = 1022 on).
TEST(Diagnostics, ADecayedFreeRunIsContinuedAsExactlyZero) {
  const Eigen::Index n = 20000;
  Eigen::VectorXd x(n);
  x[0] = 1.0;
  for (Eigen::Index t = 1; t < n; ++t) x[t] = 0.25 + 1e-3 * static_cast<double>(t % 7);
  const ArModel model = Model({0.5});
  double error = 0.0, centred = 0.0;
  const double mean = x.tail(n - 1).mean();
  for (Eigen::Index t = 1; t < n; ++t) {
    const double s = std::pow(0.5, static_cast<double>(t));
    error += (x[t] - s) * (x[t] - s);
    centred += (x[t] - mean) * (x[t] - mean);
  }
  // The same sums of 2e4 positive terms, in other orders and roundings: each within n eps = 4e-12
  // relative at worst, so the fit (|fit| ~ 1.3e4) within ~1e-11 relative.
  const double expected = 100.0 * (1.0 - std::sqrt(error / centred));
  EXPECT_NEAR(SimulationFitPercents({{x.data(), n, &model}}).front(), expected,
              1e-11 * std::fabs(expected));
}

// The p-value is the chi-square tail (the incomplete gamma itself, both of its branches, is tested
// with its owner in tests/algorithms/common/chi_square_test.cpp). Closed forms: dof = 2, exp(-x/2);
// dof = 1, erfc(sqrt(x/2)). The tail is computed directly (not as 1 - CDF), so the accuracy is
// relative even for tiny p-values.
TEST(Diagnostics, LjungBoxPValueIsTheChiSquareTailInClosedForm) {
  for (double x : {0.01, 0.5, 1.0, 2.9, 3.1, 10.0, 50.0, 200.0}) {
    EXPECT_NEAR(LjungBoxPValue(x, 2.0) / std::exp(-x / 2.0), 1.0, 1e-12) << x;
    EXPECT_NEAR(LjungBoxPValue(x, 1.0) / std::erfc(std::sqrt(x / 2.0)), 1.0, 1e-12) << x;
  }
}

// Upper critical values from the NIST/SEMATECH e-Handbook, table 1.3.6.7.4, printed to 3 decimals;
// the density there is <= 0.03, so the rounding moves the tail by <= 1.5e-5.
TEST(Diagnostics, LjungBoxPValueReproducesPublishedCriticalValues) {
  EXPECT_NEAR(LjungBoxPValue(3.841, 1), 0.05, 5e-5);
  EXPECT_NEAR(LjungBoxPValue(6.635, 1), 0.01, 1e-5);
  EXPECT_NEAR(LjungBoxPValue(11.070, 5), 0.05, 5e-5);
  EXPECT_NEAR(LjungBoxPValue(15.086, 5), 0.01, 1e-5);
  EXPECT_NEAR(LjungBoxPValue(18.307, 10), 0.05, 5e-5);
  EXPECT_NEAR(LjungBoxPValue(23.209, 10), 0.01, 1e-5);
  EXPECT_NEAR(LjungBoxPValue(31.410, 20), 0.05, 5e-5);
}

// Hand computation: e = (1, -1, ..., 1, -1), n = 10: r_1 = -9/10, Q = 10 * 12 * 0.81 / 9 = 10.8,
// one degree of freedom: p = erfc(sqrt(10.8 / 2)).
TEST(Diagnostics, LjungBoxMatchesAHandComputedStatistic) {
  Eigen::VectorXd e(10);
  for (int i = 0; i < 10; ++i) e(i) = (i % 2 == 0) ? 1.0 : -1.0;
  const LjungBoxTest lb = LjungBox(e, 1, 0);
  EXPECT_NEAR(lb.statistic, 10.8, 1e-12);
  EXPECT_EQ(lb.dof, 1);
  EXPECT_NEAR(lb.p_value, std::erfc(std::sqrt(5.4)), 1e-14);
  EXPECT_EQ(LjungBox(e, 10, 12).dof, 1);  // lag - p clamped to >= 1
}

// Under the null the p-value is uniform. Over 200 independent records, the count of p < 0.05 is
// Binomial(200, 0.05): mean 10, P(count <= 2) = 0.0023 and P(count >= 20) = 0.0027, so [3, 19] is a
// ~99.5 % acceptance band; the count of p < 0.5 is Binomial(200, 0.5), [78, 122] is ~99.86 %.
void ExpectUniformPValues(const std::vector<double>& p_values) {
  int below_005 = 0, below_05 = 0;
  for (double p : p_values) {
    below_005 += p < 0.05;
    below_05 += p < 0.5;
  }
  EXPECT_GE(below_005, 3);
  EXPECT_LE(below_005, 19);
  EXPECT_GE(below_05, 78);
  EXPECT_LE(below_05, 122);
}

TEST(Diagnostics, LjungBoxPValuesOfWhiteNoiseAreUniform) {
  std::vector<double> p10, p20;
  for (int seed = 0; seed < 200; ++seed) {
    const Eigen::VectorXd e = testing::WhiteNoise(2000, 1.0, 1000 + seed);
    p10.push_back(LjungBox(e, 10, 0).p_value);
    p20.push_back(LjungBox(e, 20, 0).p_value);
  }
  ExpectUniformPValues(p10);
  ExpectUniformPValues(p20);
}

// The residuals of a correctly specified fitted AR(2): chi-square with lag - 2 dof (Ljung & Box
// 1978) is the null distribution, so the p-values are again ~uniform.
TEST(Diagnostics, LjungBoxPValuesOfACorrectlySpecifiedFitAreUniform) {
  Eigen::VectorXd phi(2);
  phi << 0.7, -0.2;
  ArOptions options;
  options.fixed_order = 2;
  options.max_order = 2;
  std::vector<double> p10, p20;
  for (int seed = 0; seed < 200; ++seed) {
    const ArFit fit = FitAr(testing::SimulateAr(phi, 1.0, 2000, 2000 + seed, 500), options);
    p10.push_back(fit.diagnostics.ljung_box_p10);
    p20.push_back(fit.diagnostics.ljung_box_p20);
  }
  ExpectUniformPValues(p10);
  ExpectUniformPValues(p20);
}

TEST(Diagnostics, LjungBoxRejectsAnAr1FittedToAr2Data) {
  Eigen::VectorXd phi(2);
  phi << 1.2, -0.6;
  ArOptions options;
  options.fixed_order = 1;
  const ArFit fit = FitAr(testing::SimulateAr(phi, 1.0, 10000, 84), options);
  EXPECT_LT(fit.diagnostics.ljung_box_p10, 1e-10);
  EXPECT_LT(fit.diagnostics.ljung_box_p20, 1e-10);
  EXPECT_GT(fit.diagnostics.ljung_box_q10, 100.0);
}

}  // namespace
}  // namespace fogpipe::ar
