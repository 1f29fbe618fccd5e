#include "algorithms/model/deterministic_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace fogpipe::model {
namespace {

struct Synthetic {
  Eigen::VectorXd rate, temp;
  double fs = 5.0;
};

// 2 h at 5 Hz: bias 1e-3, temperature 2e-4/degC on a 3000 s sine of +-4 degC, a Shupe term
// 0.05 per degC/s, a warm-up 3e-3 exp(-t/400), a step 1.5e-3 at 4000 s and a line 1e-3 at 0.02 Hz,
// all in rad/s, plus white noise 2e-4 rad/s per sample (seeded Box-Muller).
Synthetic Make(double noise) {
  Synthetic s;
  const long n = static_cast<long>(7200 * s.fs);
  s.rate.resize(n);
  s.temp.resize(n);
  std::mt19937_64 g(7);
  auto normal = [&]() {
    const double u1 = (static_cast<double>(g() >> 11) + 0.5) * 0x1.0p-53;
    const double u2 = static_cast<double>(g() >> 11) * 0x1.0p-53;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * M_PI * u2);
  };
  const double w = 2 * M_PI / 3000.0;
  for (long i = 0; i < n; ++i) {
    const double t = i / s.fs;
    s.temp[i] = 25.0 + 4.0 * std::sin(w * t);
    const double dtdt = 4.0 * w * std::cos(w * t);
    s.rate[i] = 1e-3 + 2e-4 * (s.temp[i] - 25.0) + 0.05 * dtdt + 3e-3 * std::exp(-t / 400.0) +
                (t >= 4000.0 ? 1.5e-3 : 0.0) + 1e-3 * std::sin(2 * M_PI * 0.02 * t + 0.3) +
                noise * normal();
  }
  return s;
}

const DeterministicComponent* Find(const DeterministicFit& f, Term t) {
  for (const auto& c : f.model.components)
    if (c.term == t) return &c;
  return nullptr;
}

TEST(DeterministicFit, RecoversEveryEffectJointly) {
  const Synthetic s = Make(2e-4);
  const std::vector<Term> terms = {Term::kTemperature, Term::kTemperatureRate, Term::kWarmup,
                                   Term::kBiasStep, Term::kSinusoid};
  const DeterministicFit f = FitDeterministic(s.rate, s.fs, &s.temp, terms, {});
  ASSERT_EQ(f.summary.termination, Termination::kSuccess) << f.summary.message;
  // White noise 2e-4 over 36000 samples: amplitude SEs are ~1e-6..1e-5 rad/s, so 2 % of each
  // effect is >= 5 SE; the 120 s local slope biases dT/dt of a 3000 s sine by ~x^2/10 = 0.2 %
  // (x = pi 120 / 3000).
  // The bias is defined at T_ref = mean(T) (2.4 cycles: mean(T) != 25 degC).
  EXPECT_NEAR(f.model.temperature_ref_degc, s.temp.mean(), 1e-12);
  EXPECT_NEAR(f.model.bias_rad_s, 1e-3 + 2e-4 * (s.temp.mean() - 25.0), 2e-5);
  EXPECT_NEAR(Find(f, Term::kTemperature)->coefficients[0], 2e-4, 0.02 * 2e-4);
  EXPECT_NEAR(Find(f, Term::kTemperatureRate)->coefficients[0], 0.05, 0.02 * 0.05);
  EXPECT_NEAR(Find(f, Term::kWarmup)->coefficients[0], 3e-3, 0.05 * 3e-3);
  EXPECT_NEAR(Find(f, Term::kWarmup)->nonlinear, 400.0, 0.05 * 400.0);
  EXPECT_NEAR(Find(f, Term::kBiasStep)->coefficients[0], 1.5e-3, 0.02 * 1.5e-3);
  EXPECT_NEAR(Find(f, Term::kBiasStep)->nonlinear, 4000.0, 2.0);  // a few samples
  const auto* sin = Find(f, Term::kSinusoid);
  EXPECT_NEAR(sin->nonlinear, 0.02, 1e-5);
  EXPECT_NEAR(std::hypot(sin->coefficients[0], sin->coefficients[1]), 1e-3, 0.02 * 1e-3);
  // The residual is the white noise: its rms is 2e-4 within 2 %.
  EXPECT_NEAR(std::sqrt(f.rss / s.rate.size()), 2e-4, 4e-6);
}

TEST(DeterministicFit, StandardErrorsCoverTheEstimationError) {
  const Synthetic s = Make(2e-4);
  const DeterministicFit f = FitDeterministic(s.rate, s.fs, &s.temp, {Term::kTemperature}, {});
  // Other effects are unmodelled here, so the residual is coloured: the batch-means sandwich
  // must widen the standard error beyond OLS rather than claim precision it does not have.
  const auto* c = Find(f, Term::kTemperature);
  EXPECT_GT(c->coefficients_se[0], 0.0);
  EXPECT_GT(f.long_run_variance_ratio, 1.0);
}

TEST(DeterministicFit, ThermalTermsWithoutTemperatureAreInsufficientData) {
  const Synthetic s = Make(2e-4);
  const DeterministicFit f = FitDeterministic(s.rate, s.fs, nullptr, {Term::kTemperature}, {});
  EXPECT_EQ(f.summary.termination, Termination::kInsufficientData);
}

TEST(DeterministicFit, InvalidOptionsAreReported) {
  DeterministicOptions o;
  o.step_margin_fraction = 0.7;
  std::string err;
  EXPECT_FALSE(o.IsValid(&err));
  const Synthetic s = Make(2e-4);
  EXPECT_EQ(FitDeterministic(s.rate, s.fs, nullptr, {}, o).summary.termination,
            Termination::kInvalidOptions);
}

}  // namespace
}  // namespace fogpipe::model
