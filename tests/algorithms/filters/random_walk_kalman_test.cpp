// Tests algorithms/filters/random_walk_kalman.cpp against dense closed forms on small N (the
// smoother and filter as least-squares solutions, the likelihood of the differenced data, the
// known-R likelihood by the covariance of the data given the first sample), the maximum-likelihood
// q and R over 60 simulated records, and the known-R minimum over q on white noise and on walks.
#include "algorithms/filters/random_walk_kalman.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
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

TEST(RandomWalkMinusTwoLogLikelihood, IsThatOfTheDenseCovarianceGivenTheFirstSample) {
  // Given y_0, the diffuse first state is x_0 ~ N(y_0, r), so y_k - y_0 (k >= 1) is Gaussian with
  // covariance r + q min(j, k) + r [j == k]: its -2 ln L by a dense Cholesky factor, less the
  // (N - 1) ln(2 pi) the function leaves out.
  const Eigen::Index n = 50, m = n - 1;
  for (double r : {0.3, 1.0, 4.0}) {
    const Eigen::VectorXd y = LocalLevel(n, 0.05 * r, r, 4);
    const Eigen::VectorXd z = y.tail(m).array() - y[0];
    for (double q : {0.0, 1e-3, 0.05, 2.0}) {
      Eigen::MatrixXd s(m, m);
      for (Eigen::Index j = 0; j < m; ++j) {
        for (Eigen::Index k = 0; k < m; ++k) {
          s(j, k) = r + q * static_cast<double>(std::min(j, k) + 1) + (j == k ? r : 0.0);
        }
      }
      const Eigen::LLT<Eigen::MatrixXd> llt(s);
      ASSERT_EQ(llt.info(), Eigen::Success);
      const Eigen::MatrixXd l = llt.matrixL();
      const double log_det = 2.0 * l.diagonal().array().log().sum();
      const double quadratic = llt.matrixL().solve(z).squaredNorm();
      const double expected = log_det + quadratic;
      EXPECT_NEAR(RandomWalkMinusTwoLogLikelihood(y, q, r), expected, 1e-9 * std::abs(expected))
          << "q " << q << " r " << r;
    }
  }
}

TEST(MinimizeRandomWalkMinusTwoLogLikelihood, IsNotAboveTheLikelihoodAtAnyQOfAFineScan) {
  // The golden section ends within a factor 1.001 of the minimiser in q (header); -2 ln L is
  // quadratic there in ln q with curvature at most about (N - 1) / 2 (the information on the log
  // of a variance from N - 1 innovations), so the value found exceeds the minimum by at most
  // (N - 1) / 4 ln(1.001)^2.
  const Eigen::Index n = 500;
  const double slack = static_cast<double>(n - 1) / 4.0 * std::pow(std::log1p(1e-3), 2);
  const double r = 2.0, min_ratio = 1e-6, max_ratio = 1e2;
  for (double q : {0.0, 1e-4, 0.01, 1.0}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      const Eigen::VectorXd y = LocalLevel(n, q, r, 40 + seed);
      const WalkVarianceFit fit =
          MinimizeRandomWalkMinusTwoLogLikelihood(y, r, min_ratio, max_ratio);
      // Equal but for the rounding of q / r back from q = (q / r) r.
      const double at_q = RandomWalkMinusTwoLogLikelihood(y, fit.q, r);
      EXPECT_NEAR(fit.minus_two_log_likelihood, at_q, 1e-12 * std::abs(at_q));
      EXPECT_LE(fit.minus_two_log_likelihood, RandomWalkMinusTwoLogLikelihood(y, 0.0, r));
      const double lo = std::log(min_ratio * r), hi = std::log(max_ratio * r);
      for (int i = 0; i <= 400; ++i) {
        const double scanned = std::exp(lo + (hi - lo) * i / 400.0);
        EXPECT_LE(fit.minus_two_log_likelihood,
                  RandomWalkMinusTwoLogLikelihood(y, scanned, r) + slack)
            << "q " << q << " seed " << seed << " scanned " << scanned;
      }
    }
  }
}

TEST(MinimizeRandomWalkMinusTwoLogLikelihood, PutsTheMinimumOfWhiteNoiseAtQZeroOnMostSeeds) {
  // Without a walk the maximum-likelihood q piles up at 0 (Shephard & Harvey 1990): on 659 of the
  // 1000 design records (seeds 5001-6000, N = 300) it was exactly 0. At that rate at least 600 of
  // 1000 fail with probability < 1e-4 (4 binomial sd below the mean); a rate of 1/2 would reach
  // 600 with probability < 1e-9 (6.3 sd above 500).
  const int seeds = 1000;
  int at_zero = 0;
  for (int s = 1; s <= seeds; ++s) {
    const Eigen::VectorXd y = LocalLevel(300, 0.0, 1.0, static_cast<unsigned>(s));
    at_zero += MinimizeRandomWalkMinusTwoLogLikelihood(y, 1.0).q == 0.0 ? 1 : 0;
  }
  EXPECT_GE(at_zero, 600) << "q = 0 on " << at_zero << " of " << seeds;
}

TEST(MinimizeRandomWalkMinusTwoLogLikelihood, FindsTheWalkVarianceOfASimulatedWalk) {
  // q / r = 0.01 over N = 2000: on the design records (seeds 5001-5200) the estimate had mean
  // 0.00996 and sd 0.0020, none at 0 and all within a factor 2 of the truth. The mean of 200
  // estimates must lie within 3 standard errors of the truth; half the truth is 2.5 sd below it
  // (normal tail 0.6 %, expected misses 1.2 of 200), so more than 6 misses have probability
  // < 1e-3.
  const double q = 0.01, r = 1.0;
  const int seeds = 200;
  Eigen::VectorXd q_hat(seeds);
  int outside_factor_2 = 0;
  for (int s = 0; s < seeds; ++s) {
    const WalkVarianceFit fit = MinimizeRandomWalkMinusTwoLogLikelihood(
        LocalLevel(2000, q, r, static_cast<unsigned>(1 + s)), r);
    q_hat[s] = fit.q;
    outside_factor_2 += fit.q > 0.5 * q && fit.q < 2.0 * q ? 0 : 1;
  }
  const double mean = q_hat.mean();
  const double sd = std::sqrt((q_hat.array() - mean).square().sum() / (seeds - 1));
  EXPECT_LT(std::abs(mean - q), 3.0 * sd / std::sqrt(double(seeds)))
      << "mean " << mean << " sd " << sd;
  EXPECT_LE(outside_factor_2, 6);
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
