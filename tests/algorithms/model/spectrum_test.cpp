#include "algorithms/model/spectrum.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

namespace fogpipe::model {
namespace {

Eigen::VectorXd WhiteNoise(long n, double sigma, std::uint64_t seed) {
  std::mt19937_64 g(seed);
  Eigen::VectorXd x(n);
  for (long i = 0; i < n; i += 2) {  // Box-Muller
    const double u1 = (static_cast<double>(g() >> 11) + 0.5) * 0x1.0p-53;
    const double u2 = static_cast<double>(g() >> 11) * 0x1.0p-53;
    const double r = std::sqrt(-2.0 * std::log(u1));
    x[i] = sigma * r * std::cos(2 * M_PI * u2);
    if (i + 1 < n) x[i + 1] = sigma * r * std::sin(2 * M_PI * u2);
  }
  return x;
}

TEST(Spectrum, WelchPsdOfWhiteNoiseIsTwiceTheVarianceOverTheSampleRate) {
  const double fs = 10.0, sigma = 2.0;
  const Spectrum s = WelchPsd(WhiteNoise(1 << 17, sigma, 1), fs, 1024);
  double mean = 0;
  int count = 0;
  for (size_t k = 1; k + 1 < s.psd.size(); ++k, ++count) mean += s.psd[k];
  mean /= count;
  // One-sided level 2 sigma^2 / fs = 0.8. The average of 511 bins, each with dof ~ 2 * 255 * 0.95,
  // has a relative sd ~ 1 / sqrt(511 * 240) = 0.3 %; 2 % covers it and correlated bins.
  EXPECT_NEAR(mean, 2 * sigma * sigma / fs, 0.02 * 0.8);
  EXPECT_GT(s.dof, 400.0);  // Welch (1967): ~1.9 K for Hann / 50 %
}

TEST(Spectrum, WelchBinsOfWhiteNoiseFollowChiSquareWithWelchsDof) {
  // The frequency view tests each Welch bin as S(f) chi2(nu)/nu with nu = 36 K^2 / (19 K - 1)
  // (Welch 1967, Hann, 50 % overlap). With the view's segments (n / 8, K = 15, nu = 28.5) the
  // bins of white noise must have variance 2 / nu relative to their mean, and Wilson-Hilferty
  // z > 2 in 2.28 % of them.
  const double fs = 10.0, sigma = 1.5;
  const long n = 1L << 20;
  const Spectrum s = WelchPsd(WhiteNoise(n, sigma, 4), fs, static_cast<int>(n / 8));
  ASSERT_NEAR(s.dof, 36.0 * 225.0 / (19.0 * 15.0 - 1.0), 1e-12);
  const double level = 2 * sigma * sigma / fs;
  double sum = 0, sum2 = 0;
  int count = 0, above = 0;
  for (size_t k = 4; k + 1 < s.psd.size(); ++k, ++count) {
    const double r = s.psd[k] / level;
    sum += r;
    sum2 += r * r;
    above += WilsonHilfertyZ(r, s.dof) > 2.0;
  }
  const double mean = sum / count, var = sum2 / count - mean * mean;
  // 65532 bins, adjacent Hann bins correlated (~half as many independent ones): the mean has sd
  // sqrt(2 / nu / 32000) = 0.15 %, the variance ratio sd ~ sqrt(2 / 32000) ~ 0.8 % (plus excess
  // kurtosis), the tail fraction sd sqrt(0.0228 / 32000) = 0.08 %: 4 sd each.
  EXPECT_NEAR(mean, 1.0, 0.006);
  EXPECT_NEAR(var / (2.0 / s.dof), 1.0, 0.06);
  EXPECT_NEAR(static_cast<double>(above) / count, 0.02275, 0.0035);
}

TEST(Spectrum, FastFftSizeAtMostIsTheLargestFiveSmoothSize) {
  EXPECT_EQ(FastFftSizeAtMost(8640000 / 8), 1080000);  // 24 h at 100 Hz: 2^6 3^3 5^4
  EXPECT_EQ(FastFftSizeAtMost(1), 1);
  EXPECT_EQ(FastFftSizeAtMost(7), 6);
  for (long n = 1; n <= 3000; ++n) {
    const long m = FastFftSizeAtMost(n);
    ASSERT_LE(m, n);
    ASSERT_TRUE(IsFastFftSize(m)) << n;
    for (long k = m + 1; k <= n; ++k) ASSERT_FALSE(IsFastFftSize(k)) << n;
  }
}

// Reference: the O(n^2) sum in long double (64-bit mantissa, 2^11 times finer than double) with
// exact integer phase reduction (j k mod n) and a long double table of exp(-2 pi i q / n): its own
// error is ~1e-19 relative, negligible. Bound on the FFT's normwise relative error (Higham,
// Accuracy and Stability of Numerical Algorithms, 2nd ed., Theorem 24.2): log2(n) eta with
// eta = mu + gamma_4 (sqrt 2 + mu) ~ 3.9 eps for radix 2 (twiddles good to mu ~ eps); a radix-r
// butterfly does r - 1 additions where log2(r) radix-2 stages do log2(r), at most 1.8 times as many
// (r = 5), so 7 eps log2(n) for kissfft's radix 2, 3, 4, 5. Bluestein does three such transforms of
// size m >= 2 n - 1 (m < 4 n) and two chirp products (~4 eps); the chirp's spectrum is flat, so the
// pointwise product of spectra does not amplify the error: 3 x 7 eps log2(4 n) + 4 eps.
TEST(Spectrum, RealDftOfAnyLengthMatchesTheDefinitionInLongDouble) {
  const double eps = std::numeric_limits<double>::epsilon();
  const long double two_pi = 6.283185307179586476925286766559005768L;
  // Smooth lengths (kissfft): 2, 3, 1000, 3^7, 5^5, 2^12. Others (Bluestein): the primes 7, 97,
  // 1009, 8191 and 10007, 2 x 109 x 7 = 1526, 2 x 4999; and one point.
  for (long n :
       {1L, 2L, 3L, 7L, 97L, 1000L, 1009L, 1526L, 2187L, 3125L, 4096L, 8191L, 9998L, 10007L}) {
    const Eigen::VectorXd x = WhiteNoise(n, 1.0, 5 + n);
    const std::vector<double> v(x.data(), x.data() + n);
    const auto fast = RealDftHalf(v);
    ASSERT_EQ(static_cast<long>(fast.size()), n / 2 + 1);
    std::vector<std::complex<long double>> w(n);
    for (long q = 0; q < n; ++q) w[q] = std::polar(1.0L, -two_pi * q / n);
    long double error2 = 0, norm2 = 0;
    for (long k = 0; k <= n / 2; ++k) {
      std::complex<long double> ref = 0;
      for (long j = 0; j < n; ++j) ref += static_cast<long double>(x[j]) * w[(j * k) % n];
      error2 += std::norm(std::complex<long double>(fast[k]) - ref);
      norm2 += std::norm(ref);
    }
    const double log2n = std::log2(std::max(2.0, static_cast<double>(n)));
    const double bound =
        IsFastFftSize(n) ? 7.0 * eps * log2n : 21.0 * eps * (log2n + 2.0) + 4 * eps;
    EXPECT_LE(static_cast<double>(std::sqrt(error2 / norm2)), bound) << "n " << n;
  }
}

TEST(Spectrum, PeriodogramPeaksAtTheLineFrequency) {
  const double fs = 10.0, f0 = 0.123;
  Eigen::VectorXd x = WhiteNoise(20000, 1.0, 2);
  for (long i = 0; i < x.size(); ++i) x[i] += 0.5 * std::sin(2 * M_PI * f0 * i / fs);
  const Spectrum s = Periodogram(x, fs, 2);
  size_t best = 1;
  for (size_t k = 1; k < s.psd.size(); ++k)
    if (s.psd[k] > s.psd[best]) best = k;
  // The padded grid spacing is fs / 40000 (2 x 20000 is 2^6 5^4); the peak is within one spacing
  // of f0.
  EXPECT_NEAR(s.frequency_hz[best], f0, s.frequency_hz[1]);
}

TEST(Spectrum, WilsonHilfertyAndNormalTailsMatchKnownQuantiles) {
  EXPECT_NEAR(UpperTailZ(0.025), 1.959964, 1e-5);
  EXPECT_NEAR(UpperTailZ(1e-10), 6.361341, 1e-4);
  EXPECT_NEAR(BonferroniCriticalZ(1, 0.05), 1.959964, 1e-5);
  // chi2(10)/10 upper 5 % point is 1.8307: Wilson-Hilferty gives z ~ 1.645 there (to ~0.01).
  EXPECT_NEAR(WilsonHilfertyZ(1.8307, 10), 1.645, 0.02);
  EXPECT_NEAR(WilsonHilfertyZ(ChiSquareMedianOverNu(20), 20), 0.0, 1e-12);
}

// UpperTailZ refines Acklam's approximation by a Halley step on Phi(z) - p, Phi from erfc. Its
// error: the residual carries ~2 eps p (erfc's few ulps and p's rounding), which moves z by that
// over the density phi(z), plus the rounding of the step itself (~2 eps |z|); Boost.Math's normal
// quantile (in long double) adds < 1 eps. From p = 1e-300 to 1 - 1e-16, 10 points per decade.
TEST(Spectrum, UpperTailZAgreesWithBoostMathFromTinyTailsToTheCentre) {
  const double eps = std::numeric_limits<double>::epsilon();
  const boost::math::normal normal;
  double max_error = 0.0;
  for (double l = -300.0; l < -0.30103; l += 0.1) {
    for (double p : {std::pow(10.0, l), 1.0 - std::pow(10.0, l)}) {
      if (p > 1.0 - 1e-16) continue;
      // Phi^{-1}(1 - p) from the smaller tail (1 - p is exact for p >= 1/2).
      const double z_ref =
          p <= 0.5 ? -boost::math::quantile(normal, p) : boost::math::quantile(normal, 1.0 - p);
      const double tol = 4.0 * eps * std::min(p, 1.0 - p) / boost::math::pdf(normal, z_ref) +
                         3.0 * eps * std::abs(z_ref);
      const double error = std::abs(UpperTailZ(p) - z_ref);
      EXPECT_LE(error, tol) << p;
      max_error = std::max(max_error, error / std::max(std::abs(z_ref), 1e-300));
    }
  }
  std::printf("UpperTailZ against Boost.Math: max relative error %.3g\n", max_error);
}

TEST(Spectrum, BandMedianBackgroundOfWhiteNoiseIsItsMeanLevel) {
  const Spectrum s = Periodogram(WhiteNoise(1 << 16, 1.0, 3), 1.0, 1);
  const std::vector<double> bg = BandMedianBackground(s, 1.25, 33);
  // Level 2. From bin 2000 on the band holds >= 900 values; the sample median of m Exp values has
  // relative sd 1 / (ln 2 sqrt(m)) = 4.8 %, so 15 % is 3 sd (plus 1.3 % for Wilson-Hilferty's
  // median of chi2(2)/2, 0.702, against the exact ln 2).
  for (size_t k = 2000; k < bg.size(); k += 997) EXPECT_NEAR(bg[k], 2.0, 0.3) << k;
}

}  // namespace
}  // namespace fogpipe::model
