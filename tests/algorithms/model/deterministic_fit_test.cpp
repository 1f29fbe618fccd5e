#include "algorithms/model/deterministic_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

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
  const std::vector<ModelTerm> terms = {Term::kTemperature, Term::kTemperatureRate, Term::kWarmup,
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

// Aux terms on a channel "v" (volts): 2 h at 5 Hz, v = 12 + 0.5 sin(2 pi t / 1700 s) + 0.3
// sin(2 pi t / 610 s), white noise 2e-4 rad/s. A bias 3e-4 (v - mean) + 4e-4 (v - mean)^2 is
// recovered with order 2 (BIC), within 3 standard errors; a linear bias gets order 1; a bias in
// dv/dt is recovered by aux_rate. The same model evaluates to the fitted effect (compensation).
struct AuxSynthetic {
  Eigen::VectorXd v, dvdt, noise;
  double fs = 5.0;
};

AuxSynthetic MakeAux() {
  AuxSynthetic s;
  const long n = static_cast<long>(7200 * s.fs);
  s.v.resize(n);
  s.dvdt.resize(n);
  s.noise.resize(n);
  std::mt19937_64 g(11);
  std::normal_distribution<double> e(0.0, 2e-4);
  const double w1 = 2 * M_PI / 1700.0, w2 = 2 * M_PI / 610.0;
  for (long i = 0; i < n; ++i) {
    const double t = i / s.fs;
    s.v[i] = 12.0 + 0.5 * std::sin(w1 * t) + 0.3 * std::sin(w2 * t);
    s.dvdt[i] = 0.5 * w1 * std::cos(w1 * t) + 0.3 * w2 * std::cos(w2 * t);
    s.noise[i] = e(g);
  }
  return s;
}

TEST(DeterministicFit, AnAuxPolynomialGetsItsOrderByBicAndItsCoefficients) {
  const AuxSynthetic s = MakeAux();
  const Eigen::ArrayXd x = s.v.array() - s.v.mean();
  const ModelTerm aux = ModelTerm::Aux(AuxForm::kValue, "v");
  const std::vector<AuxSeries> channels = {{"v", "V", &s.v}};
  for (int order : {1, 2}) {
    SCOPED_TRACE(order);
    const double c1 = 3e-4, c2 = order == 2 ? 4e-4 : 0.0;
    const Eigen::VectorXd rate = (1e-3 + c1 * x + c2 * x.square()).matrix() + s.noise;
    const DeterministicFit f = FitDeterministic(rate, s.fs, channels, {aux}, {});
    ASSERT_TRUE(HasResult(f.summary.termination)) << f.summary.message;
    ASSERT_EQ(f.model.components.size(), 1u);
    const DeterministicComponent& c = f.model.components[0];
    EXPECT_EQ(c.units, "V");
    EXPECT_NEAR(c.reference, s.v.mean(), 1e-12);
    ASSERT_EQ(c.coefficients.size(), static_cast<size_t>(order));
    EXPECT_NEAR(c.coefficients[0], c1, 3 * c.coefficients_se[0]);
    if (order == 2) {
      EXPECT_NEAR(c.coefficients[1], c2, 3 * c.coefficients_se[1]);
    }
    const std::vector<AuxSeries> none;
    const Eigen::VectorXd effect =
        EvaluateDeterministic(f.model, rate.size(), s.fs, channels, false);
    EXPECT_NEAR((rate - effect - f.residual).array().mean(), f.model.bias_rad_s, 1e-12);
    EXPECT_EQ(EvaluateDeterministic(f.model, rate.size(), s.fs, none, false).norm(), 0.0);
  }
}

TEST(DeterministicFit, AnAuxRateTermFollowsTheSmoothedDerivative) {
  const AuxSynthetic s = MakeAux();
  // The term's regressor is the smoothed derivative (a local least-squares slope over 120 s),
  // which attenuates a sine of period P by 3 (sin u - u cos u) / u^3, u = pi 120 s / P (3.8 % at
  // 610 s): the effect is made with it, and its match to the true derivative checked apart.
  const Eigen::VectorXd smoothed = SmoothedDerivative(s.v, s.fs, 120.0);
  const Eigen::VectorXd rate = (1e-3 + 2.0 * smoothed.array()).matrix() + s.noise;
  const double u = M_PI * 120.0 / 610.0;
  const double attenuation = 3 * (std::sin(u) - u * std::cos(u)) / (u * u * u);
  const Eigen::ArrayXd inner = s.dvdt.array().segment(600, s.dvdt.size() - 1200);
  EXPECT_LT((smoothed.array().segment(600, s.dvdt.size() - 1200) - inner).abs().maxCoeff(),
            1.1 * (1 - attenuation) * 0.3 * 2 * M_PI / 610.0);
  const std::vector<AuxSeries> channels = {{"v", "V", &s.v}};
  const DeterministicFit f =
      FitDeterministic(rate, s.fs, channels, {ModelTerm::Aux(AuxForm::kRate, "v")}, {});
  ASSERT_TRUE(HasResult(f.summary.termination)) << f.summary.message;
  const DeterministicComponent& c = f.model.components[0];
  ASSERT_EQ(c.coefficients.size(), 1u);
  EXPECT_NEAR(c.coefficients[0], 2.0, 3 * c.coefficients_se[0]);
  EXPECT_LT(c.coefficients_se[0], 0.05);
}

TEST(DeterministicFit, AnAuxTermWithoutItsChannelOrBesideItsLinearTwinIsRefused) {
  const AuxSynthetic s = MakeAux();
  const Eigen::VectorXd rate = s.noise;
  const std::vector<AuxSeries> channels = {{"v", "V", &s.v}};
  EXPECT_EQ(FitDeterministic(rate, s.fs, channels, {ModelTerm::Aux(AuxForm::kValue, "w")}, {})
                .summary.termination,
            Termination::kInsufficientData);
  const std::vector<AuxSeries> temperature = {{"temperature", "degC", &s.v}};
  const DeterministicFit both =
      FitDeterministic(rate, s.fs, temperature,
                       {Term::kTemperature, ModelTerm::Aux(AuxForm::kValue, "temperature")}, {});
  EXPECT_EQ(both.summary.termination, Termination::kInsufficientData);
}

// Rising against falling (aux_hysteresis): the channel v of MakeAux with 1 mV white sensor noise,
// and a bias +-c with the sign of the true dv/dt. The regressor (a switch on the smoothed
// derivative with a dead band) may differ from the true sign only near the turning points, where
// the 120 s slope lags and the band holds the state; there the least-squares coefficient is c
// times the regression slope of the true sign on the state, cov(sign, state) / var(state).
TEST(DeterministicFit, AnAuxHysteresisTermFollowsTheDirectionOfTheChannel) {
  AuxSynthetic s = MakeAux();
  std::mt19937_64 g(12);
  std::normal_distribution<double> sensor(0.0, 1e-3);
  for (long i = 0; i < s.v.size(); ++i) s.v[i] += sensor(g);
  const Eigen::ArrayXd truth = s.dvdt.array().sign();
  const Eigen::VectorXd state = HysteresisState(SmoothedDerivative(s.v, s.fs, 120.0),
                                                HysteresisDeadBand(s.v, s.fs, 120.0), s.fs, 120.0);
  EXPECT_GT((state.array() == truth).cast<double>().mean(), 0.97);
  const double c = 5e-4;
  const Eigen::VectorXd rate = (1e-3 + c * truth).matrix() + s.noise;
  const std::vector<AuxSeries> channels = {{"v", "V", &s.v}};
  const ModelTerm term = ModelTerm::Aux(AuxForm::kHysteresis, "v");
  const DeterministicFit f = FitDeterministic(rate, s.fs, channels, {term}, {});
  ASSERT_TRUE(HasResult(f.summary.termination)) << f.summary.message;
  const DeterministicComponent& fitted = f.model.components[0];
  ASSERT_EQ(fitted.coefficients.size(), 1u);
  EXPECT_NEAR(fitted.reference, HysteresisDeadBand(s.v, s.fs, 120.0), 0.0);
  const Eigen::ArrayXd centred_state = state.array() - state.mean();
  const double slope =
      (centred_state * (truth - truth.mean())).sum() / centred_state.square().sum();
  EXPECT_NEAR(fitted.coefficients[0], c * slope, 3 * fitted.coefficients_se[0]);
  EXPECT_LT(fitted.coefficients_se[0], 0.05 * c);
  // The model evaluates to the fitted effect (compensation), with the fitted dead band.
  const Eigen::VectorXd effect = EvaluateDeterministic(f.model, rate.size(), s.fs, channels, false);
  EXPECT_LT((effect - fitted.coefficients[0] * state).cwiseAbs().maxCoeff(), 1e-15);
}

// The dead band is sqrt(2 ln n) standard deviations of the smoothed derivative of the sensor
// noise: on white noise alone (24 h at 1 Hz, a 121-sample window: ~700 independent slopes, so the
// sample sd is within 2.7 % of its expectation at 1 sd) the band over the derivative's sd is
// sqrt(2 ln 86400) = 4.77 within 10 %; and a flat channel never switches between rising and
// falling (an exit of the band on both sides), on any of 20 seeds. With a band of 4 sd instead, 2
// of these 20 seeds switch once: the slope of a moving window is a rough process, whose maximum
// over 86400 samples is near the universal threshold, not near the 4 sd of ~700 independent ones.
TEST(DeterministicFit, AFlatNoisyChannelDoesNotChatterTheHysteresisSwitch) {
  // Seeds 101-120: the band's size was chosen on seeds 1-20 (a fixed 4 sd switched on 2 of them,
  // the universal threshold on none). Bound: a switch needs an exit on each side; for n values
  // the universal threshold is exceeded with probability about 1 / sqrt(pi ln n) = 0.17 (n =
  // 86400, independent values; the window's correlation makes it rarer), so p(switch) <= 0.17^2
  // = 0.03 per record, and P(3 or more of 20 switch | p = 0.03) = 2.1 %: at most 2 are allowed.
  const double fs = 1.0;
  const long n = 86400;
  int chattering = 0;
  for (int seed = 101; seed <= 120; ++seed) {
    std::mt19937_64 g(seed);
    std::normal_distribution<double> sensor(0.0, 0.01);
    Eigen::VectorXd flat(n);
    for (long i = 0; i < n; ++i) flat[i] = 20.0 + sensor(g);
    const Eigen::VectorXd derivative = SmoothedDerivative(flat, fs, 120.0);
    const double band = HysteresisDeadBand(flat, fs, 120.0);
    if (seed == 101) {
      const Eigen::ArrayXd inner = derivative.segment(60, n - 120).array();
      const double sd = std::sqrt((inner - inner.mean()).square().mean());
      const double universal = std::sqrt(2 * std::log(static_cast<double>(n)));
      EXPECT_NEAR(band / sd, universal, 0.1 * universal);
    }
    const Eigen::VectorXd state = HysteresisState(derivative, band, fs, 120.0);
    int switches = 0;
    for (long i = 1; i < n; ++i) switches += state[i] * state[i - 1] < 0;
    chattering += switches > 0;
  }
  EXPECT_LE(chattering, 2);
  // A channel that never leaves the band has no direction, and one that only rises (a warm-up)
  // gives the bias column itself: the term is refused for both.
  Eigen::VectorXd rising(n);
  for (long i = 0; i < n; ++i) rising[i] = 20.0 + 1e-4 * static_cast<double>(i);
  const Eigen::VectorXd constant = Eigen::VectorXd::Constant(n, 20.0),
                        rate = Eigen::VectorXd::Zero(n);
  for (const Eigen::VectorXd* channel : std::vector<const Eigen::VectorXd*>{&constant, &rising}) {
    const std::vector<AuxSeries> channels = {{"v", "V", channel}};
    EXPECT_EQ(FitDeterministic(rate, fs, channels, {ModelTerm::Aux(AuxForm::kHysteresis, "v")}, {})
                  .summary.termination,
              Termination::kInsufficientData);
  }
}

TEST(DeterministicFit, TheHysteresisStateHoldsInsideTheDeadBand) {
  Eigen::VectorXd d(9);
  d << -1.5, 0.2, 2.0, 0.5, -0.5, -2.0, 0.9, 1.5, 0.0;
  Eigen::VectorXd expected(9);
  // A 2 s window at 1 Hz: a slope over 3 samples inside, over 2 at the ends, whose noise gain
  // sqrt(12 / (2 x 3)) is twice sqrt(12 / (3 x 8)): the band is 1 inside and 2 at the ends, so
  // -1.5 at the first sample is no exit. Before the first exit (at index 2, rising) the state is
  // that exit's.
  expected << 1, 1, 1, 1, 1, -1, -1, 1, 1;
  EXPECT_EQ(HysteresisState(d, 1.0, 1.0, 2.0), expected);
  EXPECT_EQ(HysteresisState(d, 3.0, 1.0, 2.0), Eigen::VectorXd::Zero(9));
}

// A line whose amplitude follows a channel (aux_am): (a0 + a1 (v - mean v)) sin(2 pi f t + phi) in
// white noise of sd sigma, on MakeAux's channel v. Least squares on the columns cos, sin,
// x cos, x sin (x = v - mean v) at the fitted f; in white noise each amplitude has the variance
// sigma^2 / sum(column^2), i.e. sigma^2 / (n / 2) for the carrier and sigma^2 / (n var(x) / 2) for
// the modulation.
struct AmSynthetic {
  AuxSynthetic aux;
  Eigen::VectorXd rate;
  double f = 0.37, a0 = 2e-4, a1 = 3e-4, phi = 0.7, sigma = 2e-4;
};

AmSynthetic MakeAm(std::uint64_t seed) {
  AmSynthetic s;
  s.aux = MakeAux();
  const long n = s.aux.v.size();
  std::mt19937_64 g(seed);
  std::normal_distribution<double> e(0.0, s.sigma);
  const double mean = s.aux.v.mean();
  s.rate.resize(n);
  for (long i = 0; i < n; ++i)
    s.rate[i] =
        1e-3 +
        (s.a0 + s.a1 * (s.aux.v[i] - mean)) * std::sin(2 * M_PI * s.f * i / s.aux.fs + s.phi) +
        e(g);
  return s;
}

TEST(DeterministicFit, AnAmLineGetsItsFrequencyCarrierAndModulation) {
  const AmSynthetic s = MakeAm(21);
  const std::vector<AuxSeries> channels = {{"v", "V", &s.aux.v}};
  const ModelTerm term = ModelTerm::Aux(AuxForm::kAm, "v");
  const DeterministicFit f = FitDeterministic(s.rate, s.aux.fs, channels, {term}, {});
  ASSERT_TRUE(HasResult(f.summary.termination)) << f.summary.message;
  ASSERT_EQ(f.model.components.size(), 1u);
  const DeterministicComponent& c = f.model.components[0];
  ASSERT_EQ(c.coefficients.size(), 4u);
  ASSERT_EQ(c.coefficients_covariance.size(), 16u);
  EXPECT_NEAR(c.reference, s.aux.v.mean(), 1e-12);
  EXPECT_NEAR(c.nonlinear, s.f, 3 * c.nonlinear_se);
  // (a0 + a1 x) sin(w t + phi) = (a0 + a1 x) (sin phi cos w t + cos phi sin w t).
  const double truth[4] = {s.a0 * std::sin(s.phi), s.a0 * std::cos(s.phi), s.a1 * std::sin(s.phi),
                           s.a1 * std::cos(s.phi)};
  const double n = static_cast<double>(s.rate.size());
  const Eigen::ArrayXd x = s.aux.v.array() - s.aux.v.mean();
  const double white_se[4] = {s.sigma / std::sqrt(n / 2), s.sigma / std::sqrt(n / 2),
                              s.sigma / std::sqrt(x.square().sum() / 2),
                              s.sigma / std::sqrt(x.square().sum() / 2)};
  for (int j = 0; j < 4; ++j) {
    SCOPED_TRACE(j);
    EXPECT_NEAR(c.coefficients[j], truth[j], 3 * c.coefficients_se[j]);
    // The batch-means sandwich over 32 blocks estimates a variance with ~31 degrees of freedom
    // (relative sd of the SE ~ 1 / sqrt(62) = 13 %): within 35 % (2.7 sd) of the white-noise SE.
    EXPECT_NEAR(c.coefficients_se[j] / white_se[j], 1.0, 0.35);
    EXPECT_NEAR(c.coefficients_covariance[5 * j], c.coefficients_se[j] * c.coefficients_se[j],
                1e-12 * c.coefficients_se[j] * c.coefficients_se[j] + 1e-300);
  }
  // The model evaluates to the fitted effect (compensation).
  const Eigen::VectorXd effect =
      EvaluateDeterministic(f.model, s.rate.size(), s.aux.fs, channels, false);
  double worst = 0;
  for (long i = 0; i < s.rate.size(); ++i) {
    const double w = 2 * M_PI * c.nonlinear * i / s.aux.fs;
    const double expected = (c.coefficients[0] + c.coefficients[2] * x[i]) * std::cos(w) +
                            (c.coefficients[1] + c.coefficients[3] * x[i]) * std::sin(w);
    worst = std::max(worst, std::abs(effect[i] - expected));
  }
  // Both sides round the phase 2 pi f t (up to 2 pi 0.37 x 7200 = 1.7e4 rad) to ~1.7e4 eps = 4e-12
  // rad, which the envelope (at most a0 + a1 max|x| = 5e-4) turns into ~2e-15: 10x that.
  EXPECT_LT(worst, 2e-14);
}

// Calibration over seeds: the modulation's two amplitudes, (estimate - truth) / SE over 40 noise
// seeds (80 values, nearly independent: the columns are orthogonal) have sd 1 for calibrated
// errors; the sd of 80 standard normal values has sd 1 / sqrt(160) = 0.08, and the SE's own
// scatter (31 degrees of freedom) makes z a t-variate of sd sqrt(31 / 29) = 1.03: the band
// [0.8, 1.3] is 2.5 sd of the sample sd either side. Seeds 501-540 (measured: sd 1.01, mean 0.05).
TEST(DeterministicFit, AnAmLinesStandardErrorsAreCalibratedOverSeeds) {
  std::vector<double> z;
  for (std::uint64_t seed = 501; seed <= 540; ++seed) {
    const AmSynthetic s = MakeAm(seed);
    const std::vector<AuxSeries> channels = {{"v", "V", &s.aux.v}};
    const DeterministicFit f =
        FitDeterministic(s.rate, s.aux.fs, channels, {ModelTerm::Aux(AuxForm::kAm, "v")}, {});
    ASSERT_TRUE(HasResult(f.summary.termination)) << f.summary.message;
    const DeterministicComponent& c = f.model.components[0];
    z.push_back((c.coefficients[2] - s.a1 * std::sin(s.phi)) / c.coefficients_se[2]);
    z.push_back((c.coefficients[3] - s.a1 * std::cos(s.phi)) / c.coefficients_se[3]);
  }
  double mean = 0, square = 0;
  for (double value : z) mean += value / z.size();
  for (double value : z) square += (value - mean) * (value - mean) / (z.size() - 1);
  EXPECT_GT(std::sqrt(square), 0.8);
  EXPECT_LT(std::sqrt(square), 1.3);
  EXPECT_LT(std::abs(mean), 3.0 / std::sqrt(static_cast<double>(z.size())));
}

// A channel that does not move leaves the modulation's columns zero: the term is refused (it
// would be a sinusoid with two coefficients fixed at 0 and standard errors 0).
TEST(DeterministicFit, AnAmLineOnAConstantChannelIsRefused) {
  const AmSynthetic s = MakeAm(3);
  const Eigen::VectorXd flat = Eigen::VectorXd::Constant(s.rate.size(), 12.0);
  const std::vector<AuxSeries> channels = {{"v", "V", &flat}};
  const DeterministicFit f =
      FitDeterministic(s.rate, s.aux.fs, channels, {ModelTerm::Aux(AuxForm::kAm, "v")}, {});
  EXPECT_EQ(f.summary.termination, Termination::kInsufficientData);
  EXPECT_NE(f.summary.message.find("constant"), std::string::npos) << f.summary.message;
}

TEST(ModelCatalog, AuxTermsParseFromTheirChannelNamesAndPrintBack) {
  for (const char* name : {"aux:supply_voltage", "aux_rate:pressure", "aux_hysteresis:temperature",
                           "aux_am:temperature", "temperature", "white"}) {
    const auto term = ParseModelTerm(name);
    ASSERT_TRUE(term.has_value()) << name;
    EXPECT_EQ(ToString(*term), name);
  }
  EXPECT_EQ(ParseModelTerm("aux:supply_voltage")->channel, "supply_voltage");
  EXPECT_TRUE(ParseModelTerm("aux_rate:x")->aux == AuxForm::kRate);
  EXPECT_TRUE(ParseModelTerm("aux_hysteresis:x")->aux == AuxForm::kHysteresis);
  EXPECT_TRUE(ParseModelTerm("aux_am:x")->aux == AuxForm::kAm);
  // The temperature's AM line holds no catalog term; it is a line, as the sinusoid.
  EXPECT_FALSE(ThermalTermWithin(*ParseModelTerm("aux_am:temperature")).has_value());
  EXPECT_TRUE(IsLine(*ParseModelTerm("aux_am:x")));
  EXPECT_FALSE(UsesDerivative(*ParseModelTerm("aux_am:x")));
  // The temperature's hysteresis holds no catalog term (it has no alias).
  EXPECT_FALSE(ThermalTermWithin(*ParseModelTerm("aux_hysteresis:temperature")).has_value());
  EXPECT_FALSE(ParseModelTerm("temperature_hysteresis").has_value());
  for (const char* bad : {"aux", "aux:", "aux:a/b", "aux_rate:", "auxx:v", "Aux:v"})
    EXPECT_FALSE(ParseModelTerm(bad).has_value()) << bad;
  std::vector<ModelTerm> terms;
  std::string error;
  EXPECT_FALSE(ParseTermList("white,aux", &terms, &error));
  EXPECT_NE(error.find("aux:<channel>"), std::string::npos) << error;
  EXPECT_FALSE(ParseTermList("white,aux_hysteresis", &terms, &error));
  EXPECT_NE(error.find("aux_hysteresis:<channel>"), std::string::npos) << error;
  EXPECT_FALSE(ParseTermList("white,aux_am", &terms, &error));
  EXPECT_NE(error.find("aux_am:<channel>"), std::string::npos) << error;
  terms.clear();
  ASSERT_TRUE(ParseTermList("white,aux:v,aux_rate:v", &terms, &error));
  ASSERT_EQ(terms.size(), 3u);
  EXPECT_TRUE(terms[1] != terms[2]);
  EXPECT_TRUE(terms[1] == ModelTerm::Aux(AuxForm::kValue, "v"));
  EXPECT_TRUE(ModelTerm(Term::kTemperature) != ModelTerm::Aux(AuxForm::kValue, "temperature"));
}

}  // namespace
}  // namespace fogpipe::model
