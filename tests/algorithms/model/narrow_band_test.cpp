#include "algorithms/model/narrow_band.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>

#include "algorithms/model/spectrum.h"

namespace fogpipe::model {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Simpson's rule of f over [a, b] with n (even) intervals.
template <typename F>
double Simpson(F f, double a, double b, int n) {
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
  return sum * h / 3.0;
}

// The integral of the PSD over [0, inf) is the band's variance sigma^2 (substitution f = f0 tan
// u maps [0, inf) onto [0, pi/2) and puts the peak near u = pi/4).
TEST(NarrowBand, ThePsdIntegratesToTheBandsVariance) {
  for (double zeta : {0.01, 0.05, 0.3, 0.8}) {
    const NarrowBand band{2.0, 0, zeta, 0, 3e-5};
    const double integral = Simpson(
        [&](double u) {
          if (u >= kPi / 2) return 0.0;
          const double c = std::cos(u);
          return NarrowBandOneSidedPsd(band, band.f0_hz * std::tan(u)) * band.f0_hz / (c * c);
        },
        0.0, kPi / 2, 400000);
    EXPECT_NEAR(integral / (band.sigma_rad_s * band.sigma_rad_s), 1.0, 1e-6) << zeta;
    // The peak is sigma^2 / (pi zeta f0) for small zeta (exactly at f0: 2 sigma^2/(zeta w0)).
    EXPECT_NEAR(NarrowBandOneSidedPsd(band, band.f0_hz) * kPi * zeta * band.f0_hz /
                    (band.sigma_rad_s * band.sigma_rad_s),
                1.0, 1e-12);
  }
}

// The closed-form Allan variance equals the transfer-function integral of IEEE Std 952 / NIST
// SP 1065, sigma^2(tau) = 2 int_0^inf S(f) sin^4(pi f tau) / (pi f tau)^2 df, integrated
// numerically (fine enough for the oscillation of sin^4 over the band at each tau).
TEST(NarrowBand, TheAllanVarianceIsThePsdTransferIntegral) {
  for (double zeta : {0.02, 0.2}) {
    const NarrowBand band{1.5, 0, zeta, 0, 2e-5};
    for (double tau : {0.01, 0.1, 0.37, 1.0, 3.0, 10.0}) {
      const auto integrand = [&](double f) {
        if (f <= 0) return 0.0;
        const double x = kPi * f * tau, s = std::sin(x);
        return 2.0 * NarrowBandOneSidedPsd(band, f) * s * s * s * s / (x * x);
      };
      // Up to 200 f0 the neglected tail is below 1e-6 of the band's variance (S ~ f^-4).
      const double numeric = Simpson(integrand, 0.0, 200 * band.f0_hz, 4000000);
      EXPECT_NEAR(NarrowBandAllanVariance(band, tau) / numeric, 1.0, 1e-4)
          << "zeta " << zeta << " tau " << tau;
    }
  }
}

// The band's autocovariance in closed form (narrow_band.h): R(u) = Re[C exp(lambda u)],
// lambda = -zeta w0 + i w_d, C = sigma^2 (1 - i zeta w0 / w_d). Written out here.
double BandAutocovariance(const NarrowBand& b, double u) {
  const double w0 = 2 * kPi * b.f0_hz, wd = w0 * std::sqrt(1 - b.zeta * b.zeta);
  const std::complex<double> lambda(-b.zeta * w0, wd);
  const std::complex<double> c =
      b.sigma_rad_s * b.sigma_rad_s * std::complex<double>(1.0, -b.zeta * w0 / wd);
  return (c * std::exp(lambda * std::abs(u))).real();
}

TEST(NarrowBand, SimulatedSamplesHaveTheBandsAutocovariance) {
  // Sample autocovariances at lags 0..40 of 2e6 samples against R(u). Bartlett's (1946) variance
  // of a sample autocovariance, var c(h) ~ (1/n) sum_k [R(k)^2 + R(k + h) R(k - h)] <= (2/n)
  // sum_k R(k)^2, is computed from the closed form; each lag must be within 5 of its SEs (41
  // lags: a Gaussian false alarm has probability 41 x 5.7e-7).
  for (double zeta : {0.02, 0.2}) {
    const NarrowBand band{1.5, 0, zeta, 0, 2.0};
    const double fs = 10.0;
    const long n = 2000000;
    const Eigen::VectorXd x = SimulateNarrowBand(band, n, fs, 17);
    ASSERT_EQ(x.size(), n);
    double sum_r2 = 0;
    for (long k = -20000; k <= 20000; ++k) sum_r2 += std::pow(BandAutocovariance(band, k / fs), 2);
    const double se = std::sqrt(2.0 * sum_r2 / n);
    for (int h = 0; h <= 40; ++h) {
      const double c = x.head(n - h).dot(x.tail(n - h)) / (n - h);
      EXPECT_NEAR(c, BandAutocovariance(band, h / fs), 5 * se) << "zeta " << zeta << " lag " << h;
    }
    // The same seed gives the same samples, and the block means are those of the samples.
    EXPECT_EQ(SimulateNarrowBand(band, 1000, fs, 17), x.head(1000));
    const Eigen::VectorXd means = SimulateNarrowBand(band, 250, fs, 17, 4);
    for (int i = 0; i < 250; ++i)
      EXPECT_NEAR(means[i], x.segment(4 * i, 4).mean(), 1e-15 * band.sigma_rad_s) << i;
  }
}

// Whittle fit of a simulated band (AR(2) resonator in white noise, 6 h at 10 Hz) started from a
// rough guess: centre within 1 %, damping ratio within 25 %, rms within 10 %.
TEST(NarrowBand, FitRecoversASimulatedBand) {
  const double fs = 10.0, f0 = 1.3, zeta = 0.02, white_psd = 2e-10;
  const long n = static_cast<long>(6 * 3600 * fs);
  std::mt19937_64 g(7);
  std::normal_distribution<double> e(0.0, 1.0);
  const double w0 = 2 * kPi * f0 / fs, r = std::exp(-zeta * w0);
  Eigen::VectorXd band(n), x(n);
  double x1 = 0, x2 = 0;
  for (long i = -4096; i < n; ++i) {
    const double v = 2 * r * std::cos(w0) * x1 - r * r * x2 + e(g);
    x2 = x1;
    x1 = v;
    if (i >= 0) band[i] = v;
  }
  const double power = 10 * white_psd * kPi * zeta * f0;  // peak 10x the white floor
  band *= std::sqrt(power / band.squaredNorm() * n);
  for (long i = 0; i < n; ++i) x[i] = band[i] + std::sqrt(white_psd * fs / 2) * e(g);
  const Spectrum welch = WelchPsd(x, fs, static_cast<int>(FastFftSizeAtMost(n / 8)));
  const std::vector<double> background(welch.psd.size(), white_psd);
  const NarrowBandFitResult fit =
      FitNarrowBand(welch, background, {}, 4, {1.25, 1.36, 1.31, 0.5 * power});
  ASSERT_TRUE(fit.ok) << fit.message;
  EXPECT_NEAR(fit.band.f0_hz / f0, 1.0, 0.01);
  EXPECT_NEAR(fit.band.zeta / zeta, 1.0, 0.25);
  EXPECT_NEAR(fit.band.sigma_rad_s / std::sqrt(power), 1.0, 0.10);
  EXPECT_GT(fit.band.f0_se_hz, 0);
  EXPECT_GT(fit.band.minus_two_log_likelihood_drop, 100);
}

}  // namespace
}  // namespace fogpipe::model
