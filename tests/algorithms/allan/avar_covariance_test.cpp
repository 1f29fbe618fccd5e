// Tests of algorithms/allan/avar_covariance.{h,cpp}: the covariance of overlapping Allan-variance
// estimates against three independent references: Greenhall & Riley's EDF algorithm (edf.h, a
// different derivation and code) for the diagonal, the explicit sum over every lag for the
// quadrature, and a Monte Carlo over simulated records (simulated_gyro.h) for the correlations.
#include "algorithms/allan/avar_covariance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "algorithms/allan/allan.h"
#include "algorithms/allan/edf.h"
#include "algorithms/allan/noise_model.h"
#include "tests/algorithms/allan/simulated_gyro.h"

namespace fogpipe::allan {
namespace {

// Model Allan variance of theta = (Q^2, N^2, B^2, K^2) at tau.
double ModelVariance(const std::array<double, 4>& theta, double tau) {
  const Term terms[4] = {Term::kQuantization, Term::kAngleRandomWalk, Term::kBiasInstability,
                         Term::kRateRandomWalk};
  double v = 0.0;
  for (int k = 0; k < 4; ++k) {
    TermParams p;
    p.amplitude = std::sqrt(theta[k]);
    v += TermAllanVariance(terms[k], p, tau);
  }
  return v;
}

// The EDF implied by the diagonal, 2 E[s2]^2 / var(s2), equals Greenhall's for each pure noise
// (alpha = 2 white PM, 0 white FM, -1 flicker FM, -2 random-walk FM), sampled-phase convention.
// Greenhall's large-r branch uses two-coefficient fits (his Table 2) good to about 1 %; 3 %
// allowed.
TEST(AvarCovarianceModel, DiagonalReproducesGreenhallEdfForEachPowerLaw) {
  const long long n = 100000;
  const std::vector<long long> m = {1, 3, 10, 40, 200, 1000, 5000, 20000};
  std::vector<long long> count;
  for (long long mk : m) count.push_back(n + 1 - 2 * mk);
  const double t0 = 0.01;
  const AvarCovarianceModel cov(m, count, t0);
  const int alphas[4] = {2, 0, -1, -2};
  for (int k = 0; k < 4; ++k) {
    std::array<double, 4> theta{};
    theta[k] = 1.0;
    const Eigen::MatrixXd c = cov.Covariance(theta, 0.0);
    for (size_t i = 0; i < m.size(); ++i) {
      const double v = ModelVariance(theta, m[i] * t0);
      const double edf = 2.0 * v * v / c(i, i);
      const double greenhall = GreenhallEdf(alphas[k], 2, m[i], n + 1, true, true);
      EXPECT_NEAR(edf / greenhall, 1.0, 0.03) << "alpha " << alphas[k] << " m " << m[i];
    }
  }
}

// Quadrature (lag ranges > 320) against the explicit sum over every integer lag, for a mixture of
// all four noises and a ramp; their difference is the midpoint/Gauss error, O(1 / m^2).
TEST(AvarCovarianceModel, QuadratureAgreesWithTheExplicitLagSum) {
  const long long n = 30000;
  const double t0 = 0.1;
  const std::array<double, 4> theta = {1e-4, 2e-3, 1e-4, 1e-6};
  const double r2 = 1e-9;
  const std::vector<long long> m = {90, 200, 301, 1000, 1001, 4000};
  std::vector<long long> count;
  for (long long mk : m) count.push_back(n + 1 - 2 * mk);
  const Eigen::MatrixXd c = AvarCovarianceModel(m, count, t0).Covariance(theta, r2);
  for (size_t a = 0; a < m.size(); ++a)
    for (size_t b = a; b < m.size(); ++b) {
      const double ref = AvarCovarianceBySum(m[a], m[b], count[a], count[b], t0, theta, r2);
      EXPECT_NEAR(c(a, b) / ref, 1.0, 2e-3) << "m " << m[a] << ", " << m[b];
    }
}

// The shared model is the constructed one: the same matrix for the rows asked, one object for
// rows asked again (also after other rows were asked in between), another for other rows.
TEST(AvarCovarianceModel, TheSharedModelEqualsTheConstructedOneAndIsReusedForTheSameRows) {
  const std::array<double, 4> theta = {1e-4, 2e-3, 1e-4, 1e-6};
  const std::vector<long long> m = {1, 2, 4, 8, 16}, other_m = {1, 2, 4, 8};
  std::vector<long long> count, other_count;
  for (long long mk : m) count.push_back(4001 - 2 * mk);
  for (long long mk : other_m) other_count.push_back(4001 - 2 * mk);
  const auto shared = SharedAvarCovarianceModel(m, count, 0.01);
  EXPECT_EQ(shared->Covariance(theta, 1e-9),
            AvarCovarianceModel(m, count, 0.01).Covariance(theta, 1e-9));
  const auto other = SharedAvarCovarianceModel(other_m, other_count, 0.01);
  const auto other_period = SharedAvarCovarianceModel(m, count, 0.02);
  EXPECT_NE(other.get(), shared.get());
  EXPECT_NE(other_period.get(), shared.get());
  EXPECT_EQ(other_period->Covariance(theta, 0.0),
            AvarCovarianceModel(m, count, 0.02).Covariance(theta, 0.0));
  EXPECT_EQ(SharedAvarCovarianceModel(m, count, 0.01).get(), shared.get());
}

// The Gauss-Markov term's difference variance at lag 0, c(0) / (2 tau^2), is its IEEE Std 952
// Allan law (noise_model.h, a separate closed form), from Tc far below t0 to far above tau; the two
// are the same function, so only rounding separates them.
TEST(AvarCovarianceModel, GaussMarkovDifferenceVarianceIsTheIeeeAllanLaw) {
  const double t0 = 0.1, sigma2 = 4.0;
  for (const double tc_samples : {0.5, 2.0, 30.0, 1000.0, 1e5})
    for (const long long m : {1LL, 3LL, 10LL, 100LL, 1000LL}) {
      const double tau = m * t0;
      TermParams p;
      p.amplitude = std::sqrt(sigma2);
      p.correlation_time_s = tc_samples * t0;
      const double law = TermAllanVariance(Term::kGaussMarkov, p, tau);
      const double c0 = GaussMarkovDifferenceCovariance(m, m, 0.0, tc_samples) * sigma2 * t0 * t0;
      EXPECT_NEAR(c0 / (2.0 * tau * tau) / law, 1.0, 1e-8) << "Tc " << tc_samples << " m " << m;
    }
}

// Brute force from the rate: the angle over one sample interval, y_k = integral of the rate over
// [k, k + 1) (t0 = 1), has Cov(y_k, y_k') = integral over the unit square of e^{-r |s - s' + d|},
// d = k - k', r = 1 / Tc: 2 (r - 1 + e^{-r}) / r^2 at d = 0 and e^{-r |d|} (e^r + e^{-r} - 2) / r^2
// otherwise. D_i(m) = sum of y over [i + m, i + 2m) less the sum over [i, i + m), so the
// covariance of two differences is a double sum of those, with no phase autocovariance in it.
// Lags run inside, across and beyond the support (where the differences share no interval).
TEST(AvarCovarianceModel, GaussMarkovDifferenceCovarianceIsTheDoubleSumOfTheRateAutocovariance) {
  const std::pair<long long, long long> pairs[] = {{1, 1}, {2, 5}, {7, 3}, {10, 10}};
  for (const double tc_samples : {0.7, 4.0, 50.0, 3000.0}) {
    const double r = 1.0 / tc_samples;
    // In long double, with sinh for e^r + e^-r - 2: both cancel for r << 1.
    const auto interval_cov = [r](long long d) {
      const long double rl = r, half_sinh = std::sinh(rl / 2);
      return static_cast<double>(d == 0 ? 2.0L * (rl + std::expm1(-rl)) / (rl * rl)
                                        : std::exp(-rl * std::abs(d)) * 4.0L * half_sinh *
                                              half_sinh / (rl * rl));
    };
    for (const auto& [ma, mb] : pairs) {
      const double scale = std::abs(GaussMarkovDifferenceCovariance(ma, ma, 0.0, tc_samples));
      for (long long l = -2 * mb - 40; l <= 2 * ma + 40; ++l) {
        double brute = 0.0;
        for (long long k = 0; k < 2 * ma; ++k)
          for (long long k2 = l; k2 < l + 2 * mb; ++k2)
            brute += (k < ma ? -1.0 : 1.0) * (k2 - l < mb ? -1.0 : 1.0) * interval_cov(k - k2);
        EXPECT_NEAR(GaussMarkovDifferenceCovariance(ma, mb, static_cast<double>(l), tc_samples),
                    brute, 1e-9 * scale)
            << "Tc " << tc_samples << " m " << ma << ", " << mb << " lag " << l;
      }
    }
  }
}

// The same with a Gauss-Markov term beside the power laws, at correlation times whose tail beyond
// the support is summed exactly (Tc = 3 t0), integrated on panels (200 t0) and longer than the
// record's lags (20000 t0): the lag sums, the tail and the cross terms against the explicit sum.
// Every pair is held, those of a short difference (m 1 and 5) with a long one included: their
// lags next to the knots are summed exactly (the midpoint rule alone was 7 % off at m 1 against
// 90, where the knots are one sample apart).
TEST(AvarCovarianceModel, QuadratureAgreesWithTheExplicitLagSumWithAGaussMarkovTerm) {
  const long long n = 30000;
  const double t0 = 0.1;
  const std::array<double, 4> theta = {1e-4, 2e-3, 1e-4, 1e-6};
  const double r2 = 1e-9;
  const std::vector<long long> m = {1, 5, 20, 90, 301, 1000, 4000};
  std::vector<long long> count;
  for (long long mk : m) count.push_back(n + 1 - 2 * mk);
  for (const double tc_samples : {3.0, 200.0, 20000.0}) {
    const double tc = tc_samples * t0;
    // sigma^2 such that the term's Allan variance at tau = Tc matches white FM's there.
    TermParams unit;
    unit.amplitude = 1.0;
    unit.correlation_time_s = tc;
    const double gm2 = theta[1] / tc / TermAllanVariance(Term::kGaussMarkov, unit, tc);
    const Eigen::MatrixXd c = AvarCovarianceModel(m, count, t0, tc).Covariance(theta, r2, gm2);
    for (size_t a = 0; a < m.size(); ++a)
      for (size_t b = a; b < m.size(); ++b) {
        const double ref =
            AvarCovarianceBySum(m[a], m[b], count[a], count[b], t0, theta, r2, gm2, tc);
        EXPECT_NEAR(c(a, b) / ref, 1.0, 2e-3) << "Tc " << tc << " m " << m[a] << ", " << m[b];
      }
  }
}

// Monte Carlo: 600 records of 8192 samples with all four noises; the sample covariance of the
// OADEV variances at 6 taus against the model. Correlations: Fisher z has sd 1/sqrt(R - 3), so
// 4 sd (a family of 55 correlations at ~6e-5 each) is tanh-ed back. Variances: var(s2_hat) of
// R draws has relative sd sqrt((kappa - 1) / R) with kurtosis kappa of s2; kappa <= 15 for the
// fewest-average point here (edf ~ 6: 3 + 12 / edf = 5, the rest margin for the flicker tail),
// so sqrt(14 / 600) = 0.15 and 3.5 sd = 0.53; a wrong off-diagonal structure changes the
// correlations by far more than their tolerance.
TEST(AvarCovarianceModel, MatchesTheMonteCarloCovarianceOfSimulatedRecords) {
  const long long n = 8192;
  const double rate_hz = 1.0;
  testing::GyroTruth truth;
  truth.q_rad = 1.0;
  truth.n_rad_sqrt_s = 1.0;
  truth.b_rad_s = 0.1;
  truth.k_rad_s_sqrt_s = 0.01;
  AllanOptions options;
  options.grid = TauGridOptions();
  options.confidence_intervals = false;
  const int records = 600;
  std::vector<Eigen::VectorXd> samples;
  std::vector<long long> m, count;
  for (int r = 0; r < records; ++r) {
    const Eigen::VectorXd rate = testing::SimulateGyro(truth, n, rate_hz, 9100 + r);
    const AllanTable t = ComputeAllan(rate, rate_hz, options).table;
    if (m.empty()) {
      for (size_t i = 0; i < t.size(); ++i)
        if (t.m[i] <= 1024) m.push_back(t.m[i]), count.push_back(t.count[i]);
    }
    Eigen::VectorXd v(static_cast<Eigen::Index>(m.size()));
    for (size_t i = 0; i < m.size(); ++i) v[i] = t.sigma[i] * t.sigma[i];
    samples.push_back(v);
  }
  const Eigen::Index k = static_cast<Eigen::Index>(m.size());
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(k);
  for (const auto& s : samples) mean += s / records;
  Eigen::MatrixXd sample_cov = Eigen::MatrixXd::Zero(k, k);
  for (const auto& s : samples) sample_cov += (s - mean) * (s - mean).transpose() / (records - 1);
  const std::array<double, 4> theta = {1.0, 1.0, 0.01, 1e-4};
  const Eigen::MatrixXd model = AvarCovarianceModel(m, count, 1.0 / rate_hz).Covariance(theta, 0.0);
  const double z_tol = 4.0 / std::sqrt(records - 3.0);
  for (Eigen::Index a = 0; a < k; ++a) {
    EXPECT_NEAR(sample_cov(a, a) / model(a, a), 1.0, 3.5 * std::sqrt(14.0 / records)) << m[a];
    for (Eigen::Index b = a + 1; b < k; ++b) {
      const double rho_model = model(a, b) / std::sqrt(model(a, a) * model(b, b));
      const double rho_mc = sample_cov(a, b) / std::sqrt(sample_cov(a, a) * sample_cov(b, b));
      EXPECT_LT(std::abs(std::atanh(rho_mc) - std::atanh(rho_model)), z_tol)
          << "m " << m[a] << ", " << m[b] << ": model " << rho_model << " MC " << rho_mc;
    }
  }
}

}  // namespace
}  // namespace fogpipe::allan
