// Tests of algorithms/allan/nnls.{h,cpp} against problems with known solutions.
#include "algorithms/allan/nnls.h"

#include <gtest/gtest.h>

namespace fogpipe::allan {
namespace {

// If the unconstrained least-squares solution is positive, NNLS must return it.
TEST(SolveNnls, ReturnsTheUnconstrainedSolutionWhenItIsPositive) {
  Eigen::MatrixXd a(4, 2);
  a << 1, 0, 1, 1, 1, 2, 1, 3;
  const Eigen::VectorXd x_true = (Eigen::VectorXd(2) << 0.5, 2.0).finished();
  const NnlsResult r = SolveNnls(a, a * x_true);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR((r.x - x_true).norm(), 0.0, 1e-12);
}

// Lawson & Hanson's KKT conditions on a problem whose unconstrained optimum has a negative
// component: x = argmin over x >= 0 satisfies w = A^T (b - A x) <= 0 where x = 0, = 0 where x > 0.
// Worked by hand: A = I(3), b = (1, -2, 3) -> x = (1, 0, 3).
TEST(SolveNnls, ClampsNegativeComponentsAndSatisfiesKkt) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Identity(3, 3);
  const Eigen::VectorXd b = (Eigen::VectorXd(3) << 1, -2, 3).finished();
  const NnlsResult r = SolveNnls(a, b);
  EXPECT_NEAR(r.x[0], 1.0, 1e-14);
  EXPECT_EQ(r.x[1], 0.0);
  EXPECT_NEAR(r.x[2], 3.0, 1e-14);
  EXPECT_LE(r.gradient[1], 0.0);
}

// A coupled case where freeing variables in order of gradient must later drop one:
// columns (1,1) and (1,-1)... b = (1, 0.2): unconstrained x = (0.6, 0.4) > 0 with these
// columns; with b = (-1, 3) the unconstrained solution (1, -2) is infeasible and the optimum is
// x = (0, ... ) on column 2 alone: x2 = (a2 . b) / |a2|^2 = (-1 - 3) / 2 < 0 -> also 0, so x = 0
// would be wrong only if a1 . b > 0: a1 . b = 2 > 0 -> x = (1, 0).
TEST(SolveNnls, FindsTheActiveSetOfACoupledProblem) {
  Eigen::MatrixXd a(2, 2);
  a << 1, 1, 1, -1;
  const NnlsResult r = SolveNnls(a, (Eigen::VectorXd(2) << -1, 3).finished());
  EXPECT_NEAR(r.x[0], 1.0, 1e-14);
  EXPECT_EQ(r.x[1], 0.0);
}

}  // namespace
}  // namespace fogpipe::allan
