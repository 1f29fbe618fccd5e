#include "algorithms/model/stochastic_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

#include "algorithms/common/units.h"
#include "algorithms/model/views.h"

namespace fogpipe::model {
namespace {

using namespace units;

StochasticModel Truth(bool with_gm) {
  StochasticModel m;
  m.terms = {Term::kWhite, Term::kQuantization, Term::kBiasInstability, Term::kRateRandomWalk,
             Term::kRateRamp};
  m.n_rad_sqrt_s = DegPerSqrtHourToArw(0.005);
  m.q_rad = ArcsecToQuantization(0.1);
  m.b_rad_s = DegPerHourToBias(0.004);
  m.k_rad_s_sqrt_s = DegPerHourSqrtHourToRrw(0.006);
  if (with_gm) {
    m.terms.push_back(Term::kGaussMarkov);
    m.gm_sigma_rad_s = DegPerHourToBias(0.05);
    m.gm_correlation_time_s = 120.0;
  }
  return m;
}

TEST(StochasticFit, RecoversTheTermsFromTheirExactAllanVariances) {
  const StochasticModel truth = Truth(false);
  std::vector<double> tau, avar, edf;
  for (double t = 0.1; t < 3000; t *= 2) {
    tau.push_back(t);
    avar.push_back(ModelAllanVariance(truth, t));
    edf.push_back(100.0);
  }
  const StochasticFit f = FitStochastic(tau, avar, edf, 10.0, 21600.0, truth.terms, {});
  ASSERT_TRUE(HasResult(f.summary.termination));
  // Noise-free input: only rounding; 1e-6 relative.
  EXPECT_NEAR(f.model.n_rad_sqrt_s / truth.n_rad_sqrt_s, 1.0, 1e-6);
  EXPECT_NEAR(f.model.q_rad / truth.q_rad, 1.0, 1e-6);
  EXPECT_NEAR(f.model.b_rad_s / truth.b_rad_s, 1.0, 1e-6);
  EXPECT_NEAR(f.model.k_rad_s_sqrt_s / truth.k_rad_s_sqrt_s, 1.0, 1e-6);
  EXPECT_LT(f.model.r_rad_s2, 1e-12);
}

TEST(StochasticFit, FindsTheGaussMarkovCorrelationTime) {
  const StochasticModel truth = Truth(true);
  std::vector<double> tau, avar, edf;
  for (double t = 0.1; t < 3000; t *= std::sqrt(2.0)) {
    tau.push_back(t);
    avar.push_back(ModelAllanVariance(truth, t));
    edf.push_back(100.0);
  }
  const StochasticFit f = FitStochastic(tau, avar, edf, 10.0, 21600.0, truth.terms, {});
  // The golden-section search brackets log(Tc) to ~1e-6; amplitudes follow exactly.
  EXPECT_NEAR(f.model.gm_correlation_time_s / 120.0, 1.0, 1e-3);
  EXPECT_NEAR(f.model.gm_sigma_rad_s / truth.gm_sigma_rad_s, 1.0, 1e-3);
}

TEST(StochasticFit, GaussMarkovPsdIntegratesToItsVariance) {
  StochasticModel m;
  m.terms = {Term::kGaussMarkov};
  m.gm_sigma_rad_s = 2.0;
  m.gm_correlation_time_s = 5.0;
  // One-sided Lorentzian 4 s^2 Tc / (1 + (2 pi f Tc)^2) integrates to s^2 over [0, inf).
  double sum = 0;
  const double df = 1e-4;
  for (double f = 0.5 * df; f < 50.0; f += df) sum += ModelOneSidedPsd(m, f, 1e9) * df;
  EXPECT_NEAR(sum, 4.0, 4.0 * 0.003);  // tail beyond 50 Hz: 2/(pi^2 Tc 50) s^2 ~ 0.2 %
}

// White rate noise (N), a rate random walk (K) and a first-order Gauss-Markov rate (sigma, Tc),
// 6 h at 10 Hz, written out here (exact AR(1) discretisation started from its stationary law; the
// random walk's steps K / sqrt(fs)): not fogpipe's simulator.
Eigen::VectorXd NoisePlusGaussMarkov(double n_rad_sqrt_s, double k_rad_s_sqrt_s, double sigma_rad_s,
                                     double tc_s, std::uint64_t seed) {
  const double fs = 10.0;
  const long n = 216000;
  std::mt19937_64 g(seed);
  std::normal_distribution<double> e(0.0, 1.0);
  const double phi = std::exp(-1.0 / (tc_s * fs)),
               innovation = sigma_rad_s * std::sqrt(1 - phi * phi);
  const double white = n_rad_sqrt_s * std::sqrt(fs);  // per-sample sd of white rate noise
  Eigen::VectorXd rate(n);
  double x = sigma_rad_s * e(g), walk = 0;
  for (long i = 0; i < n; ++i) {
    x = phi * x + innovation * e(g);
    walk += k_rad_s_sqrt_s / std::sqrt(fs) * e(g);
    rate[i] = x + walk + white * e(g);
  }
  return rate;
}

TEST(StochasticFit, GaussMarkovUncertaintiesAreCalibratedOverSeeds) {
  // Test seeds 950-989 for each of two correlation times (the design study used `fogpipe simulate`
  // navigation records, seeds 1-40, Tc 30, 300 and 1000 s). Truth: N = 0.003 deg/sqrt(h), K =
  // 0.01 deg/h/sqrt(h), sigma = 0.08 deg/h; the Gauss-Markov bump is well above the other terms'
  // Allan variance at tau = 1.89 Tc, so the term is identified on every seed. The model fitted is
  // white + quantization + bias instability + RRW + ramp + GM, as `compare --add gauss_markov`
  // fits it. Measured on these seeds (and asserted below as a guard, not as the nominal value):
  //   Tc 120 s: interval coverage 33/40; z(sigma) mean -0.72 sd 1.34; z(ln Tc) mean -0.52 sd 1.12
  //   Tc 300 s: interval coverage 39/40; z(sigma) mean -0.78 sd 1.32; z(ln Tc) mean -0.36 sd 0.90
  // and with the standard errors at fixed Tc (before the profile's delta method): z(sigma) sd
  // 1.49 and 2.12.
  //  - The 95 % profile interval of Tc: nominal coverage 95 % (binomial(40, 0.95): mean 38, sd
  //    1.38). It is not met at 120 s (33/40): the cost is a chi-square only if the Allan points
  //    were independent, and neighbouring overlapping points are correlated, so the profile is
  //    too sharp. Asserted: at least 32 of 40, the measured state less 1.
  //  - z = (estimate - truth) / SE of sigma and of ln Tc. A calibrated SE gives sd 1 (its
  //    estimate over 40 seeds has sd ~0.11); the same correlation leaves the SEs ~30 % small.
  //    Asserted: sd <= 1.5, which the fixed-Tc SEs fail at 300 s; and |mean| <= 1: the estimates
  //    are biased low by 0.4-0.8 SE (few averages at the taus where the bump shows), which this
  //    bounds below one SE.
  const double n = DegPerSqrtHourToArw(0.003), k = DegPerHourSqrtHourToRrw(0.01),
               sigma = DegPerHourToBias(0.08);
  const std::vector<Term> terms = {Term::kWhite,           Term::kQuantization,
                                   Term::kBiasInstability, Term::kRateRandomWalk,
                                   Term::kRateRamp,        Term::kGaussMarkov};
  for (const double tc : {120.0, 300.0}) {
    int covered = 0;
    std::vector<double> z_sigma, z_log_tc;
    for (std::uint64_t seed = 950; seed < 990; ++seed) {
      const Eigen::VectorXd rate = NoisePlusGaussMarkov(n, k, sigma, tc, seed);
      const AllanData allan = ResidualAllan(rate, 10.0, ViewOptions());
      const StochasticFit f =
          FitStochastic(allan.tau_s, allan.avar, allan.edf, 10.0, rate.size() / 10.0, terms, {});
      ASSERT_TRUE(HasResult(f.summary.termination)) << f.summary.message;
      const StochasticModel& m = f.model;
      covered += m.gm_correlation_time_low_s <= tc && tc <= m.gm_correlation_time_high_s;
      ASSERT_GT(m.gm_sigma_se, 0.0);
      ASSERT_GT(m.gm_correlation_time_se, 0.0);
      z_sigma.push_back((m.gm_sigma_rad_s - sigma) / m.gm_sigma_se);
      z_log_tc.push_back(std::log(m.gm_correlation_time_s / tc) /
                         (m.gm_correlation_time_se / m.gm_correlation_time_s));
    }
    auto mean_sd = [](const std::vector<double>& z) {
      double mean = 0, var = 0;
      for (double v : z) mean += v / z.size();
      for (double v : z) var += (v - mean) * (v - mean) / (z.size() - 1);
      return std::make_pair(mean, std::sqrt(var));
    };
    const auto [ms, ss] = mean_sd(z_sigma);
    const auto [mt, st] = mean_sd(z_log_tc);
    std::printf(
        "Tc %.0f s: interval coverage %d/40; z(sigma) mean %.2f sd %.2f; z(ln Tc) mean %.2f sd "
        "%.2f\n",
        tc, covered, ms, ss, mt, st);
    EXPECT_GE(covered, 32) << "Tc " << tc;
    EXPECT_LE(std::abs(ms), 1.0) << "Tc " << tc;
    EXPECT_LE(ss, 1.5) << "Tc " << tc;
    EXPECT_LE(std::abs(mt), 1.0) << "Tc " << tc;
    EXPECT_LE(st, 1.5) << "Tc " << tc;
  }
}

}  // namespace
}  // namespace fogpipe::model
