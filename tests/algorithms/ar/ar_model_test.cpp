#include "algorithms/ar/ar_model.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "tests/algorithms/ar/ar_test_support.h"

namespace fogpipe::ar {
namespace {

TEST(ArModel, MatlabAIsTheNegatedRecursionCoefficients) {
  const ArModel model = MakeArModel(testing::PaperImf6Phi(), 1.0, 0.0, 1000);
  EXPECT_TRUE(model.MatlabA().isApprox(-testing::PaperImf6Phi()));
  // The paper's Table 2 imf6 row in A(q) form: -3.9151, 5.7665, -3.7869, 0.9356.
  Eigen::VectorXd table2(4);
  table2 << -3.9151, 5.7665, -3.7869, 0.9356;
  EXPECT_EQ(model.MatlabA(), table2);
}

// For a complex pair the root modulus is sqrt(-phi_2): z^2 - phi_1 z - phi_2 has |z|^2 = -phi_2.
TEST(ArModel, FlagsThePaperImf9RowAsNonStationaryWithItsClosedFormRootModulus) {
  Eigen::VectorXd phi(2);
  phi << 2.0004, -1.0005;
  const ArModel model = MakeArModel(phi, 1.0, 0.0, 3600);
  EXPECT_FALSE(model.stationary);
  EXPECT_NEAR(model.max_root_modulus, std::sqrt(1.0005), 1e-12);
  EXPECT_TRUE(model.phi_std_error.array().isNaN().all());
}

TEST(ArModel, FlagsThePaperImf8RowAsNonStationary) {
  Eigen::VectorXd phi(3);  // a3 printed as +0.9997 (sic): phi_3 = -0.9997.
  phi << 2.9994, -2.9991, -0.9997;
  const ArModel model = MakeArModel(phi, 1.0, 0.0, 3600);
  EXPECT_FALSE(model.stationary);
  EXPECT_GT(model.max_root_modulus, 1.0);
}

// The product of the root moduli is |phi_p| (determinant of the companion matrix); the imf6 roots
// come in two conjugate pairs, so both pair moduli are determined by it and by the largest one.
TEST(ArModel, ThePaperImf6ModelIsStationaryWithRootsInsideTheUnitCircle) {
  const ArModel model = MakeArModel(testing::PaperImf6Phi(), 1.0, 0.0, 1000);
  EXPECT_TRUE(model.stationary);
  EXPECT_LT(model.max_root_modulus, 1.0);
  EXPECT_GT(model.max_root_modulus, 0.99);
  const Eigen::VectorXcd roots = CharacteristicRoots(testing::PaperImf6Phi());
  double product = 1.0;
  for (Eigen::Index i = 0; i < roots.size(); ++i) product *= std::abs(roots(i));
  EXPECT_NEAR(product, 0.9356, 1e-12);
  // Each root satisfies z^4 = phi_1 z^3 + phi_2 z^2 + phi_3 z + phi_4.
  const Eigen::VectorXd phi = testing::PaperImf6Phi();
  for (Eigen::Index i = 0; i < roots.size(); ++i) {
    const std::complex<double> z = roots(i);
    const std::complex<double> residual =
        std::pow(z, 4) - phi(0) * std::pow(z, 3) - phi(1) * z * z - phi(2) * z - phi(3);
    EXPECT_LT(std::abs(residual), 1e-12);
  }
}

// Gohberg-Semencul against a direct inverse of the autocovariance matrix summed from the MA(inf)
// weights (an independent route). AR(3) with moderate roots: Gamma_p is well conditioned, so the
// direct inverse is accurate to ~1e-13.
TEST(ArModel, ClosedFormInverseAutocovarianceMatchesADirectInverse) {
  Eigen::VectorXd phi(3);
  phi << 0.5, 0.2, -0.3;
  const Eigen::VectorXd gamma = testing::TheoreticalAutocovariance(phi, 2);
  Eigen::Matrix3d g;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) g(i, j) = gamma(std::abs(i - j));
  const Eigen::MatrixXd direct = g.inverse();  // sigma^2 = 1
  EXPECT_LT((ScaledInverseAutocovariance(phi) - direct).cwiseAbs().maxCoeff(), 1e-12);
}

// AR(1): Var(phi_hat) = (1 - phi^2) / N (Box, Jenkins & Reinsel, eq. 7.2.x).
TEST(ArModel, StandardErrorOfAnAr1IsSqrtOfOneMinusPhiSquaredOverN) {
  Eigen::VectorXd phi(1);
  phi << 0.8;
  const ArModel model = MakeArModel(phi, 2.0, 0.0, 10000);
  EXPECT_NEAR(model.phi_std_error(0), std::sqrt((1 - 0.64) / 10000.0), 1e-15);
}

}  // namespace
}  // namespace fogpipe::ar
