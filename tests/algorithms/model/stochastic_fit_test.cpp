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
#include "algorithms/simulation/random.h"

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
// random walk's steps K / sqrt(fs)): not fogpipe's simulator (only its random numbers, which
// are the same on every standard library).
Eigen::VectorXd NoisePlusGaussMarkov(double n_rad_sqrt_s, double k_rad_s_sqrt_s, double sigma_rad_s,
                                     double tc_s, std::uint64_t seed) {
  const double fs = 10.0;
  const long n = 216000;
  simulation::RandomSource random(seed);
  const double phi = std::exp(-1.0 / (tc_s * fs)),
               innovation = sigma_rad_s * std::sqrt(1 - phi * phi);
  const double white = n_rad_sqrt_s * std::sqrt(fs);  // per-sample sd of white rate noise
  Eigen::VectorXd rate(n);
  double x = sigma_rad_s * random.Normal(), walk = 0;
  for (long i = 0; i < n; ++i) {
    x = phi * x + innovation * random.Normal();
    walk += k_rad_s_sqrt_s / std::sqrt(fs) * random.Normal();
    rate[i] = x + walk + white * random.Normal();
  }
  return rate;
}

TEST(StochasticFit, GaussMarkovUncertaintiesAreCalibratedOverSeeds) {
  // Test seeds 950-989 for each of two correlation times (the design study used `fogpipe simulate`
  // navigation records, seeds 1-40, Tc 30, 300 and 1000 s). Truth: N = 0.003 deg/sqrt(h), K =
  // 0.01 deg/h/sqrt(h), sigma = 0.08 deg/h; the Gauss-Markov bump is well above the other terms'
  // Allan variance at tau = 1.89 Tc, so the term is identified on every seed. The model fitted is
  // white + quantization + bias instability + RRW + ramp + GM, as `compare --add gauss_markov`
  // fits it. Bounds for calibrated uncertainties over 40 seeds:
  //  - the 95 % profile interval of Tc holds the truth on at least 34: the count is binomial(40,
  //    0.95), mean 38, sd 1.38, P(<= 33) = 0.3 %;
  //  - z = (estimate - truth) / SE of sigma and of ln Tc has sd <= 1.33 (a calibrated SE gives
  //    1; the sample sd of 40 has sd ~0.11, and 1.33 is 3 of those) and |mean| <= 0.6 (3 sd /
  //    sqrt(40) at sd 1.25).
  // Measured on these seeds: Tc 120 s: 38/40, z(sigma) mean 0.18 sd 1.06, z(ln Tc) 0.10 / 0.86;
  // Tc 300 s: 40/40, -0.05 / 0.94, -0.12 / 0.72. Over 200 seeds (950-1149) the same code gives
  // 189/200 and 196/200, z(sigma) sd 1.20 and 1.25, z(ln Tc) sd 0.99 and 0.89: sigma's SE is still
  // ~20 % small (the Allan points are weighed as independent), which 40 seeds cannot resolve.
  // With sigma's SE at fixed Tc (before the delta method on the profile) these seeds give z(sigma)
  // sd 1.32 and 1.94: the second fails.
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
    EXPECT_GE(covered, 34) << "Tc " << tc;
    EXPECT_LE(std::abs(ms), 0.6) << "Tc " << tc;
    EXPECT_LE(ss, 1.33) << "Tc " << tc;
    EXPECT_LE(std::abs(mt), 0.6) << "Tc " << tc;
    EXPECT_LE(st, 1.33) << "Tc " << tc;
  }
}

}  // namespace
}  // namespace fogpipe::model
