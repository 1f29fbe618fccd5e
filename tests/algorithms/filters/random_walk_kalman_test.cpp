// Tests algorithms/filters/random_walk_kalman.cpp against dense closed forms on small N (the
// smoother and filter as least-squares solutions, the likelihood of the differenced data) and the
// maximum-likelihood q and R over 60 simulated records.
#include "algorithms/filters/random_walk_kalman.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

namespace fogpipe::filters {
namespace {

Eigen::VectorXd LocalLevel(Eigen::Index n, double q, double r, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  Eigen::VectorXd y(n);
  double x = 5.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    if (k > 0) x += std::sqrt(q) * g(rng);
    y[k] = x + std::sqrt(r) * g(rng);
  }
  return y;
}

/// argmin sum (y_k - x_k)^2 / r + sum (x_k - x_{k-1})^2 / q: (I / r + D'D / q) x = y / r.
Eigen::VectorXd DenseSmoother(const Eigen::VectorXd& y, double q, double r) {
  const Eigen::Index n = y.size();
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(n, n) / r;
  for (Eigen::Index k = 1; k < n; ++k) {
    a(k, k) += 1.0 / q;
    a(k - 1, k - 1) += 1.0 / q;
    a(k, k - 1) -= 1.0 / q;
    a(k - 1, k) -= 1.0 / q;
  }
  return a.ldlt().solve(y / r);
}

TEST(RandomWalkKalman, SmootherEqualsTheTridiagonalLeastSquaresSolution) {
  const Eigen::VectorXd y = LocalLevel(60, 0.05, 1.0, 1);
  for (double q : {1e-4, 0.05, 3.0}) {
    Eigen::VectorXd filtered, smoothed;
    RandomWalkFilterSmoother(y, q, 0.7, &filtered, &smoothed);
    EXPECT_LT((smoothed - DenseSmoother(y, q, 0.7)).cwiseAbs().maxCoeff(), 1e-9) << q;
  }
}

TEST(RandomWalkKalman, FilterEqualsTheLastStateOfEachPrefixLeastSquaresSolution) {
  const Eigen::VectorXd y = LocalLevel(40, 0.05, 1.0, 2);
  Eigen::VectorXd filtered, smoothed;
  RandomWalkFilterSmoother(y, 0.02, 0.5, &filtered, &smoothed);
  for (Eigen::Index k : {0, 1, 5, 20, 39}) {
    const Eigen::VectorXd prefix = DenseSmoother(y.head(k + 1), 0.02, 0.5);
    EXPECT_NEAR(filtered[k], prefix[k], 1e-10) << k;
  }
}

TEST(RandomWalkKalman, ProfileLikelihoodIsThatOfTheDifferencedData) {
  // The diffuse likelihood of the local-level model is the Gaussian likelihood of the first
  // differences d_k = y_k - y_{k-1}: an MA(1) with var q + 2R and lag-1 covariance -R.
  const Eigen::Index n = 80;
  const Eigen::VectorXd y = LocalLevel(n, 0.05, 1.0, 3);
  const Eigen::VectorXd d = y.tail(n - 1) - y.head(n - 1);
  for (double ratio : {1e-3, 0.05, 2.0}) {
    Eigen::MatrixXd s = Eigen::MatrixXd::Zero(n - 1, n - 1);
    for (Eigen::Index k = 0; k < n - 1; ++k) {
      s(k, k) = ratio + 2.0;
      if (k > 0) s(k, k - 1) = s(k - 1, k) = -1.0;
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(s);
    const double m = static_cast<double>(n - 1);
    const double r_hat = d.dot(ldlt.solve(d)) / m;
    const double log_det = ldlt.vectorD().array().log().sum();
    const double expected = -0.5 * m * std::log(r_hat) - 0.5 * log_det;
    double got_r = 0.0;
    EXPECT_NEAR(RandomWalkProfileLikelihood(y, ratio, &got_r), expected, 1e-8) << ratio;
    EXPECT_NEAR(got_r / r_hat, 1.0, 1e-10) << ratio;
  }
}

TEST(RandomWalkKalman, TheFourLaneLikelihoodsEqualTheOneRatioReferenceBitForBit) {
  // The lanes must repeat the one-ratio recursion exactly, so that the search's grid chooses
  // what it chose with one ratio at a time. Ratios from gains that settle within a few samples
  // to ones that never settle within the record (1e-12 with N = 5000), in counts that leave
  // partial groups of lanes.
  const Eigen::VectorXd y = LocalLevel(5000, 1e-4, 1.0, 11);
  const std::vector<double> ratios = {1e-12, 3e-9, 1e-6, 2e-4, 0.05, 1.0, 7.0, 300.0, 1e6};
  for (int count = 1; count <= static_cast<int>(ratios.size()); ++count) {
    std::vector<double> values(count);
    RandomWalkProfileLikelihoods(y, ratios.data(), count, values.data());
    for (int i = 0; i < count; ++i) {
      EXPECT_EQ(values[i], RandomWalkProfileLikelihood(y, ratios[i])) << count << " " << ratios[i];
    }
  }
}

TEST(RandomWalkKalman, MaximumLikelihoodQAndRAreUnbiasedWithinTheirSpreadOver60Seeds) {
  // The ML estimates are consistent; at N = 5000 their bias is far below their spread. The mean
  // of 60 estimates must lie within 3 standard errors (sd / sqrt(60)) of the truth.
  const double q = 0.01, r = 1.0;
  const int seeds = 60;
  Eigen::VectorXd q_hat(seeds), r_hat(seeds);
  for (int s = 0; s < seeds; ++s) {
    const RandomWalkKalmanResult fit =
        RandomWalkKalman(LocalLevel(5000, q, r, 1000 + s), RandomWalkKalmanOptions());
    ASSERT_EQ(fit.termination, Termination::kSuccess);
    q_hat[s] = fit.q;
    r_hat[s] = fit.r;
  }
  auto check = [&](const Eigen::VectorXd& v, double truth, const char* name) {
    const double mean = v.mean();
    const double sd = std::sqrt((v.array() - mean).square().sum() / (seeds - 1));
    EXPECT_LT(std::abs(mean - truth), 3.0 * sd / std::sqrt(double(seeds)))
        << name << " mean " << mean << " sd " << sd;
  };
  check(q_hat, q, "q");
  check(r_hat, r, "R");
}

TEST(RandomWalkKalman, AConstantRateWithNoiseIsFlaggedAtTheLowerBound) {
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g;
  Eigen::VectorXd y(20000);
  for (auto& v : y) v = g(rng);
  const RandomWalkKalmanResult fit = RandomWalkKalman(y, RandomWalkKalmanOptions());
  ASSERT_EQ(fit.termination, Termination::kSuccess);
  EXPECT_NEAR(fit.r, 1.0, 0.05);
  // Smoothed output of a (near-)constant model: close to the sample mean everywhere.
  EXPECT_LT((fit.smoothed.array() - y.mean()).abs().maxCoeff(), 0.1);
}

}  // namespace
}  // namespace fogpipe::filters
