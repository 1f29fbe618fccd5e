#include "algorithms/ar/reflection.h"

#include <gtest/gtest.h>

#include "tests/algorithms/ar/ar_test_support.h"

namespace fogpipe::ar {
namespace {

// AR(2) partial autocorrelations in closed form (Box, Jenkins & Reinsel, sec. 3.2.6):
// kappa_1 = rho_1 = phi_1 / (1 - phi_2), kappa_2 = phi_2.
TEST(Reflection, StepDownOfAnAr2GivesItsClosedFormPartialAutocorrelations) {
  Eigen::VectorXd phi(2);
  phi << 1.5, -0.75;
  Eigen::VectorXd kappa;
  ASSERT_TRUE(StepDown(phi, &kappa));
  EXPECT_NEAR(kappa(0), 1.5 / 1.75, 1e-15);
  EXPECT_NEAR(kappa(1), -0.75, 1e-15);
}

TEST(Reflection, StepUpInvertsStepDownOnThePaperImf6Model) {
  const Eigen::VectorXd phi = testing::PaperImf6Phi();
  Eigen::VectorXd kappa;
  ASSERT_TRUE(StepDown(phi, &kappa));
  EXPECT_LT(kappa.cwiseAbs().maxCoeff(), 1.0);
  // Each step-down/step-up divides/multiplies by 1 - kappa^2; with kappa_1 near 1 the round trip
  // loses about log10(1 / (1 - kappa_1^2)) digits, hence 1e-11 rather than 1e-15.
  EXPECT_LT((StepUp(kappa) - phi).cwiseAbs().maxCoeff(), 1e-11);
}

TEST(Reflection, StepDownRejectsANonStationaryModel) {
  Eigen::VectorXd phi(2);
  phi << 2.0004, -1.0005;  // the paper's imf9 row: complex roots of modulus sqrt(1.0005)
  Eigen::VectorXd kappa;
  EXPECT_FALSE(StepDown(phi, &kappa));
}

}  // namespace
}  // namespace fogpipe::ar
