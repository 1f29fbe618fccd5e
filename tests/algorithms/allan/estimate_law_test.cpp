// Tests of algorithms/allan/estimate_law.{h,cpp}: the saddlepoint distribution of a weighted sum of
// chi-square(1) variables against the exact chi-square law and against simulation, and the
// sampled covariance's weights against the full eigenvalue problem and Greenhall's EDF.
#include "algorithms/allan/estimate_law.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "algorithms/allan/avar_covariance.h"
#include "algorithms/allan/deviation.h"
#include "algorithms/allan/edf.h"
#include "algorithms/common/chi_square.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::allan {
namespace {

constexpr double kLow = 0.5 * (1.0 - 0.683), kHigh = 1.0 - kLow;

// A 68.3 % interval's coverage moves by the difference of its two tail errors. 0.005 on that
// probability is a quarter of the standard error of a 600-realisation coverage estimate (0.019).
// Each tail alone may err by 0.01: the Lugannani-Rice approximation's error for a dominant
// chi-square(1) term is 0.012 (Kuonen 1999), shared by both tails of one interval.
constexpr double kIntervalTolerance = 0.005, kTailTolerance = 0.01;

// Equal weights are a scaled chi-square: sum_{j<nu} chi2_1 / nu = chi2_nu / nu, known exactly;
// with two or more the saddlepoint is within 0.005 in each tail, one weight is exact.
TEST(EstimateLaw, EqualWeightsGiveTheChiSquareLaw) {
  for (int nu : {1, 2, 3, 4, 10, 50}) {
    const std::vector<double> mu(static_cast<size_t>(nu), 1.0 / nu);
    for (double p : {kLow, 0.5, kHigh}) {
      const double x = stats::ChiSquareQuantile(p, nu) / nu;
      if (nu == 1)
        EXPECT_NEAR(WeightedChiSquareQuantile(mu, p), x, 1e-9 * x);
      else
        EXPECT_NEAR(WeightedChiSquareCdf(mu, x), p, kIntervalTolerance)
            << "nu " << nu << " p " << p;
    }
  }
}

// Unequal weights against 400 000 simulated sums (three fixed vectors and the law of random-walk
// FM with 4 averages, the most skewed one fogpipe uses): the probability of the saddlepoint's
// 68.3 % interval is within kIntervalTolerance, and each tail within kTailTolerance, plus 4
// binomial standard errors.
TEST(EstimateLaw, QuantilesOfUnequalWeightsMatchSimulatedSums) {
  std::vector<std::vector<double>> cases = {
      {0.5, 0.3, 0.15, 0.05}, {0.7, 0.2, 0.1}, {0.4, 0.4, 0.1, 0.05, 0.05}};
  const long long n = 4096, m = 1024;
  cases.push_back(OverlappingLawWeights(2, {0.0, 0.0, 0.0, 1.0}, m,
                                        DifferenceCount(Deviation::kOverlappingAllan, n, m)));
  simulation::RandomSource rng(424242);
  const int draws = 400000;
  for (const std::vector<double>& mu : cases) {
    ASSERT_FALSE(mu.empty());
    std::vector<double> sums(draws);
    for (double& s : sums) {
      s = 0.0;
      for (double w : mu) {
        const double z = rng.Normal();
        s += w * z * z;
      }
    }
    const double q_low = WeightedChiSquareQuantile(mu, kLow);
    const double q_high = WeightedChiSquareQuantile(mu, kHigh);
    const auto below = [&](double q) {
      return static_cast<double>(
                 std::count_if(sums.begin(), sums.end(), [&](double s) { return s <= q; })) /
             draws;
    };
    const double f_low = below(q_low), f_high = below(q_high);
    const double se = std::sqrt(0.683 * 0.317 / draws), se_tail = std::sqrt(kLow * kHigh / draws);
    EXPECT_NEAR(f_high - f_low, kHigh - kLow, kIntervalTolerance + 4.0 * se) << mu[0];
    EXPECT_NEAR(f_low, kLow, kTailTolerance + 4.0 * se_tail) << mu[0];
    EXPECT_NEAR(f_high, kHigh, kTailTolerance + 4.0 * se_tail) << mu[0];
  }
}

// The weights from K = 128 sampled starts against the eigenvalues of the full M x M covariance of
// the second (OADEV) and third (OHDEV) differences (white FM and random-walk FM, 1024 samples,
// 4-13 averages): the 15.85 %
// and 84.15 % quantiles agree to 5e-3 (relative; q f(q) < 0.6 at these quantiles, so a tail
// probability moves by under 0.003, within kIntervalTolerance), and 1 / sum mu^2 is Greenhall's EDF
// for sampled phase within the 3 % of his asymptotic forms (edf.h).
TEST(EstimateLaw, SampledCovarianceGivesTheFullEigenvaluesQuantiles) {
  const long long n = 1024;
  for (int d : {2, 3})
    for (int alpha : {0, -2}) {
      std::array<double, 4> theta{};
      theta[static_cast<size_t>(1 - alpha)] = 1.0;
      for (long long m : {80LL, 128LL, 256LL}) {
        const long long count = DifferenceCount(
            d == 2 ? Deviation::kOverlappingAllan : Deviation::kOverlappingHadamard, n, m);
        Eigen::MatrixXd cov(count, count);
        for (long long i = 0; i < count; ++i)
          for (long long j = 0; j < count; ++j) {
            const std::array<double, 4> c =
                DifferenceCovariance(d, m, static_cast<double>(std::abs(i - j)));
            cov(i, j) = theta[1] * c[1] + theta[3] * c[3];
          }
        const Eigen::VectorXd ev =
            Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(cov, Eigen::EigenvaluesOnly)
                .eigenvalues();
        std::vector<double> full;
        for (Eigen::Index j = 0; j < ev.size(); ++j)
          if (ev[j] > 1e-12 * ev.maxCoeff()) full.push_back(ev[j]);
        double sum = 0.0;
        for (double v : full) sum += v;
        for (double& v : full) v /= sum;
        const std::vector<double> sampled = OverlappingLawWeights(d, theta, m, count);
        ASSERT_FALSE(sampled.empty());
        for (double p : {kLow, kHigh})
          EXPECT_NEAR(WeightedChiSquareQuantile(sampled, p) / WeightedChiSquareQuantile(full, p),
                      1.0, 5e-3)
              << "d " << d << " alpha " << alpha << " m " << m << " p " << p;
        double sum_sq = 0.0;
        for (double v : sampled) sum_sq += v * v;
        EXPECT_NEAR((1.0 / sum_sq) / GreenhallEdf(alpha, d, m, n + 1, true, true), 1.0, 0.03)
            << "d " << d << " alpha " << alpha << " m " << m;
      }
    }
}

// With 4 averages the law's interval is narrower than chi-square's with the same EDF: the
// over-wide intervals it replaces (file comment of estimate_law.h).
TEST(EstimateLaw, FewAveragesGiveANarrowerIntervalThanChiSquare) {
  const long long n = 4096, m = 1024;
  const std::vector<double> mu = OverlappingLawWeights(
      2, {0.0, 1.0, 0.0, 0.0}, m, DifferenceCount(Deviation::kOverlappingAllan, n, m));
  double sum_sq = 0.0;
  for (double v : mu) sum_sq += v * v;
  const double edf = 1.0 / sum_sq;
  double low = 0.0, high = 0.0;
  LawBounds(1.0, mu, 0.683, &low, &high);
  const double chi_low = std::sqrt(edf / stats::ChiSquareQuantile(kHigh, edf));
  const double chi_high = std::sqrt(edf / stats::ChiSquareQuantile(kLow, edf));
  EXPECT_GT(low, chi_low);
  EXPECT_LT(high, chi_high);
}

}  // namespace
}  // namespace fogpipe::allan
