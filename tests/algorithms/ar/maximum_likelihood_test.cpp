#include "algorithms/ar/maximum_likelihood.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>

#include "algorithms/ar/burg.h"
#include "algorithms/ar/fit_ar.h"
#include "algorithms/ar/reflection.h"
#include "tests/algorithms/ar/ar_test_support.h"

namespace fogpipe::ar {
namespace {

// -2 ln L concentrated over sigma^2, minus N (1 + ln 2 pi), computed the brute-force way: the
// full N x N Toeplitz covariance of the model (unit innovation variance, autocovariances from the
// MA(inf) weights), its Cholesky factor, x' Gamma^{-1} x and ln det Gamma. Independent of the
// Gohberg-Semencul / QR / reflection-coefficient machinery under test.
double DirectObjective(const Eigen::VectorXd& x, const Eigen::VectorXd& phi) {
  const Eigen::Index n = x.size();
  const Eigen::VectorXd gamma = testing::TheoreticalAutocovariance(phi, static_cast<int>(n - 1));
  Eigen::MatrixXd cov(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) cov(i, j) = gamma(std::abs(i - j));
  const Eigen::LLT<Eigen::MatrixXd> llt(cov);
  const double quad = x.dot(llt.solve(x));
  const double logdet = 2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  return n * std::log(quad / n) + logdet;
}

TEST(MaximumLikelihood, ObjectiveEqualsTheBruteForceGaussianLikelihood) {
  Eigen::VectorXd truth(2);
  truth << 0.9, -0.4;
  const Eigen::VectorXd x = testing::SimulateAr(truth, 1.0, 200, 71);
  Eigen::VectorXd phi(2);
  phi << 0.85, -0.35;
  MaximumLikelihoodOptions options;
  options.max_iterations = 1;
  Eigen::VectorXd kappa;
  ASSERT_TRUE(StepDown(phi, &kappa));
  const MaximumLikelihoodResult r = FitMaximumLikelihood(x, kappa, options);
  ASSERT_TRUE(r.valid);
  // Both sides are O(100); the N x N Cholesky loses ~1e-13 relative.
  EXPECT_NEAR(r.objective_start, DirectObjective(x, phi), 1e-9);
}

TEST(MaximumLikelihood, ReturnsAStationaryMaximumOfTheBruteForceLikelihood) {
  Eigen::VectorXd truth(3);
  truth << 0.6, 0.1, -0.3;
  const Eigen::VectorXd x = testing::SimulateAr(truth, 1.0, 300, 72);
  const Eigen::VectorXd xc = x.array() - x.mean();
  const OrderSequence burg = BurgAllOrders(xc, 3);
  const MaximumLikelihoodResult ml = FitMaximumLikelihood(xc, burg.reflection.head(3), {});
  ASSERT_TRUE(ml.valid);
  ASSERT_TRUE(ml.converged);
  const double f_ml = DirectObjective(xc, ml.phi);
  EXPECT_NEAR(ml.objective, f_ml, 1e-9);
  EXPECT_LT(f_ml, DirectObjective(xc, burg.phi[2]));  // ML improves on its Burg start
  // No coordinate step of 1e-4 (0.002 standard errors here) lowers the brute-force objective.
  // Near the optimum F rises by ~(h / se)^2 ~ 4e-6, far above the 1e-10 rounding of F.
  for (int i = 0; i < 3; ++i) {
    for (double h : {-1e-4, 1e-4}) {
      Eigen::VectorXd phi = ml.phi;
      phi(i) += h;
      EXPECT_GT(DirectObjective(xc, phi), f_ml) << "coordinate " << i << " step " << h;
    }
  }
}

void ExpectMlRecovers(const Eigen::VectorXd& truth, double sigma, Eigen::Index n,
                      std::uint64_t seed) {
  const Eigen::VectorXd x = testing::SimulateAr(truth, sigma, n, seed);
  ArOptions options;
  options.estimator = Estimator::kMaximumLikelihood;
  options.compute_diagnostics = false;
  const ArFit ml = FitAr(x, options);
  ASSERT_EQ(ml.summary.termination, Termination::kSuccess) << ml.summary.message;
  ASSERT_EQ(ml.model.order, truth.size());
  for (Eigen::Index i = 0; i < truth.size(); ++i)
    EXPECT_LT(std::abs(ml.model.phi(i) - truth(i)), 3.0 * ml.model.phi_std_error(i)) << i;

  // How far ML moves Burg, in standard errors (reported in fit_ar.h).
  options.estimator = Estimator::kBurg;
  const ArFit burg = FitAr(x, options);
  const double shift =
      ((ml.model.phi - burg.model.phi).array() / ml.model.phi_std_error.array()).abs().maxCoeff();
  std::cout << "ML - Burg, N = " << n << ", order " << truth.size()
            << ": max |dphi| / se = " << shift
            << ", max |dphi| = " << (ml.model.phi - burg.model.phi).cwiseAbs().maxCoeff()
            << ", ML iterations " << ml.summary.ml_iterations << "\n";
  // Theory: Burg and exact ML differ by O(1/N) in phi, i.e. O(1/sqrt(N)) standard errors. A shift
  // above 0.1 se would mean one of them is not doing what it claims.
  EXPECT_LT(shift, 0.1);
}

TEST(MaximumLikelihood, RecoversAnAr2AndStaysWithinATenthOfAStandardErrorOfBurg) {
  Eigen::VectorXd truth(2);
  truth << 1.2, -0.6;
  ExpectMlRecovers(truth, 0.3, 100000, 73);
}

TEST(MaximumLikelihood, RecoversAnAr4AndStaysWithinATenthOfAStandardErrorOfBurg) {
  Eigen::VectorXd truth(4);
  truth << 0.6, -0.3, 0.2, 0.15;
  ExpectMlRecovers(truth, 2.0, 1000000, 74);
}

TEST(MaximumLikelihood, RecoversThePaperImf6ModelAndStaysWithinATenthOfAStandardErrorOfBurg) {
  ExpectMlRecovers(testing::PaperImf6Phi(), 1e-3, 1000000, 75);
}

TEST(MaximumLikelihood, RejectsANonStationaryStart) {
  Eigen::VectorXd kappa(2);
  kappa << 0.5, -1.0;
  const MaximumLikelihoodResult r =
      FitMaximumLikelihood(testing::WhiteNoise(500, 1.0, 76), kappa, {});
  EXPECT_FALSE(r.valid);
}

}  // namespace
}  // namespace fogpipe::ar
