#include "algorithms/simulation/noise_generators.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/units.h"

namespace fogpipe::simulation {
namespace {

// Statistical tolerances are 5 standard errors of the estimator, derived per test from the
// distribution of the statistic; the seeds are fixed, so every run gives the same verdict.
constexpr Eigen::Index kSamples = 200000;

double Variance(const Eigen::VectorXd& x) { return (x.array() - x.mean()).square().mean(); }

// Integrated angle theta_k = dt * sum_{j<=k} rate_j.
Eigen::VectorXd Integrate(const Eigen::VectorXd& rate, double sample_rate_hz) {
  Eigen::VectorXd angle(rate.size());
  double sum = 0.0;
  for (Eigen::Index k = 0; k < rate.size(); ++k) {
    sum += rate[k];
    angle[k] = sum / sample_rate_hz;
  }
  return angle;
}

TEST(WhiteRateNoise, PerSampleStandardDeviationIsNTimesSqrtOfSampleRate) {
  const double fs = 10.0;
  const double n_arw = units::DegPerSqrtHourToArw(0.005);
  RandomSource rng(1);
  const Eigen::VectorXd x = WhiteRateNoise(kSamples, fs, n_arw, &rng);
  const double expected = n_arw * n_arw * fs;
  EXPECT_NEAR(x.mean(), 0.0, 5.0 * std::sqrt(expected / kSamples));
  // Var of a normal sample variance: 2 sigma^4 / n.
  EXPECT_NEAR(Variance(x) / expected, 1.0, 5.0 * std::sqrt(2.0 / kSamples));
}

TEST(QuantizationRateNoise, IntegratedAngleErrorStaysBoundedWithVarianceTwoQSquared) {
  // theta_k = e_k - e_{-1}: the angle error does not grow with time (unlike angle random walk),
  // and Var(theta_{k+m} - theta_k) = 2 Q^2 for every lag m >= 1.
  const double fs = 10.0;
  const double q = units::ArcsecToQuantization(0.1);
  RandomSource rng(2);
  const Eigen::VectorXd angle = Integrate(QuantizationRateNoise(kSamples, fs, q, &rng), fs);
  for (Eigen::Index m : {1, 10, 1000}) {
    // Non-overlapping pairs (stride 2m) are independent when m >= 1 except for shared e_{-1},
    // which cancels in the difference.
    double sum2 = 0.0;
    Eigen::Index count = 0;
    for (Eigen::Index k = 0; k + m < kSamples; k += 2 * m) {
      const double d = angle[k + m] - angle[k];
      sum2 += d * d;
      ++count;
    }
    SCOPED_TRACE(m);
    EXPECT_NEAR(sum2 / count / (2.0 * q * q), 1.0, 5.0 * std::sqrt(2.0 / count));
  }
}

TEST(QuantizationRateNoise, AllanVarianceIsThreeQSquaredOverTauSquared) {
  // A direct Allan variance from its definition (IEEE Std 952-1997 eq. C.10), written here
  // independently of algorithms/allan: sigma^2(tau) = E[(ybar_2 - ybar_1)^2] / 2 with ybar the
  // rate averaged over tau = m dt. Windows are taken at stride 2m + 1 so that the second
  // differences e_{a+2m} - 2 e_{a+m} + e_a are independent.
  const double fs = 1.0;
  const double q = 1e-6;
  RandomSource rng(3);
  const Eigen::VectorXd rate = QuantizationRateNoise(kSamples, fs, q, &rng);
  for (Eigen::Index m : {1, 3, 30}) {
    const double tau = m / fs;
    double sum2 = 0.0;
    Eigen::Index count = 0;
    for (Eigen::Index a = 0; a + 2 * m <= kSamples; a += 2 * m + 1) {
      const double y1 = rate.segment(a, m).mean();
      const double y2 = rate.segment(a + m, m).mean();
      sum2 += (y2 - y1) * (y2 - y1);
      ++count;
    }
    SCOPED_TRACE(m);
    EXPECT_NEAR(0.5 * sum2 / count / (3.0 * q * q / (tau * tau)), 1.0,
                5.0 * std::sqrt(2.0 / count));
  }
}

TEST(QuantizeAngle, KeepsTheIntegratedAngleOnTheQuantizationGrid) {
  const double fs = 100.0;
  const double step = 1e-6;
  RandomSource rng(4);
  const Eigen::VectorXd input =
      WhiteRateNoise(20000, fs, 3e-6, &rng).array() + 5e-5;  // a bias so the angle travels
  const Eigen::VectorXd angle = Integrate(QuantizeAngle(input, fs, step), fs);
  double worst = 0.0;
  for (Eigen::Index k = 0; k < angle.size(); ++k) {
    const double steps = angle[k] / step;
    worst = std::max(worst, std::abs(steps - std::round(steps)));
  }
  // The only error is the rounding of the test's own plain summation (~k eps in units of steps).
  EXPECT_LT(worst, 1e-6);
  // And it tracks the true angle to within half a step (plus that summation error).
  const Eigen::VectorXd true_angle = Integrate(input, fs);
  EXPECT_LE((angle - true_angle).cwiseAbs().maxCoeff(), 0.5 * step * (1.0 + 1e-6));
}

TEST(QuantizeAngle, WithAmpleDitherTheAngleErrorIsUniformWithVarianceStepSquaredOverTwelve) {
  // Widrow's condition: the angle moves by many steps per sample, so the rounding error is
  // independent and uniform on [-step/2, step/2]: mean 0, variance step^2/12, i.e. Q =
  // step/sqrt 12.
  const double fs = 10.0;
  const double step = 1e-7;
  RandomSource rng(5);
  const Eigen::VectorXd input = WhiteRateNoise(kSamples, fs, 50.0 * step * std::sqrt(fs), &rng);
  const Eigen::VectorXd error =
      Integrate(QuantizeAngle(input, fs, step), fs) - Integrate(input, fs);
  const double expected = step * step / 12.0;
  EXPECT_NEAR(error.mean(), 0.0, 5.0 * std::sqrt(expected / kSamples));
  // Var(e^2) / (E e^2)^2 = 9/5 - 1 = 4/5 for a uniform e.
  EXPECT_NEAR(error.squaredNorm() / kSamples / expected, 1.0, 5.0 * std::sqrt(0.8 / kSamples));
}

TEST(RateRandomWalk, IncrementsHaveVarianceKSquaredDt) {
  const double fs = 10.0;
  const double k = units::DegPerHourSqrtHourToRrw(0.01);
  RandomSource rng(6);
  const Eigen::VectorXd x = RateRandomWalk(kSamples, fs, k, &rng);
  const Eigen::VectorXd increments = x.tail(kSamples - 1) - x.head(kSamples - 1);
  const double expected = k * k / fs;
  EXPECT_NEAR(increments.squaredNorm() / (kSamples - 1) / expected, 1.0,
              5.0 * std::sqrt(2.0 / kSamples));
  // Started at rest: x_0 is one increment.
  EXPECT_LT(std::abs(x[0]), 6.0 * std::sqrt(expected));
}

TEST(RateRamp, IsExactlyRTimesTime) {
  const double fs = 4.0;
  const double r = units::DegPerHour2ToRamp(0.02);
  const Eigen::VectorXd x = RateRamp(1001, fs, r);
  for (Eigen::Index k = 0; k < x.size(); ++k) EXPECT_NEAR(x[k], r * k / fs, 1e-15 * r * k / fs);
}

TEST(GaussMarkov, HasStationaryVarianceSigmaSquaredAndLagOneCorrelationExpMinusDtOverTc) {
  const double fs = 1.0;
  const double tc = 5.0;
  const double sigma = 2e-6;
  RandomSource rng(7);
  const Eigen::VectorXd x = GaussMarkov(kSamples, fs, sigma, tc, &rng);
  const double phi = std::exp(-1.0 / (fs * tc));
  const double var = x.squaredNorm() / kSamples;
  // Effective sample count of an AR(1) for the variance: n (1 - phi^2) / (1 + phi^2).
  const double n_eff = kSamples * (1.0 - phi * phi) / (1.0 + phi * phi);
  EXPECT_NEAR(var / (sigma * sigma), 1.0, 5.0 * std::sqrt(2.0 / n_eff));
  const double lag1 = x.head(kSamples - 1).dot(x.tail(kSamples - 1)) / (kSamples - 1) / var;
  // Bartlett: Var(r_1) ~ (1 - phi^2) / n.
  EXPECT_NEAR(lag1, phi, 5.0 * std::sqrt((1.0 - phi * phi) / kSamples));
}

TEST(GaussMarkov, StaysExactWhenTheCorrelationTimeSpansManySamples) {
  // With Tc = 1e4 s at 100 Hz, phi = 1 - 1e-6: the innovations x_{k+1} - phi x_k must still carry
  // variance sigma^2 (1 - phi^2) = 2e-6 sigma^2 (computed with expm1, not 1 - phi^2).
  const double fs = 100.0;
  const double tc = 1e4;
  const double sigma = 1.0;
  RandomSource rng(8);
  const Eigen::VectorXd x = GaussMarkov(kSamples, fs, sigma, tc, &rng);
  const double phi = std::exp(-1.0 / (fs * tc));
  const Eigen::VectorXd innovations = x.tail(kSamples - 1) - phi * x.head(kSamples - 1);
  const double expected = -std::expm1(-2.0 / (fs * tc)) * sigma * sigma;
  EXPECT_NEAR(innovations.squaredNorm() / (kSamples - 1) / expected, 1.0,
              5.0 * std::sqrt(2.0 / kSamples));
}

TEST(SinusoidalRate, HasTheRequestedAmplitudeFrequencyAndPhase) {
  // Projection on sin and cos over a whole number of periods recovers W and the phase exactly
  // (up to rounding): W sin(wt + p) = W cos p sin wt + W sin p cos wt.
  const double fs = 10.0;
  const double f0 = 1.0 / 40.0;  // 400 samples per period
  const double amplitude = 3e-7;
  const double phase = 0.7;
  const Eigen::Index n = 400 * 25;
  const Eigen::VectorXd x = SinusoidalRate(n, fs, f0, amplitude, phase);
  double a = 0.0;
  double b = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double w = 2.0 * units::kPi * f0 * k / fs;
    a += x[k] * std::sin(w);
    b += x[k] * std::cos(w);
  }
  a *= 2.0 / n;
  b *= 2.0 / n;
  EXPECT_NEAR(std::hypot(a, b), amplitude, 1e-12 * amplitude);
  EXPECT_NEAR(std::atan2(b, a), phase, 1e-12);
  EXPECT_NEAR(x.cwiseAbs().maxCoeff(), amplitude, 1e-4 * amplitude);  // dense sampling of peaks
}

TEST(Generators, SameSeedGivesIdenticalOutputAndDifferentSeedDifferentOutput) {
  auto draw = [](std::uint64_t seed) {
    RandomSource rng(seed);
    Eigen::VectorXd x = WhiteRateNoise(1000, 10.0, 1e-6, &rng);
    x += RateRandomWalk(1000, 10.0, 1e-7, &rng);
    x += GaussMarkov(1000, 10.0, 1e-6, 30.0, &rng);
    x += QuantizationRateNoise(1000, 10.0, 1e-6, &rng);
    return x;
  };
  EXPECT_EQ(draw(42), draw(42));
  EXPECT_NE(draw(42), draw(43));
}

}  // namespace
}  // namespace fogpipe::simulation
