#include "algorithms/model/stochastic_fit.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/units.h"

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

}  // namespace
}  // namespace fogpipe::model
