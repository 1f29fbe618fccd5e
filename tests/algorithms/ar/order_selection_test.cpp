#include "algorithms/ar/order_selection.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/ar/fit_ar.h"
#include "tests/algorithms/ar/ar_test_support.h"

namespace fogpipe::ar {
namespace {

TEST(OrderSelection, BicIsNLogSigma2PlusPLogN) {
  Eigen::VectorXd s2(3);
  s2 << 2.0, 1.0, 0.0;
  const Eigen::VectorXd bic = Bic(s2, 100);
  EXPECT_DOUBLE_EQ(bic(0), 100 * std::log(2.0) + 1 * std::log(100.0));
  EXPECT_DOUBLE_EQ(bic(1), 100 * std::log(1.0) + 2 * std::log(100.0));
  EXPECT_TRUE(std::isinf(bic(2)));
}

TEST(OrderSelection, PicksTheSmallestBicAndTheLowerOrderOnTies) {
  Eigen::VectorXd bic(4);
  bic << 5.0, 3.0, 3.0, 4.0;
  EXPECT_EQ(SelectOrderByBic(bic), 2);
  EXPECT_EQ(SelectOrderByBic(Eigen::VectorXd(0)), 0);
}

// The reason for a common N: changing the units of x (x -> 1000 x) adds the same N ln(1e6) to every
// order, so BIC differences and the selected order do not move.
TEST(OrderSelection, TheSelectedOrderDoesNotDependOnTheUnitsOfX) {
  Eigen::VectorXd phi(3);
  phi << 0.4, 0.2, 0.25;
  const Eigen::VectorXd x = testing::SimulateAr(phi, 1.0, 20000, 61);
  ArOptions options;
  options.compute_diagnostics = false;
  const ArFit a = FitAr(x, options);
  const ArFit b = FitAr(1000.0 * x, options);
  ASSERT_EQ(a.model.order, b.model.order);
  const Eigen::VectorXd da = a.bic.array() - a.bic(0);
  const Eigen::VectorXd db = b.bic.array() - b.bic(0);
  // BIC ~ 2e4 * ln(sigma^2); its rounding is ~1e-16 * 2e5 -> 1e-9 absolute on differences.
  EXPECT_LT((da - db).cwiseAbs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace fogpipe::ar
