#include "algorithms/ar/least_squares.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "algorithms/ar/fit_ar.h"
#include "tests/algorithms/ar/ar_test_support.h"

namespace fogpipe::ar {
namespace {

// The lagged matrix Z = [x_{t-1} .. x_{t-P}, x_t], t = P..N-1, built explicitly.
Eigen::MatrixXd LaggedMatrix(const Eigen::VectorXd& x, int order) {
  const Eigen::Index rows = x.size() - order;
  Eigen::MatrixXd z(rows, order + 1);
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (int j = 0; j < order; ++j) z(i, j) = x(order + i - 1 - j);
    z(i, order) = x(order + i);
  }
  return z;
}

TEST(LeastSquares, BlockedFactorEqualsOneQrOfTheWholeLaggedMatrix) {
  Eigen::VectorXd phi(2);
  phi << 0.9, -0.4;
  const Eigen::VectorXd x = testing::SimulateAr(phi, 1.0, 3000, 31);  // 6 row blocks of 512
  const int order = 5;
  const Eigen::MatrixXd z = LaggedMatrix(x, order);
  const Eigen::MatrixXd r = LaggedTriangularFactor(x, order);
  const Eigen::MatrixXd gram = z.transpose() * z;
  // R'R = Z'Z up to rounding of the Householder updates (~1e-15 relative per block).
  EXPECT_LT((r.transpose() * r - gram).norm() / gram.norm(), 1e-13);
  // Each nested order against an independent dense column-pivoting QR solve on the same rows.
  const OrderSequence seq = LeastSquaresAllOrders(x, order);
  ASSERT_EQ(seq.orders_completed, order);
  EXPECT_EQ(seq.num_effective, x.size() - order);
  for (int p = 1; p <= order; ++p) {
    const Eigen::VectorXd direct = z.leftCols(p).colPivHouseholderQr().solve(z.col(order));
    EXPECT_LT((seq.phi[p - 1] - direct).cwiseAbs().maxCoeff(), 1e-12) << "order " << p;
    const double rss = (z.col(order) - z.leftCols(p) * direct).squaredNorm();
    EXPECT_NEAR(seq.innovation_variance(p - 1), rss / z.rows(), 1e-12 * rss / z.rows());
  }
}

TEST(LeastSquares, BicPicksTheOrderAndRecoversThePaperImf6ModelOnAMillionSamples) {
  const Eigen::VectorXd truth = testing::PaperImf6Phi();
  const Eigen::VectorXd x = testing::SimulateAr(truth, 1e-3, 1000000, 32);
  ArOptions options;
  options.estimator = Estimator::kLeastSquaresQr;
  const ArFit fit = FitAr(x, options);
  ASSERT_EQ(fit.summary.termination, Termination::kSuccess) << fit.summary.message;
  ASSERT_EQ(fit.model.order, 4);
  for (int i = 0; i < 4; ++i)
    EXPECT_LT(std::abs(fit.model.phi(i) - truth(i)), 3.0 * fit.model.phi_std_error(i)) << i;
}

// Why not the normal equations: Z'Z of the imf6 model at order 20 has the condition number of
// the model's 20 x 20 autocovariance matrix, 7.2e11 in theory (computed here from the MA(inf)
// weights), so solving Z'Z phi = Z'y keeps ~4 of 16 digits. cond(Z'Z) = cond(R)^2 exactly, so it is
// measured from R without forming Z'Z. The sample value must agree with theory within a factor 2
// (sampling error of the smallest eigenvalue at 1e7 samples is a few per cent).
TEST(LeastSquares, TheNormalEquationsOfThePaperImf6ModelHaveConditionNear1e12) {
  const Eigen::VectorXd x = testing::SimulateAr(testing::PaperImf6Phi(), 1e-3, 10000000, 33);
  const Eigen::VectorXd xc = x.array() - x.mean();
  const int p = 20;
  const Eigen::MatrixXd r = LaggedTriangularFactor(xc, p);
  const Eigen::VectorXd sv =
      Eigen::JacobiSVD<Eigen::MatrixXd>(r.topLeftCorner(p, p)).singularValues();
  const double cond_sample = std::pow(sv(0) / sv(p - 1), 2);

  const Eigen::VectorXd gamma = testing::TheoreticalAutocovariance(testing::PaperImf6Phi(), p);
  Eigen::MatrixXd toeplitz(p, p);
  for (int i = 0; i < p; ++i)
    for (int j = 0; j < p; ++j) toeplitz(i, j) = gamma(std::abs(i - j));
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(toeplitz).eigenvalues();
  const double cond_theory = ev(p - 1) / ev(0);

  EXPECT_GT(cond_theory, 5e11);
  EXPECT_GT(cond_sample, 1e11);
  EXPECT_LT(std::abs(std::log(cond_sample / cond_theory)), std::log(2.0));
}

}  // namespace
}  // namespace fogpipe::ar
