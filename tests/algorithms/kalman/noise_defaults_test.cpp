#include "algorithms/kalman/noise_defaults.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>

#include "algorithms/simulation/random.h"
#include "tests/algorithms/kalman/paper_models.h"
#include "tests/algorithms/kalman/simulate_ar.h"

namespace fogpipe::kalman {
namespace {

// Closed form for AR(1) + white noise. z(k) - phi z(k-1) = w(k) + v(k) - phi v(k-1) is an MA(1)
// with autocovariances g0 = q + R (1 + phi^2), g1 = -phi R; writing it as eps(k) + theta eps(k-1)
// with |theta| < 1 gives theta = (1 - sqrt(1 - 4 rho^2)) / (2 rho), rho = g1 / g0, and the
// innovation variance of z is sigma^2 = g1 / theta (Box & Jenkins, ARMA(1,1) innovations).
double Arma11InnovationVariance(double phi, double q, double r) {
  const double g0 = q + r * (1.0 + phi * phi), g1 = -phi * r;
  const double rho = g1 / g0;
  const double theta = (1.0 - std::sqrt(1.0 - 4.0 * rho * rho)) / (2.0 * rho);
  return g1 / theta;
}

TEST(DefaultNoise, RecoversQFromTheClosedFormArma11InnovationVariance) {
  for (double phi : {0.3, 0.9, -0.7, 0.999}) {
    for (double q : {1e-4, 0.1, 1.0, 10.0}) {
      const double r = 2.0;
      Eigen::VectorXd phi_v(1);
      phi_v << phi;
      const double s = Arma11InnovationVariance(phi, q, r);
      const DefaultNoiseResult d = DefaultNoise(phi_v, s, r);
      ASSERT_EQ(d.summary.termination, Termination::kSuccess) << d.summary.message;
      EXPECT_DOUBLE_EQ(d.r, r);
      // The root is bracketed to 1e-12 relative; the closed form loses a few digits when
      // 4 rho^2 is close to 1 (small q): 1e-8 relative covers both.
      EXPECT_NEAR(d.q, q, 1e-8 * q) << "phi " << phi << " q " << q;
      EXPECT_NEAR(d.implied_innovation_variance, s, 1e-11 * s);
      EXPECT_LE(d.summary.iterations, 100);
    }
  }
}

// Innovation variance of z estimated from data, independently of fogpipe's AR code: least squares
// (Householder QR) of z(k) on its previous m values. For AR(2) + noise, z is ARMA(2,2); its MA
// roots (the eigenvalues of A (I - G H)) have modulus 0.605 here, so the AR(40) truncation error is
// ~0.605^80 ~ 3e-18, negligible.
double LongArInnovationVariance(const Eigen::VectorXd& z, int m) {
  const Eigen::Index n = z.size() - m;
  Eigen::MatrixXd x(n, m);
  for (int j = 0; j < m; ++j) x.col(j) = z.segment(m - 1 - j, n);
  const Eigen::VectorXd y = z.tail(n);
  const Eigen::VectorXd beta = x.householderQr().solve(y);
  return (y - x * beta).squaredNorm() / static_cast<double>(n - m);
}

TEST(DefaultNoise, RecoversTheTrueNoiseFromSimulatedDataAndTheNaiveRuleDoubleCounts) {
  Eigen::VectorXd phi(2);
  phi << 1.5, -0.7;
  const double q_true = 1.0, r_true = 4.0;
  const long long n = 400000;
  const testing::ArSimulation sim = testing::SimulateArPlusNoise(phi, q_true, r_true, n, 2024);
  const double s_hat = LongArInnovationVariance(sim.z, 40);

  // R is the white-noise floor (given: estimating it is the Allan part's job); q from the rule.
  const DefaultNoiseResult d = DefaultNoise(phi, s_hat, r_true);
  ASSERT_EQ(d.summary.termination, Termination::kSuccess);
  EXPECT_DOUBLE_EQ(d.r, r_true);

  // Tolerance: s_hat is a residual variance of n ~white residuals, relative standard error
  // sqrt(2 / n) = 0.22 %. It maps onto q through the slope of S(q): dq/q = (S / (q dS/dq)) dS/S.
  const double h = 1e-4;
  const double s_plus = SolveDare(phi, q_true * (1 + h), r_true).innovation_variance;
  const double s_minus = SolveDare(phi, q_true * (1 - h), r_true).innovation_variance;
  const double s_true = SolveDare(phi, q_true, r_true).innovation_variance;
  const double elasticity = (s_plus - s_minus) / (2 * h * s_true);  // (q/S) dS/dq
  const double tolerance = 5.0 * std::sqrt(2.0 / n) / elasticity;
  EXPECT_NEAR(d.q / q_true, 1.0, tolerance) << "elasticity " << elasticity;
  EXPECT_LT(tolerance, 0.05);  // the check is meaningful: q is pinned to a few percent

  // Naive rule: q = s_hat. Its model implies a one-step prediction-error variance of at least
  // s_hat + R: the measurement noise is counted twice (noise_defaults.h), and q is far off.
  const double s_naive = SolveDare(phi, s_hat, r_true).innovation_variance;
  EXPECT_GE(s_naive, s_hat + r_true);
  EXPECT_NEAR(d.implied_innovation_variance, s_hat, 1e-10 * s_hat);
  EXPECT_GT(s_hat / q_true, 2.0);  // naive q more than twice the truth for this model
}

TEST(DefaultNoise, WorksOnThePapersSlowModels) {
  for (const testing::PaperModel& m : testing::PaperTable2Models()) {
    const double q = 1e-6, r = 1.0;
    const double s = SolveDare(m.phi, q, r).innovation_variance;
    const DefaultNoiseResult d = DefaultNoise(m.phi, s, r);
    ASSERT_EQ(d.summary.termination, Termination::kSuccess) << m.name << d.summary.message;
    // S(q) - R grows like a fractional power of q for these near-unit-root models, so matching S to
    // 1e-12 relative pins q to ~1e-12 * S / (q dS/dq), here ~1e-6 relative.
    EXPECT_NEAR(d.q, q, 1e-5 * q) << m.name;
  }
}

TEST(DefaultNoise, ClampsQToZeroWhenThereIsNoPredictionErrorAboveTheWhiteFloor) {
  Eigen::VectorXd phi(1);
  phi << 0.5;
  const DefaultNoiseResult d = DefaultNoise(phi, 1.0, 1.5);
  EXPECT_EQ(d.summary.termination, Termination::kSuccess);
  EXPECT_TRUE(d.summary.q_clamped_to_zero);
  EXPECT_EQ(d.q, 0.0);
  EXPECT_FALSE(d.summary.message.empty());
  EXPECT_EQ(DefaultNoise(phi, -1.0, 1.0).summary.termination, Termination::kInvalidOptions);
  EXPECT_EQ(DefaultNoise(phi, 1.0, std::nan("")).summary.termination, Termination::kInvalidOptions);
}

// R from an angle random walk: simulated white rate noise of per-sample standard deviation sigma
// at f_s has N = sigma / sqrt(f_s); the per-sample variance is recovered as N^2 f_s, and the
// Allan variance at tau0 (half the mean squared first difference) agrees within its standard error.
TEST(DefaultNoise, WhiteNoiseVarianceFromArwIsTheAllanVarianceAtTau0) {
  const double sigma = 3e-5, fs = 100.0;
  const double arw = sigma / std::sqrt(fs);
  EXPECT_NEAR(WhiteNoiseVarianceFromArw(arw, fs), sigma * sigma, 1e-15 * sigma * sigma);
  simulation::RandomSource source(5);
  const int n = 200000;
  double sum = 0.0, prev = sigma * source.Normal();
  for (int k = 1; k < n; ++k) {
    const double y = sigma * source.Normal();
    sum += (y - prev) * (y - prev);
    prev = y;
  }
  const double avar_tau0 = 0.5 * sum / (n - 1);
  // Overlapping differences: var of the estimate ~ (3/2)(2/n) sigma^4 -> relative SE sqrt(3/n).
  EXPECT_NEAR(avar_tau0 / WhiteNoiseVarianceFromArw(arw, fs), 1.0, 5.0 * std::sqrt(3.0 / n));
}

}  // namespace
}  // namespace fogpipe::kalman
