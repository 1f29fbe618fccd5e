// Tests of algorithms/common/chi_square.{h,cpp} against closed forms, printed tables and
// Boost.Math (an independent implementation, a test-only dependency: algorithms/ uses Eigen only).
#include "algorithms/common/chi_square.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace fogpipe::stats {
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

// The upper tail is computed directly, so p-values far below 1e-16 keep their digits; for two
// degrees of freedom Q(1, x/2) = exp(-x/2) exactly.
TEST(ChiSquareSurvival, KeepsTinyTailsForTwoDegreesOfFreedom) {
  for (double x : {1.0, 10.0, 100.0, 600.0}) {
    EXPECT_NEAR(ChiSquareSurvival(x, 2.0) / std::exp(-0.5 * x), 1.0, 1e-12) << x;
  }
  EXPECT_NEAR(ChiSquareSurvival(3.0, 4.0) + ChiSquareCdf(3.0, 4.0), 1.0, 1e-15);
}

// The grid of the Boost.Math comparisons: degrees of freedom 0.5 .. 1e6, 20 per decade, and
// probabilities 1e-12 .. 1 - 1e-12, 10 per decade on either side of 1/2.
std::vector<double> DegreesOfFreedom() {
  std::vector<double> dofs;
  for (double l = std::log10(0.5); l <= 6.0 + 1e-9; l += 0.05) dofs.push_back(std::pow(10.0, l));
  return dofs;
}
std::vector<double> Probabilities() {
  std::vector<double> ps;
  for (double l = -12.0; l < std::log10(0.5); l += 0.1) {
    ps.push_back(std::pow(10.0, l));
    ps.push_back(1.0 - std::pow(10.0, l));
  }
  ps.push_back(0.5);
  return ps;
}
// The chi-square quantile by Boost.Math, from the smaller tail (1 - p is exact for p >= 1/2).
double BoostQuantile(double p, double dof) {
  const boost::math::chi_squared law(dof);
  return p < 0.5 ? boost::math::quantile(law, p)
                 : boost::math::quantile(boost::math::complement(law, 1.0 - p));
}

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Relative error bound of P(a, x) and Q(a, x) where the smaller of them is >= 1e-12:
//   - the prefactor x^a e^-x / Gamma(a) = sqrt(a / 2 pi) exp(-bd0 - StirlingError(a)) has an
//     exponent of at most ln(1e12) + ln(sqrt(a)) ~ 35 there, summed from positive series terms:
//     a few ulps of 35, i.e. < 150 eps relative after exp, including sqrt and exp's own ulp;
//   - the series (x < a + 1) and the continued fraction add <= 1 eps per term, and both need
//     ~ sqrt(2 a ln(1 / eps)) < 9 sqrt(a) terms near x = a (fewer away from it), plus ~ 50;
//   - the complement 1 - P or 1 - Q is taken only for the larger of the two (>= ~0.3), which at
//     most triples a relative error;
//   - Boost.Math evaluates double arguments in long double (its default promote_double policy):
//     its own error is below 1 eps.
// Together 3 (200 + 9 sqrt(a)) eps, 1.6e-12 at a = 5e5; the hand-written form before Loader's
// prefactor was off by 1.1e-9 there.
double GammaTolerance(double a) { return 3.0 * (200.0 + 9.0 * std::sqrt(a)) * kEps; }

TEST(RegularizedGamma, AgreesWithBoostMathOverTheChiSquareRange) {
  double max_error = 0.0;
  for (double dof : DegreesOfFreedom()) {
    const boost::math::chi_squared law(dof);
    const double a = 0.5 * dof;
    for (double p : Probabilities()) {
      const double x = BoostQuantile(p, dof);
      const double lower = boost::math::gamma_p(a, 0.5 * x);
      const double upper = boost::math::gamma_q(a, 0.5 * x);
      const double errors[] = {
          std::abs(RegularizedGammaP(a, 0.5 * x) / lower - 1.0),
          std::abs(RegularizedGammaQ(a, 0.5 * x) / upper - 1.0),
          std::abs(ChiSquareCdf(x, dof) / boost::math::cdf(law, x) - 1.0),
          std::abs(ChiSquareSurvival(x, dof) / boost::math::cdf(boost::math::complement(law, x)) -
                   1.0)};
      for (double e : errors) {
        EXPECT_LE(e, GammaTolerance(a)) << "dof " << dof << " p " << p;
        max_error = std::max(max_error, e);
      }
    }
  }
  RecordProperty("max_relative_error", std::to_string(max_error));
  std::printf("P, Q, CDF and survival against Boost.Math: max relative error %.3g\n", max_error);
}

// The quantile solves ChiSquareCdf(x) = p. Near the root the CDF carries an absolute error of
// eps / 2 (the rounding of p itself, and of 1 - Q for p > 1/2) plus min(p, 1 - p) times its
// relative error (GammaTolerance), which moves the root by that over the density; the iteration
// stops within 1e-14 x; Boost.Math's quantile is good to ~1 eps. Near p = 1 - 1e-12 the first
// term dominates: there the spacing of doubles, not the method, limits the answer.
TEST(ChiSquareQuantile, AgreesWithBoostMathOverTheChiSquareRange) {
  double max_error = 0.0, max_ratio = 0.0;
  for (double dof : DegreesOfFreedom()) {
    const boost::math::chi_squared law(dof);
    for (double p : Probabilities()) {
      const double x = BoostQuantile(p, dof);
      const double error = std::abs(ChiSquareQuantile(p, dof) - x);
      const double tol =
          (kEps + std::min(p, 1.0 - p) * GammaTolerance(0.5 * dof)) / boost::math::pdf(law, x) +
          (1e-14 + kEps) * x;
      EXPECT_LE(error, tol) << "dof " << dof << " p " << p;
      max_error = std::max(max_error, error / x);
      max_ratio = std::max(max_ratio, error / tol);
    }
  }
  std::printf("quantile against Boost.Math: max relative error %.3g, max error / bound %.3g\n",
              max_error, max_ratio);
}

// Quantiles are remembered per thread (chi_square.cpp): asked again, in another order, after more
// pairs than the table holds, or on a thread that has asked nothing before, the same bits.
TEST(ChiSquareQuantile, AskedAgainGivesTheSameBitsOnAnyThread) {
  std::vector<std::pair<double, double>> pairs;
  for (double dof : DegreesOfFreedom())
    for (double p : Probabilities()) pairs.emplace_back(p, dof);
  ASSERT_GT(pairs.size(), 1024u);
  std::vector<double> first;
  for (const auto& [p, dof] : pairs) first.push_back(ChiSquareQuantile(p, dof));
  for (std::size_t k = pairs.size(); k-- > 0;)
    EXPECT_EQ(ChiSquareQuantile(pairs[k].first, pairs[k].second), first[k]) << k;
  std::vector<double> fresh(pairs.size());
  std::thread([&] {
    for (std::size_t k = 0; k < pairs.size(); k += 7)
      fresh[k] = ChiSquareQuantile(pairs[k].first, pairs[k].second);
  }).join();
  for (std::size_t k = 0; k < pairs.size(); k += 7) EXPECT_EQ(fresh[k], first[k]) << k;
}

}  // namespace
}  // namespace fogpipe::stats
