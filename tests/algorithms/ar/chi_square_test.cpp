#include "algorithms/ar/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fogpipe::ar {
namespace {

// For even dof = 2k: P(chi2 > x) = exp(-x/2) sum_{j<k} (x/2)^j / j!  (Abramowitz & Stegun 26.4.21).
double EvenDofSurvival(double x, int dof) {
  const double h = 0.5 * x;
  double term = 1.0;
  double sum = 1.0;
  for (int j = 1; j < dof / 2; ++j) {
    term *= h / j;
    sum += term;
  }
  return std::exp(-h) * sum;
}

TEST(ChiSquare, TwoDegreesOfFreedomIsAnExponentialTail) {
  for (double x : {0.01, 0.5, 1.0, 2.9, 3.1, 10.0, 50.0, 200.0}) {
    EXPECT_NEAR(ChiSquareSurvival(x, 2.0), std::exp(-x / 2.0), 1e-14 * std::exp(-x / 2.0)) << x;
  }
}

TEST(ChiSquare, OneDegreeOfFreedomIsTheComplementaryErrorFunction) {
  for (double x : {0.001, 0.3, 1.0, 3.841, 10.0, 40.0}) {
    const double expected = std::erfc(std::sqrt(x / 2.0));
    EXPECT_NEAR(ChiSquareSurvival(x, 1.0), expected, 1e-13 * expected) << x;
  }
}

// Both branches (series below a + 1, continued fraction above) against the even-dof closed form.
TEST(ChiSquare, EvenDegreesOfFreedomMatchThePoissonSumOnBothBranches) {
  for (int dof : {4, 10, 18, 20, 40}) {
    for (double x : {0.5, 5.0, 9.0, 11.0, 19.0, 21.0, 30.0, 60.0, 150.0}) {
      const double expected = EvenDofSurvival(x, dof);
      EXPECT_NEAR(ChiSquareSurvival(x, dof), expected, 1e-12 * expected + 1e-300)
          << "dof " << dof << " x " << x;
    }
  }
}

// Upper critical values from NIST/SEMATECH e-Handbook, table 1.3.6.7.4 (printed to 3 decimals,
// so the tail probabilities agree to ~1e-4 relative).
TEST(ChiSquare, ReproducesPublishedCriticalValues) {
  EXPECT_NEAR(ChiSquareSurvival(3.841, 1), 0.05, 5e-5);
  EXPECT_NEAR(ChiSquareSurvival(6.635, 1), 0.01, 1e-5);
  EXPECT_NEAR(ChiSquareSurvival(18.307, 10), 0.05, 5e-5);
  EXPECT_NEAR(ChiSquareSurvival(23.209, 10), 0.01, 1e-5);
  EXPECT_NEAR(ChiSquareSurvival(31.410, 20), 0.05, 5e-5);
  EXPECT_NEAR(ChiSquareSurvival(11.070, 5), 0.05, 5e-5);
  EXPECT_NEAR(ChiSquareSurvival(15.086, 5), 0.01, 1e-5);
}

TEST(ChiSquare, InvalidArgumentsGiveNan) {
  EXPECT_TRUE(std::isnan(RegularizedGammaQ(0.0, 1.0)));
  EXPECT_TRUE(std::isnan(RegularizedGammaQ(1.0, -1.0)));
  EXPECT_EQ(RegularizedGammaQ(3.0, 0.0), 1.0);
}

}  // namespace
}  // namespace fogpipe::ar
