#include "algorithms/emd/cubic_spline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace fogpipe::emd {
namespace {

// p(t) = 2 - 0.5 t + 0.3 t^2 - 0.02 t^3 and its second derivative.
double Cubic(double t) { return 2.0 - 0.5 * t + 0.3 * t * t - 0.02 * t * t * t; }
double CubicSecond(double t) { return 0.6 - 0.12 * t; }

struct Spline {
  std::vector<double> t, y, moment;
  ArrayKnots knots() const { return {t.data(), y.data(), static_cast<int>(t.size())}; }
  double operator()(double u) const { return EvaluateSpline(knots(), moment.data(), u); }
};

Spline Fit(std::vector<double> t, double (*f)(double), SplineKind kind) {
  Spline s;
  s.t = std::move(t);
  for (double u : s.t) s.y.push_back(f(u));
  s.moment.assign(s.t.size(), 0.0);
  std::vector<double> work(s.t.size());
  SolveMoments(s.knots(), kind, s.moment.data(), work.data());
  return s;
}

// Rounding only: values of order 10 and a few operations per piece, so a few 1e-15 relative;
// 1e-12 leaves room for the elimination growth over 20 knots (the system is diagonally dominant).
constexpr double kRoundingTolerance = 1e-12;

TEST(CubicSpline, NotAKnotReproducesACubicPolynomialExactly) {
  for (const std::vector<double>& t :
       {std::vector<double>{0.0, 1.0, 2.5, 4.0},  // n = 4: a single cubic.
        std::vector<double>{-3.0, -1.0, 0.5, 1.0, 3.0, 7.5, 8.0},
        std::vector<double>{0,  1,  2,  3,  5,  8,  13, 21, 22, 23,
                            24, 26, 29, 30, 31, 33, 35, 36, 38, 40}}) {
    const Spline s = Fit(t, Cubic, SplineKind::kNotAKnot);
    for (double u = t.front() - 2.0; u <= t.back() + 2.0; u += 0.37) {
      EXPECT_NEAR(s(u), Cubic(u), kRoundingTolerance * 100.0) << "t = " << u;
    }
    for (size_t j = 0; j < t.size(); ++j) {
      EXPECT_NEAR(s.moment[j], CubicSecond(t[j]), kRoundingTolerance) << "knot " << j;
    }
  }
}

TEST(CubicSpline, NotAKnotThroughThreeKnotsIsTheInterpolatingParabola) {
  auto parabola = [](double t) { return 1.0 + 2.0 * t - 0.75 * t * t; };
  const Spline s = Fit(
      {0.0, 1.0, 3.0}, +[](double t) { return 1.0 + 2.0 * t - 0.75 * t * t; },
      SplineKind::kNotAKnot);
  for (double u = -1.0; u <= 4.0; u += 0.25) EXPECT_NEAR(s(u), parabola(u), kRoundingTolerance);
  for (double m : s.moment) EXPECT_NEAR(m, -1.5, kRoundingTolerance);
}

TEST(CubicSpline, NaturalSplineMatchesTheClosedFormThroughThreePoints) {
  // Through (0,0), (1,1), (2,0) with S''(0) = S''(2) = 0: M1 = 6 (-1 - 1) / (2 (1 + 1)) = -3, so on
  // [0, 1] S(t) = t - (M1 / 6)(t - t^3) ... = 1.5 t - 0.5 t^3, symmetric about t = 1.
  const Spline s = Fit(
      {0.0, 1.0, 2.0}, +[](double t) { return t <= 1.0 ? t : 2.0 - t; }, SplineKind::kNatural);
  EXPECT_NEAR(s.moment[1], -3.0, kRoundingTolerance);
  for (double u = 0.0; u <= 1.0; u += 0.125) {
    const double expected = 1.5 * u - 0.5 * u * u * u;
    EXPECT_NEAR(s(u), expected, kRoundingTolerance);
    EXPECT_NEAR(s(2.0 - u), expected, kRoundingTolerance);
  }
}

TEST(CubicSpline, NaturalSplineHasZeroSecondDerivativeAtTheEnds) {
  const std::vector<double> t = {0.0, 0.7, 1.1, 2.9, 3.0, 4.5, 6.0, 6.2};
  const Spline s = Fit(
      t, +[](double u) { return std::sin(u) + 0.1 * u * u; }, SplineKind::kNatural);
  const int n = static_cast<int>(t.size());
  const CubicPiece first = PieceOf(s.knots(), s.moment.data(), 0);
  const CubicPiece last = PieceOf(s.knots(), s.moment.data(), n - 2);
  EXPECT_EQ(first.SecondDerivative(t[0]), 0.0);
  EXPECT_NEAR(last.SecondDerivative(t[n - 1]), 0.0, kRoundingTolerance);
  // The pieces join with continuous value, slope and curvature (the defining equations).
  for (int j = 1; j < n - 1; ++j) {
    const CubicPiece left = PieceOf(s.knots(), s.moment.data(), j - 1);
    const CubicPiece right = PieceOf(s.knots(), s.moment.data(), j);
    const double e = 1e-6;  // Slope by central differences of the two polynomials: error O(e^2).
    EXPECT_NEAR(left(t[j]), right(t[j]), kRoundingTolerance);
    EXPECT_NEAR((left(t[j]) - left(t[j] - e)) / e, (right(t[j] + e) - right(t[j])) / e, 1e-5);
    EXPECT_NEAR(left.SecondDerivative(t[j]), right.SecondDerivative(t[j]), kRoundingTolerance);
  }
}

TEST(CubicSpline, NaturalSplineReproducesStraightLines) {
  const Spline s = Fit(
      {-2.0, 0.0, 0.5, 3.0, 3.5, 9.0}, +[](double t) { return 4.0 - 1.5 * t; },
      SplineKind::kNatural);
  for (double u = -3.0; u <= 10.0; u += 0.5) EXPECT_NEAR(s(u), 4.0 - 1.5 * u, kRoundingTolerance);
}

TEST(CubicSpline, TwoKnotsGiveTheStraightLineForBothKinds) {
  for (SplineKind kind : {SplineKind::kNotAKnot, SplineKind::kNatural}) {
    const Spline s = Fit(
        {1.0, 3.0}, +[](double t) { return t * t; }, kind);
    EXPECT_NEAR(s(2.0), 5.0, kRoundingTolerance) << ToString(kind);
  }
}

TEST(CubicSpline, KindsHaveStableNames) {
  EXPECT_STREQ(ToString(SplineKind::kNotAKnot), "not_a_knot");
  EXPECT_STREQ(ToString(SplineKind::kNatural), "natural");
}

}  // namespace
}  // namespace fogpipe::emd
