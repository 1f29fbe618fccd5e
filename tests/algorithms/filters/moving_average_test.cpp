// Tests algorithms/filters/moving_average.cpp against the naive O(N w) window sums and the
// direct GCV formula.
#include "algorithms/filters/moving_average.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace fogpipe::filters {
namespace {

Eigen::VectorXd NaiveAverage(const Eigen::VectorXd& x, Eigen::Index h, Eigen::VectorXd* counts) {
  const Eigen::Index n = x.size();
  Eigen::VectorXd y(n);
  counts->resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    double sum = 0.0;
    int count = 0;
    for (Eigen::Index j = std::max<Eigen::Index>(0, i - h); j <= std::min(n - 1, i + h); ++j) {
      sum += x[j];
      ++count;
    }
    y[i] = sum / count;
    (*counts)[i] = count;
  }
  return y;
}

Eigen::VectorXd Noise(Eigen::Index n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(3.0, 2.0);
  Eigen::VectorXd x(n);
  for (auto& v : x) v = g(rng);
  return x;
}

TEST(MovingAverage, EqualsTheNaiveWindowSumsIncludingTruncatedEnds) {
  const Eigen::VectorXd x = Noise(500, 1);
  for (Eigen::Index h : {0, 1, 7, 60, 400}) {
    Eigen::VectorXd counts;
    const Eigen::VectorXd expected = NaiveAverage(x, h, &counts);
    EXPECT_LT((CentredMovingAverage(x, h) - expected).cwiseAbs().maxCoeff(), 1e-12) << h;
  }
}

TEST(MovingAverage, GcvScoreAndTraceEqualTheDirectFormula) {
  const Eigen::VectorXd x = Noise(700, 2);
  const MovingAverageGcv gcv(x);
  // Down to no full window at all (2h + 1 > N from h = 350 on).
  for (Eigen::Index h : {1, 2, 3, 5, 33, 200, 348, 349, 350, 400, 699, 800}) {
    Eigen::VectorXd counts;
    const Eigen::VectorXd y = NaiveAverage(x, h, &counts);
    const double trace = counts.cwiseInverse().sum();
    const double n = 700.0;
    const double expected = n * (x - y).squaredNorm() / ((n - trace) * (n - trace));
    double got_trace = 0.0;
    EXPECT_NEAR(gcv.Score(h, &got_trace) / expected, 1.0, 1e-10) << h;
    EXPECT_NEAR(got_trace, trace, 1e-9) << h;
  }
}

TEST(MovingAverage, GcvWindowIsTheGridMinimumWithinTheSearchTolerance) {
  // GCV's choice must score no worse than every half-width on a dense check grid (an
  // independent exhaustive search), up to the golden section's last bracket.
  Eigen::VectorXd x = Noise(3000, 3);
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += 4.0 * std::sin(i / 300.0);
  const MovingAverageResult r = MovingAverage(x, MovingAverageOptions());
  ASSERT_EQ(r.termination, Termination::kSuccess);
  const MovingAverageGcv gcv(x);
  double best = 1e300;
  for (Eigen::Index h = 1; h <= 750; ++h) best = std::min(best, gcv.Score(h));
  EXPECT_LE(r.gcv, best * 1.02);
}

}  // namespace
}  // namespace fogpipe::filters
