// Spectral estimates used by the model comparison: a zero-padded periodogram (to locate lines) and
// Welch's averaged periodogram (Welch 1967) for the frequency view, plus a robust band-median
// background against which lines are judged.
//
// All PSDs are one-sided: the variance of x equals the integral of psd over [0, fs/2].
#pragma once

#include <Eigen/Core>
#include <complex>
#include <vector>

namespace fogpipe::model {

struct Spectrum {
  std::vector<double> frequency_hz;
  std::vector<double> psd;  ///< one-sided, (units of x)^2 / Hz
  /// Equivalent degrees of freedom of each psd value: psd / E[psd] ~ chi2(dof) / dof.
  double dof = 2.0;
  int segment_length = 0;  ///< samples per FFT segment (before zero padding)
};

/// Largest 2^a 3^b 5^c <= n (n >= 1): a segment length that kissfft transforms with radix 2, 3,
/// 4, 5 butterflies only.
long FastFftSizeAtMost(long n);

/// True when n has no prime factor other than 2, 3 and 5.
bool IsFastFftSize(long n);

/// DFT X_k = sum_j x_j exp(-2 pi i j k / n) of a real series of any length n, bins 0 .. n / 2.
/// Lengths with a prime factor above 5 (kissfft would fall back to O(n p) butterflies: a 24 h,
/// 100 Hz record one sample short of 8.64e6 has the prime factor 8639999) go through Bluestein's
/// (1970) chirp-z convolution on a fast size >= 2 n - 1.
std::vector<std::complex<double>> RealDftHalf(const std::vector<double>& x);

/// Periodogram of x - mean(x), zero padded to the smallest 2^a 3^b 5^c >= pad_factor * n
/// (pad_factor >= 1). Rectangular window: best resolution for locating a line's frequency.
Spectrum Periodogram(const Eigen::VectorXd& x, double sample_rate_hz, int pad_factor);

/// Welch PSD with Hann windows of `segment_length` samples (FastFftSizeAtMost sizes are fast) and
/// 50 % overlap; each segment's mean is removed. dof from Welch (1967) for Hann/50 %:
/// nu = 36 K^2 / (19 K - 1), K segments (cf. Percival & Walden 1993, eq. 292b).
Spectrum WelchPsd(const Eigen::VectorXd& x, double sample_rate_hz, int segment_length);

/// A smooth background for line detection: for each bin, the median of the psd over a band of
/// bins [j / ratio, j * ratio] widened to at least min_bins, divided by the median of chi2(dof)/dof
/// so that it estimates the mean. Robust to the lines themselves (a line is a few bins).
std::vector<double> BandMedianBackground(const Spectrum& spectrum, double ratio, int min_bins);

/// Median of chi2(nu)/nu (Wilson-Hilferty approximation; exact enough for nu >= 2).
double ChiSquareMedianOverNu(double nu);

/// Standard normal deviate of a ratio r = estimate / expectation distributed as chi2(nu)/nu
/// (Wilson & Hilferty 1931). Positive when the estimate is above its expectation.
double WilsonHilfertyZ(double ratio, double nu);

/// z with upper-tail probability p: Phi^{-1}(1 - p), accurate for tiny p (within 5e-16 relative
/// of Boost.Math from p = 1e-300 to 1 - 1e-16, spectrum_test).
double UpperTailZ(double p);

/// Upper tail of the standard normal, P(Z > z): the inverse of UpperTailZ.
double UpperTailP(double z);

/// Wallace's (1959) normal deviate with the tail probability of Student's t with nu degrees of
/// freedom, z = (8 nu + 1) / (8 nu + 3) sqrt(nu ln(1 + t^2 / nu)) (sign of t), and its inverse;
/// nu = infinity is the normal law itself.
double StudentToNormal(double t, double nu);
double NormalToStudent(double z, double nu);

/// Two-sided family-wise critical |z| for `count` tests at total level alpha (Bonferroni):
/// Phi^{-1}(1 - alpha / (2 count)).
double BonferroniCriticalZ(int count, double alpha);

/// One-sided family-wise critical z for `count` tests: Phi^{-1}(1 - alpha / count).
double BonferroniCriticalZOneSided(int count, double alpha);

}  // namespace fogpipe::model
