// Tests of algorithms/allan/chi_square.{h,cpp} against closed forms and printed tables.
#include "algorithms/allan/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fogpipe::allan {
namespace {

// With 2 degrees of freedom the chi-square CDF is 1 - exp(-x/2), so the quantile is -2 ln(1-p).
// The quantile is found from P = 1 - Q, which carries an absolute rounding of ~1e-16, so x is
// determined to 1e-16 / pdf(x) = 1e-16 / (0.5 (1 - p)) plus 1e-12 relative for the iteration.
TEST(ChiSquareQuantile, EqualsTheClosedFormForTwoDegreesOfFreedom) {
  for (double p : {1e-6, 0.1585, 0.5, 0.8415, 0.999999}) {
    const double x = -2.0 * std::log1p(-p);
    EXPECT_NEAR(ChiSquareQuantile(p, 2.0), x, 1e-12 * x + 4e-16 / (0.5 * (1.0 - p))) << p;
  }
}

// One degree of freedom: chi2 = z^2, so the CDF at x is erf(sqrt(x/2)).
TEST(ChiSquareCdf, EqualsErfForOneDegreeOfFreedom) {
  for (double x : {1e-4, 0.3, 1.0, 4.0, 25.0}) {
    EXPECT_NEAR(ChiSquareCdf(x, 1.0), std::erf(std::sqrt(x / 2.0)), 1e-14) << x;
  }
}

// Printed quantiles (Abramowitz & Stegun Table 26.8; 3-5 significant digits as printed).
TEST(ChiSquareQuantile, MatchesPrintedTables) {
  EXPECT_NEAR(ChiSquareQuantile(0.025, 10.0), 3.24697, 5e-5);
  EXPECT_NEAR(ChiSquareQuantile(0.975, 10.0), 20.4832, 5e-4);
  EXPECT_NEAR(ChiSquareQuantile(0.05, 1.0), 0.00393214, 5e-8);
  EXPECT_NEAR(ChiSquareQuantile(0.95, 100.0), 124.342, 5e-3);
  EXPECT_NEAR(ChiSquareQuantile(0.01, 30.0), 14.9535, 5e-4);
}

// Round trip over the range of EDFs the engine meets (fractional ones included). The CDF is
// exp(-x/2 + a ln(x/2) - lgamma(a)) times a series: the exponent has magnitude ~ dof ln(dof), so
// its rounding gives a relative error ~ 1e-16 dof ln(dof) (1.4e-9 at dof = 1e6).
TEST(ChiSquareQuantile, InvertsTheCdf) {
  for (double dof : {0.7, 1.0, 2.5, 3.03, 17.0, 999.5, 1e6}) {
    const double tol = 1e-12 + 1e-16 * dof * std::log(dof + 1.0);
    for (double p : {0.1585, 0.8415, 0.01, 0.99}) {
      EXPECT_NEAR(ChiSquareCdf(ChiSquareQuantile(p, dof), dof), p, tol) << dof << " " << p;
    }
  }
}

}  // namespace
}  // namespace fogpipe::allan
