#include "algorithms/simulation/flicker_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <unsupported/Eigen/FFT>
#include <vector>

#include "algorithms/common/units.h"

namespace fogpipe::simulation {
namespace {

using units::kPi;

TEST(KasdinCoefficients, MatchTheGammaFunctionClosedForm) {
  // h_k = Gamma(k + alpha/2) / (Gamma(alpha/2) k!)   (Kasdin 1995, eq. 116).
  for (double alpha : {0.5, 1.0, 1.5}) {
    const Eigen::VectorXd h = KasdinCoefficients(20001, alpha);
    for (Eigen::Index k : {0, 1, 2, 10, 1000, 20000}) {
      const double expected =
          std::exp(std::lgamma(k + alpha / 2.0) - std::lgamma(alpha / 2.0) - std::lgamma(k + 1.0));
      // lgamma of ~2e4 carries ~1e-16 * 2e5 absolute error, i.e. ~1e-11 relative after exp.
      EXPECT_NEAR(h[k] / expected, 1.0, 1e-10) << "alpha " << alpha << " k " << k;
    }
  }
}

TEST(KasdinCoefficients, ReduceToWhiteNoiseAndRandomWalkAtAlphaZeroAndTwo) {
  const Eigen::VectorXd white = KasdinCoefficients(50, 0.0);
  const Eigen::VectorXd walk = KasdinCoefficients(50, 2.0);
  EXPECT_EQ(white[0], 1.0);
  EXPECT_EQ(white.tail(49).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(walk, Eigen::VectorXd::Ones(50));
}

TEST(FastFftSize, IsTheSmallestMultipleOfFourWithFactorsTwoThreeFive) {
  EXPECT_EQ(FastFftSize(1), 4);
  EXPECT_EQ(FastFftSize(4), 4);
  EXPECT_EQ(FastFftSize(13), 16);
  EXPECT_EQ(FastFftSize(17), 20);
  EXPECT_EQ(FastFftSize(2 * 216000 - 1), 432000);  // 6 h at 10 Hz
  EXPECT_EQ(FastFftSize(1025), 1080);
}

TEST(FlickerRateNoise, EqualsTheDirectConvolutionOfKasdinsFilterWithWhiteNoise) {
  const Eigen::Index n = 1500;
  const double b = 3e-8;
  RandomSource rng_fft(9);
  const Eigen::VectorXd x = FlickerRateNoise(n, 10.0, b, &rng_fft);
  RandomSource rng_direct(9);
  const Eigen::VectorXd w = rng_direct.Normals(n) * b;
  const Eigen::VectorXd h = KasdinCoefficients(n, 1.0);
  double worst = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    double sum = 0.0;
    for (Eigen::Index j = 0; j <= k; ++j) sum += h[j] * w[k - j];
    worst = std::max(worst, std::abs(sum - x[k]));
  }
  // FFT round-off: ~eps * log2(size) * sum |h| |w| ~ 1e-16 * 12 * 80 * 4 b.
  EXPECT_LT(worst, 1e-12 * b);
}

// Welch periodogram (periodic Hann, non-overlapping segments, segment mean removed), two-sided
// PSD in units^2/Hz at f = j fs / L, j = 0..L/2.
Eigen::VectorXd WelchPsd(const Eigen::VectorXd& x, Eigen::Index length, double fs) {
  const Eigen::Index segments = x.size() / length;
  Eigen::VectorXd window(length);
  for (Eigen::Index i = 0; i < length; ++i)
    window[i] = 0.5 - 0.5 * std::cos(2.0 * kPi * i / length);
  const double power = window.squaredNorm();
  Eigen::FFT<double> fft;
  Eigen::VectorXd psd = Eigen::VectorXd::Zero(length / 2 + 1);
  std::vector<double> buffer(static_cast<size_t>(length));
  std::vector<std::complex<double>> spectrum;
  for (Eigen::Index s = 0; s < segments; ++s) {
    const Eigen::VectorXd segment = x.segment(s * length, length);
    const double mean = segment.mean();
    for (Eigen::Index i = 0; i < length; ++i) buffer[i] = (segment[i] - mean) * window[i];
    fft.fwd(spectrum, buffer);
    for (Eigen::Index j = 0; j <= length / 2; ++j) psd[j] += std::norm(spectrum[j]);
  }
  return psd / (segments * power * fs);
}

TEST(FlickerRateNoise, HasTheIeeeBiasInstabilityPsdLevelAndSlopeMinusOne) {
  // Expected two-sided PSD of the generated sequence: S(f) = B^2 dt / (2 sin(pi f dt)), which is
  // B^2 / (2 pi f) at low frequency (IEEE Std 952-1997 C.3).
  const double fs = 10.0;
  const double b = units::DegPerHourToBias(0.004);
  const Eigen::Index n = Eigen::Index(1) << 20;
  const Eigen::Index length = 4096;
  const Eigen::Index segments = n / length;
  RandomSource rng(10);
  const Eigen::VectorXd psd = WelchPsd(FlickerRateNoise(n, fs, b, &rng), length, fs);
  auto expected = [&](Eigen::Index j) {
    return b * b / fs / (2.0 * std::sin(kPi * static_cast<double>(j) / length));
  };
  // Level, octave by octave. Each Hann periodogram bin is chi^2_2 / 2 (relative std 1); averaging
  // K segments and J bins gives relative std sqrt(c / (K J)), where c = 1 + 2 (2/3)^2 + 2 (1/6)^2
  // = 1.94 accounts for the correlation of neighbouring Hann bins (Harris 1978). Octaves from bin 8
  // keep the window's leakage from the steep low end below 1 %.
  for (Eigen::Index lo = 8; lo < length / 2; lo *= 2) {
    double ratio = 0.0;
    for (Eigen::Index j = lo; j < 2 * lo; ++j) ratio += psd[j] / expected(j);
    ratio /= lo;
    SCOPED_TRACE(lo);
    EXPECT_NEAR(ratio, 1.0, 0.01 + 5.0 * std::sqrt(1.94 / (segments * lo)));
  }
  // Slope of log S against log f over bins 8..256 (f <= fs/16, where sin(pi f dt) ~ pi f dt within
  // 0.7 %): least squares of the measured and of the expected curve over the same bins.
  double sxx = 0.0, sxy_measured = 0.0, sxy_expected = 0.0, mean_x = 0.0;
  const Eigen::Index first = 8;
  const Eigen::Index last = 256;
  const Eigen::Index count = last - first + 1;
  for (Eigen::Index j = first; j <= last; ++j) mean_x += std::log(double(j)) / count;
  for (Eigen::Index j = first; j <= last; ++j) {
    const double dx = std::log(double(j)) - mean_x;
    sxx += dx * dx;
    sxy_measured += dx * std::log(psd[j]);
    sxy_expected += dx * std::log(expected(j));
  }
  const double slope = sxy_measured / sxx;
  EXPECT_NEAR(sxy_expected / sxx, -1.0, 0.01);
  // Standard error of a least-squares slope with per-bin log noise 1/sqrt(K), inflated by the Hann
  // bin correlation 1.94.
  EXPECT_NEAR(slope, sxy_expected / sxx, 5.0 * std::sqrt(1.94 / segments / sxx));
}

// Expected Allan variance of a discrete sequence with two-sided PSD S(f) (dt = 1, f in cycles
// per sample): the Allan difference is a filter with |A(f)|^2 = 4 sin^4(pi f m) / (m^2 sin^2(pi
// f)), so sigma^2(m) = 0.5 * integral_{-1/2}^{1/2} S |A|^2 df. For Kasdin's S = B^2 / (2 sin(pi
// f)):
//   sigma^2(m) = (2 B^2 / m^2) integral_0^{1/2} sin^4(pi f m) / sin^3(pi f) df,
// which tends to (2 ln 2 / pi) B^2 as m grows (IEEE Std 952-1997 C.3). Midpoint rule; the
// integrand is smooth and vanishes linearly at f = 0.
double KasdinFlickerAllanVariance(int m, double b) {
  const int steps = 200000;  // ~1500 points per oscillation at m = 128
  const double h = 0.5 / steps;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double f = (i + 0.5) * h;
    const double s4 = std::pow(std::sin(kPi * f * m), 4);
    sum += s4 / std::pow(std::sin(kPi * f), 3);
  }
  return 2.0 * b * b / (m * m) * sum * h;
}

TEST(FlickerRateNoise, AllanDeviationFloorIsPoint664B) {
  // The closed form first: the discrete flicker sequence reaches the IEEE floor for m >> 1.
  const double floor2 = 2.0 * std::log(2.0) / kPi;
  EXPECT_NEAR(KasdinFlickerAllanVariance(128, 1.0) / floor2, 1.0, 2e-3);
  // Then the generator against it, with a non-overlapping Allan variance written here from its
  // definition (not algorithms/allan). 16 independent records; the mean ratio is compared with
  // its own standard error from the spread of the 16 (Student t with 15 dof: P(|t| > 5) < 2e-4),
  // which needs no equivalent-degrees-of-freedom model for flicker noise.
  const Eigen::Index n = Eigen::Index(1) << 16;
  const int records = 16;
  for (int m : {16, 128}) {
    const double expected = KasdinFlickerAllanVariance(m, 1.0);
    Eigen::VectorXd ratios(records);
    for (int r = 0; r < records; ++r) {
      RandomSource rng(DeriveSeed(100, r));
      const Eigen::VectorXd x = FlickerRateNoise(n, 1.0, 1.0, &rng);
      const Eigen::Index windows = n / m;
      double sum2 = 0.0;
      for (Eigen::Index j = 0; j + 1 < windows; ++j) {
        const double d = x.segment((j + 1) * m, m).mean() - x.segment(j * m, m).mean();
        sum2 += d * d;
      }
      ratios[r] = 0.5 * sum2 / (windows - 1) / expected;
    }
    const double mean = ratios.mean();
    const double standard_error =
        std::sqrt((ratios.array() - mean).square().sum() / (records - 1) / records);
    SCOPED_TRACE(m);
    EXPECT_NEAR(mean, 1.0, 5.0 * standard_error);
    EXPECT_LT(standard_error, 0.05);  // the test has power: a 25 % level error cannot pass
  }
}

TEST(FlickerRateNoise, SameSeedSameOutputDifferentSeedDifferentOutput) {
  RandomSource a(1), b(1), c(2);
  const Eigen::VectorXd xa = FlickerRateNoise(999, 1.0, 1.0, &a);
  EXPECT_EQ(xa, FlickerRateNoise(999, 1.0, 1.0, &b));
  EXPECT_NE(xa, FlickerRateNoise(999, 1.0, 1.0, &c));
}

}  // namespace
}  // namespace fogpipe::simulation
