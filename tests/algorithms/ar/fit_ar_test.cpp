#include "algorithms/ar/fit_ar.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "algorithms/ar/order_selection.h"
#include "tests/algorithms/ar/ar_test_support.h"

namespace fogpipe::ar {
namespace {

TEST(FitAr, EstimatorNamesAreStable) {
  EXPECT_STREQ(ToString(Estimator::kBurg), "burg");
  EXPECT_STREQ(ToString(Estimator::kLeastSquaresQr), "least_squares_qr");
  EXPECT_STREQ(ToString(Estimator::kYuleWalker), "yule_walker");
  EXPECT_STREQ(ToString(Estimator::kMaximumLikelihood), "maximum_likelihood");
}

TEST(FitAr, RejectsInvalidOptionsWithAMessage) {
  std::string error;
  EXPECT_TRUE(ArOptions{}.IsValid(&error));
  ArOptions bad;
  bad.max_order = 0;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_FALSE(error.empty());
  bad = ArOptions{};
  bad.fixed_order = 21;
  EXPECT_FALSE(bad.IsValid(&error));
  const ArFit fit = FitAr(testing::WhiteNoise(1000, 1.0, 1), bad);
  EXPECT_EQ(fit.summary.termination, Termination::kInvalidOptions);
  EXPECT_FALSE(HasResult(fit.summary.termination));
}

TEST(FitAr, ReportsTooFewSamplesNonFiniteAndConstantInputAsData) {
  EXPECT_EQ(FitAr(testing::WhiteNoise(60, 1.0, 2), ArOptions{}).summary.termination,
            Termination::kInsufficientData);
  Eigen::VectorXd x = testing::WhiteNoise(1000, 1.0, 3);
  x(500) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(FitAr(x, ArOptions{}).summary.termination, Termination::kNumericalFailure);
  EXPECT_EQ(FitAr(Eigen::VectorXd::Constant(1000, 2.5), ArOptions{}).summary.termination,
            Termination::kNumericalFailure);
}

// Every estimator, through the front door, on the same AR(4) record of 1e6 samples: BIC picks 4 and
// each coefficient lies within 3 standard errors of the truth. The mean is removed and reported.
class EveryEstimator : public ::testing::TestWithParam<Estimator> {};

TEST_P(EveryEstimator, PicksTheOrderAndRecoversAKnownAr4WithItsMean) {
  Eigen::VectorXd truth(4);
  truth << 0.6, -0.3, 0.2, 0.15;
  static const Eigen::VectorXd x = testing::SimulateAr(truth, 2.0, 1000000, 91, 20000, -7.0);
  ArOptions options;
  options.estimator = GetParam();
  options.max_order = 8;  // keeps the QR estimator's 2 N (P+1)^2 flops modest
  const ArFit fit = FitAr(x, options);
  ASSERT_EQ(fit.summary.termination, Termination::kSuccess) << fit.summary.message;
  EXPECT_EQ(fit.summary.orders_tried, 8);
  ASSERT_EQ(fit.bic.size(), 8);
  ASSERT_EQ(fit.model.order, 4) << fit.summary.message;
  for (int i = 0; i < 4; ++i)
    EXPECT_LT(std::abs(fit.model.phi(i) - truth(i)), 3.0 * fit.model.phi_std_error(i)) << i;
  EXPECT_TRUE(fit.model.stationary);
  // Innovation variance 4; sd of its estimate ~ 4 sqrt(2 / N) = 0.0057.
  EXPECT_NEAR(fit.model.innovation_variance, 4.0, 0.03);
  // Mean of an AR process: sd = sigma / (1 - sum phi) / sqrt(N) = 2 / 0.35 / 1000 = 0.0057.
  EXPECT_NEAR(fit.model.mean, -7.0, 0.03);
  EXPECT_EQ(fit.model.num_samples, x.size());
}

// A smooth trend (what the EMD residue looks like): a root cluster at z = 1. Every estimator must
// still return a finite model with a perfect one-step fit. Burg's and Yule-Walker's reflection
// coefficients stay inside (-1, 1) exactly; ML starts from them (the step-down of the rounded phi
// fails here), so ML must return a result too.
TEST_P(EveryEstimator, ReturnsAFiniteModelForASmoothTrend) {
  Eigen::VectorXd trend(3600);
  for (int i = 0; i < trend.size(); ++i) trend(i) = 1e-3 * i + 2e-7 * i * static_cast<double>(i);
  ArOptions options;
  options.estimator = GetParam();
  const ArFit fit = FitAr(trend, options);
  ASSERT_TRUE(HasResult(fit.summary.termination)) << fit.summary.message;
  EXPECT_GE(fit.model.order, 1);
  EXPECT_TRUE(fit.model.phi.allFinite());
  EXPECT_GT(fit.diagnostics.fit_one_step_percent, 99.0);
}

INSTANTIATE_TEST_SUITE_P(FitAr, EveryEstimator,
                         ::testing::Values(Estimator::kBurg, Estimator::kLeastSquaresQr,
                                           Estimator::kYuleWalker, Estimator::kMaximumLikelihood),
                         [](const auto& info) { return std::string(ToString(info.param)); });

// The paper's Table 2 imf6 row is printed in MATLAB's A(q) form; fogpipe's MatlabA() of a model
// fitted to data simulated from it shows the same sign pattern (-, +, -, +) and values within 3 se.
TEST(FitAr, MatlabAReproducesThePaperTable2Imf6Row) {
  Eigen::VectorXd table2(4);
  table2 << -3.9151, 5.7665, -3.7869, 0.9356;
  const Eigen::VectorXd x = testing::SimulateAr(-table2, 1e-3, 1000000, 92);
  const ArFit fit = FitAr(x, ArOptions{});
  ASSERT_EQ(fit.model.order, 4);
  const Eigen::VectorXd a = fit.model.MatlabA();
  EXPECT_TRUE(a.isApprox(-fit.model.phi));
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(std::signbit(a(i)), std::signbit(table2(i))) << i;
    EXPECT_LT(std::abs(a(i) - table2(i)), 3.0 * fit.model.phi_std_error(i)) << i;
  }
}

TEST(FitAr, FixedOrderIsUsedAndBicIsStillReported) {
  Eigen::VectorXd phi(2);
  phi << 1.2, -0.6;
  ArOptions options;
  options.fixed_order = 5;
  const ArFit fit = FitAr(testing::SimulateAr(phi, 1.0, 20000, 93), options);
  EXPECT_EQ(fit.model.order, 5);
  EXPECT_EQ(fit.bic.size(), 5);
  EXPECT_EQ(SelectOrderByBic(fit.bic), 2);
}

// A mildly explosive AR(1), phi = 1.001: least squares reproduces the explosive root (its error is
// ~phi^-N, super-consistent) and the model is flagged; Burg's reflection coefficient is bounded by
// 1 by construction, so Burg reports a root just inside the unit circle.
TEST(FitAr, FlagsAnExplosiveFitAndReportsItsRootModulus) {
  const Eigen::VectorXd x =
      testing::SimulateAr(Eigen::VectorXd::Constant(1, 1.001), 1.0, 20000, 94, 0);
  ArOptions options;
  options.fixed_order = 1;
  options.compute_diagnostics = false;
  options.estimator = Estimator::kLeastSquaresQr;
  const ArFit ls = FitAr(x, options);
  EXPECT_FALSE(ls.model.stationary);
  EXPECT_NEAR(ls.model.max_root_modulus, 1.001, 1e-4);
  EXPECT_NE(ls.summary.message.find("NOT stationary"), std::string::npos);
  options.estimator = Estimator::kBurg;
  const ArFit burg = FitAr(x, options);
  EXPECT_TRUE(burg.model.stationary);
  EXPECT_GT(burg.model.max_root_modulus, 0.999);
}

// Random walk: the Burg AR(1) root is reported at ~1 (>= 0.999 for 1e5 samples).
TEST(FitAr, ReportsARootModulusNearOneForARandomWalk) {
  const Eigen::VectorXd steps = testing::WhiteNoise(100000, 1.0, 95);
  Eigen::VectorXd walk(steps.size());
  double s = 0.0;
  for (Eigen::Index i = 0; i < steps.size(); ++i) walk(i) = (s += steps(i));
  ArOptions options;
  options.fixed_order = 1;
  const ArFit fit = FitAr(walk, options);
  EXPECT_GT(fit.model.max_root_modulus, 0.999);
  EXPECT_LT(fit.model.max_root_modulus, 1.0 + 1e-12);
}

TEST(FitAr, SkipsDiagnosticsWhenAskedTo) {
  ArOptions options;
  options.compute_diagnostics = false;
  const ArFit fit = FitAr(testing::WhiteNoise(5000, 1.0, 96), options);
  EXPECT_EQ(fit.diagnostics.fit_one_step_percent, 0.0);
  EXPECT_EQ(fit.diagnostics.ljung_box_q10, 0.0);
}

// The streamed method fits each component in its own buffer and reads it back for the
// diagnostics (FitArInPlace): every field must equal FitAr's, whose x stays untouched.
TEST(FitAr, TheInPlaceFitEqualsTheFitOnAKeptSeriesBitForBit) {
  Eigen::VectorXd phi(4);
  phi << 1.2, -0.6, 0.3, -0.1;
  const Eigen::VectorXd x = testing::SimulateAr(phi, 0.7, 20000, 31).array() + 3.5;
  for (Estimator estimator : {Estimator::kBurg, Estimator::kYuleWalker}) {
    ArOptions options;
    options.estimator = estimator;
    ArWork kept_work, in_place_work;
    const ArFit kept = FitAr(x, options, &kept_work);
    Eigen::VectorXd buffer = x;
    int reloads = 0;
    const ArFit in_place = FitArInPlace(&buffer, options, &in_place_work, [&](Eigen::VectorXd* v) {
      ++reloads;
      *v = x;
    });
    const bool burg = estimator == Estimator::kBurg;
    EXPECT_EQ(reloads, burg ? 1 : 0) << ToString(estimator);
    EXPECT_EQ(buffer, x) << "the series is back (or untouched) after the fit";
    if (burg) {
      EXPECT_EQ(in_place_work.burg.forward.size(), 0) << "no forward array of its own";
    }
    EXPECT_EQ(in_place.model.order, kept.model.order);
    EXPECT_EQ(in_place.model.phi, kept.model.phi);
    EXPECT_EQ(in_place.model.mean, kept.model.mean);
    EXPECT_EQ(in_place.model.innovation_variance, kept.model.innovation_variance);
    EXPECT_EQ(in_place.bic, kept.bic);
    EXPECT_EQ(in_place.diagnostics.fit_one_step_percent, kept.diagnostics.fit_one_step_percent);
    EXPECT_EQ(in_place.diagnostics.fit_simulation_percent, kept.diagnostics.fit_simulation_percent);
    EXPECT_EQ(in_place.diagnostics.residual_variance, kept.diagnostics.residual_variance);
    EXPECT_EQ(in_place.diagnostics.ljung_box_q10, kept.diagnostics.ljung_box_q10);
    EXPECT_EQ(in_place.diagnostics.ljung_box_q20, kept.diagnostics.ljung_box_q20);
    EXPECT_EQ(in_place.summary.message, kept.summary.message);
  }
}

// The diagnostics read the series after the reload: a reload that returns other data must show.
TEST(FitAr, TheInPlaceFitsDiagnosticsReadTheReloadedSeries) {
  const Eigen::VectorXd x = testing::WhiteNoise(20000, 1.0, 32);
  ArWork work;
  Eigen::VectorXd buffer = x;
  const ArFit fit =
      FitArInPlace(&buffer, ArOptions(), &work, [&](Eigen::VectorXd* v) { *v = 2.0 * x; });
  const ArFit kept = FitAr(x, ArOptions());
  EXPECT_EQ(fit.model.phi, kept.model.phi);
  EXPECT_NE(fit.diagnostics.residual_variance, kept.diagnostics.residual_variance);
}

}  // namespace
}  // namespace fogpipe::ar
