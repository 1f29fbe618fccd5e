#include "algorithms/ar/burg.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "algorithms/ar/fit_ar.h"
#include "algorithms/ar/reflection.h"
#include "tests/algorithms/ar/ar_test_support.h"

namespace fogpipe::ar {
namespace {

// Burg written the textbook way (Kay & Marple 1981, eqs. 93-97): separate arrays per order, no
// blocking, no fused sums. An implementation cross-check for the fused, blocked production code.
Eigen::VectorXd TextbookBurgReflections(const Eigen::VectorXd& x, int order) {
  const Eigen::Index n = x.size();
  Eigen::VectorXd f = x, b = x, kappa(order);
  for (int m = 1; m <= order; ++m) {
    // forward errors f(t), t = m-1..N-1, backward b(t) aligned so that the pair is (f(t), b(t-1)).
    double num = 0.0, den = 0.0;
    for (Eigen::Index t = m; t < n; ++t) {
      num += f(t) * b(t - 1);
      den += f(t) * f(t) + b(t - 1) * b(t - 1);
    }
    const double k = 2.0 * num / den;
    Eigen::VectorXd f2 = f, b2 = b;
    for (Eigen::Index t = m; t < n; ++t) {
      f2(t) = f(t) - k * b(t - 1);
      b2(t) = b(t - 1) - k * f(t);
    }
    f = f2;
    b = b2;
    kappa(m - 1) = k;
  }
  return kappa;
}

TEST(Burg, MatchesTheTextbookRecursionToRoundingOnAShortRecord) {
  const Eigen::VectorXd x = testing::SimulateAr(testing::PaperImf6Phi(), 1.0, 5000, 11);
  const Eigen::VectorXd xc = x.array() - x.mean();
  const OrderSequence seq = BurgAllOrders(xc, 8);
  ASSERT_EQ(seq.orders_completed, 8);
  const Eigen::VectorXd kappa = TextbookBurgReflections(xc, 8);
  // Same arithmetic up to summation order (blocks of 1024 and Eigen's packet sums): ~1e-13.
  EXPECT_LT((seq.phi[7] - StepUp(kappa)).cwiseAbs().maxCoeff(), 1e-9);
  Eigen::VectorXd kappa_fused;
  ASSERT_TRUE(StepDown(seq.phi[7], &kappa_fused));
  EXPECT_LT((kappa_fused - kappa).cwiseAbs().maxCoeff(), 1e-11);
}

// Checks the BIC-selected order and that every coefficient lies within 3 asymptotic standard
// errors of the truth (a 3-sigma band: 0.27 % miss probability per coefficient for a fixed seed).
void ExpectRecovers(const Eigen::VectorXd& truth, const Eigen::VectorXd& x,
                    const ArOptions& options) {
  const ArFit fit = FitAr(x, options);
  ASSERT_TRUE(HasResult(fit.summary.termination)) << fit.summary.message;
  ASSERT_EQ(fit.model.order, truth.size()) << fit.summary.message;
  for (Eigen::Index i = 0; i < truth.size(); ++i) {
    EXPECT_LT(std::abs(fit.model.phi(i) - truth(i)), 3.0 * fit.model.phi_std_error(i))
        << "phi_" << i + 1 << " = " << fit.model.phi(i) << " +/- " << fit.model.phi_std_error(i);
  }
  EXPECT_TRUE(fit.model.stationary);
}

TEST(Burg, BicPicksTheOrderAndRecoversAnAr2OnAMillionSamples) {
  Eigen::VectorXd phi(2);
  phi << 1.2, -0.6;
  ExpectRecovers(phi, testing::SimulateAr(phi, 0.3, 1000000, 21, 20000, 5.0), ArOptions{});
}

TEST(Burg, BicPicksTheOrderAndRecoversThePaperImf6ModelOnAMillionSamples) {
  const Eigen::VectorXd phi = testing::PaperImf6Phi();
  ExpectRecovers(phi, testing::SimulateAr(phi, 1e-3, 1000000, 22), ArOptions{});
}

TEST(Burg, BicPicksTheOrderAndRecoversThePaperImf6ModelOnTenMillionSamples) {
  const Eigen::VectorXd phi = testing::PaperImf6Phi();
  ExpectRecovers(phi, testing::SimulateAr(phi, 1e-3, 10000000, 23), ArOptions{});
}

TEST(Burg, BicPicksTheOrderAndRecoversAnAr4OnTenMillionSamples) {
  Eigen::VectorXd phi(4);
  phi << 0.6, -0.3, 0.2, 0.15;
  ExpectRecovers(phi, testing::SimulateAr(phi, 2.0, 10000000, 24), ArOptions{});
}

TEST(Burg, StopsCleanlyOrStaysFiniteWhenTheSignalIsExactlyPredictable) {
  // A pure cosine obeys x_t = 2 cos(w) x_{t-1} - x_{t-2} exactly, so order 2 leaves only rounding
  // and Burg's known phase-dependent frequency bias on pure tones (Swingler 1979), O(1/N).
  Eigen::VectorXd x(4000);
  for (Eigen::Index t = 0; t < x.size(); ++t) x(t) = std::cos(0.1 * t + 0.3);
  const OrderSequence seq = BurgAllOrders(x, 20);
  ASSERT_GE(seq.orders_completed, 2);
  EXPECT_NEAR(seq.phi[1](0), 2.0 * std::cos(0.1), 1e-5);
  EXPECT_NEAR(seq.phi[1](1), -1.0, 1e-5);
  EXPECT_LT(seq.innovation_variance(1), 1e-10 * 0.5);  // signal variance 0.5
  for (int p = 1; p <= seq.orders_completed; ++p) {
    EXPECT_TRUE(seq.phi[p - 1].allFinite());
    EXPECT_GT(seq.innovation_variance(p - 1), 0.0);
  }
}

}  // namespace
}  // namespace fogpipe::ar
