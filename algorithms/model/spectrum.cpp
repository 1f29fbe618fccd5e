#include "algorithms/model/spectrum.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <unsupported/Eigen/FFT>

#include "algorithms/common/units.h"

namespace fogpipe::model {
namespace {

// Smallest 2^a 3^b 5^c >= n: a size kissfft transforms with radix 2, 3, 4, 5 butterflies only
// (cf. scipy.fft.next_fast_len). Padding a 24 h, 100 Hz record 2x to 2^25 instead would nearly
// double the transform and its memory.
long NextFastSize(long n) {
  long best = 1;
  while (best < n) best <<= 1;
  for (long p5 = 1; p5 < 2 * n; p5 *= 5)
    for (long p35 = p5; p35 < 2 * n; p35 *= 3) {
      long candidate = p35;
      while (candidate < n) candidate <<= 1;
      best = std::min(best, candidate);
    }
  return best;
}

}  // namespace

long FastFftSizeAtMost(long n) {
  long best = 1;
  for (long p5 = 1; p5 <= n; p5 *= 5)
    for (long p35 = p5; p35 <= n; p35 *= 3) {
      long candidate = p35;
      while (2 * candidate <= n) candidate <<= 1;
      best = std::max(best, candidate);
    }
  return best;
}

bool IsFastFftSize(long n) {
  if (n < 1) return false;
  for (long factor : {2L, 3L, 5L})
    while (n % factor == 0) n /= factor;
  return n == 1;
}

std::vector<std::complex<double>> RealDftHalf(const std::vector<double>& x) {
  const long n = static_cast<long>(x.size());
  std::vector<std::complex<double>> out;
  if (n == 0) return out;
  if (n == 1) return {x[0]};  // Eigen's kissfft has no plan for one point (it crashes)
  if (IsFastFftSize(n)) {
    Eigen::FFT<double> fft;
    fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);  // real input: bins 0 .. n/2 only
    fft.fwd(out, x);
    out.resize(n / 2 + 1);
    return out;
  }
  // Bluestein: j k = (j^2 + k^2 - (k - j)^2) / 2, so X_k = w_k^* sum_j (x_j w_j^*) w_{k-j} with the
  // chirp w_m = exp(i pi m^2 / n): a convolution, done by FFTs of a fast size m >= 2 n - 1. The
  // chirp's phase uses m^2 mod 2n in exact integer arithmetic (no loss for large m).
  const long padded_length = NextFastSize(2 * n - 1);
  std::vector<std::complex<double>> chirp(n), chirped(padded_length, 0.0),
      chirp_kernel(padded_length, 0.0), chirped_dft, kernel_dft, conv;
  for (long j = 0; j < n; ++j) {
    const long long phase_index = (static_cast<long long>(j) * j) % (2LL * n);
    chirp[j] =
        std::polar(1.0, units::kPi * static_cast<double>(phase_index) / static_cast<double>(n));
    chirped[j] = x[j] * std::conj(chirp[j]);
    chirp_kernel[j] = chirp[j];
    if (j > 0) chirp_kernel[padded_length - j] = chirp[j];
  }
  Eigen::FFT<double> fft;
  fft.fwd(chirped_dft, chirped);
  fft.fwd(kernel_dft, chirp_kernel);
  for (long k = 0; k < padded_length; ++k) chirped_dft[k] *= kernel_dft[k];
  fft.inv(conv, chirped_dft);  // Eigen's inverse is scaled by 1 / padded_length
  out.resize(n / 2 + 1);
  for (long k = 0; k <= n / 2; ++k) out[k] = std::conj(chirp[k]) * conv[k];
  return out;
}

namespace {

// Inverse standard normal CDF: Acklam's rational approximation (relative error < 1.2e-9), then
// one Halley step on Phi(z) - p with Phi from erfc, which Acklam gives as the refinement to full
// double precision (the step's error is cubic in the approximation's).
double AcklamNormalQuantile(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  const double lo = 0.02425, hi = 1 - lo;
  if (p < lo) {
    double q = std::sqrt(-2 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  if (p > hi) return -AcklamNormalQuantile(1 - p);
  double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
}

double NormalQuantile(double p) {
  // The lower tail is refined directly; for p > 1/2 the quantile is minus that of 1 - p (exact in
  // floating point there), so that the step works on the small tail and keeps its digits.
  if (p > 0.5) return -NormalQuantile(1 - p);
  const double z = AcklamNormalQuantile(p);
  constexpr double kSqrt2Pi = 2.506628274631000502415765284811;
  const double cdf_error = 0.5 * std::erfc(-z / std::sqrt(2.0)) - p;
  const double correction = cdf_error * kSqrt2Pi * std::exp(0.5 * z * z);
  return z - correction / (1 + 0.5 * z * correction);
}

}  // namespace

Spectrum Periodogram(const Eigen::VectorXd& x, double fs, int pad_factor) {
  Spectrum spectrum;
  const long n = x.size();
  if (n < 2) return spectrum;
  const long nfft = NextFastSize(std::max<long>(n, static_cast<long>(pad_factor) * n));
  std::vector<double> in(nfft, 0.0);
  const double mean = x.mean();
  for (long i = 0; i < n; ++i) in[i] = x[i] - mean;
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);  // real input: bins 0 .. nfft/2 only
  std::vector<std::complex<double>> out;
  fft.fwd(out, in);
  const int half = nfft / 2;
  spectrum.frequency_hz.resize(half + 1);
  spectrum.psd.resize(half + 1);
  const double scale = 2.0 / (fs * static_cast<double>(n));  // one-sided, rectangular window
  for (int k = 0; k <= half; ++k) {
    spectrum.frequency_hz[k] = fs * k / nfft;
    spectrum.psd[k] = std::norm(out[k]) * scale * ((k == 0 || k == half) ? 0.5 : 1.0);
  }
  spectrum.dof = 2.0;
  spectrum.segment_length = static_cast<int>(n);
  return spectrum;
}

Spectrum WelchPsd(const Eigen::VectorXd& x, double fs, int segment_length) {
  Spectrum spectrum;
  const long n = x.size();
  segment_length = static_cast<int>(std::min<long>(segment_length, n));
  if (segment_length < 8) return spectrum;
  const int step = segment_length / 2;
  const long num_segments = (n - segment_length) / step + 1;
  std::vector<double> window(segment_length);
  double window_energy = 0;
  for (int i = 0; i < segment_length; ++i) {
    window[i] = 0.5 - 0.5 * std::cos(2 * units::kPi * i / segment_length);  // periodic Hann
    window_energy += window[i] * window[i];
  }
  const int half = segment_length / 2;
  spectrum.frequency_hz.resize(half + 1);
  spectrum.psd.assign(half + 1, 0.0);
  for (int k = 0; k <= half; ++k) spectrum.frequency_hz[k] = fs * k / segment_length;
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);  // real input: bins 0 .. nfft/2 only
  std::vector<double> in(segment_length);
  std::vector<std::complex<double>> out;
  for (long segment_index = 0; segment_index < num_segments; ++segment_index) {
    const long start = segment_index * step;
    const double mean = x.segment(start, segment_length).mean();
    for (int i = 0; i < segment_length; ++i) in[i] = (x[start + i] - mean) * window[i];
    fft.fwd(out, in);
    for (int k = 0; k <= half; ++k) spectrum.psd[k] += std::norm(out[k]);
  }
  const double scale = 2.0 / (fs * window_energy * static_cast<double>(num_segments));
  for (int k = 0; k <= half; ++k) spectrum.psd[k] *= scale * ((k == 0 || k == half) ? 0.5 : 1.0);
  const double segments = static_cast<double>(num_segments);
  spectrum.dof = num_segments == 1 ? 2.0 : 36.0 * segments * segments / (19.0 * segments - 1.0);
  spectrum.segment_length = segment_length;
  return spectrum;
}

double ChiSquareMedianOverNu(double nu) {
  const double variance = 2.0 / (9.0 * nu);
  return std::pow(1.0 - variance, 3.0);
}

double WilsonHilfertyZ(double ratio, double nu) {
  const double variance = 2.0 / (9.0 * nu);
  return (std::cbrt(std::max(ratio, 0.0)) - (1.0 - variance)) / std::sqrt(variance);
}

double UpperTailZ(double p) {
  p = std::clamp(p, 1e-300, 1.0 - 1e-16);
  return -NormalQuantile(p);
}

double UpperTailP(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

double StudentToNormal(double t, double nu) {
  if (!std::isfinite(nu)) return t;
  const double z = (8.0 * nu + 1.0) / (8.0 * nu + 3.0) * std::sqrt(nu * std::log1p(t * t / nu));
  return t < 0 ? -z : z;
}

double NormalToStudent(double z, double nu) {
  if (!std::isfinite(nu)) return z;
  const double corrected = z * (8.0 * nu + 3.0) / (8.0 * nu + 1.0);
  return (z < 0 ? -1.0 : 1.0) * std::sqrt(nu * std::expm1(corrected * corrected / nu));
}

double BonferroniCriticalZ(int count, double alpha) {
  return NormalQuantile(1.0 - alpha / (2.0 * std::max(count, 1)));
}

double BonferroniCriticalZOneSided(int count, double alpha) {
  return NormalQuantile(1.0 - alpha / std::max(count, 1));
}

std::vector<double> BandMedianBackground(const Spectrum& spectrum, double ratio, int min_bins) {
  const int num_bins = static_cast<int>(spectrum.psd.size());
  std::vector<double> background(num_bins, 0.0);
  const double chi_square_median = ChiSquareMedianOverNu(spectrum.dof);
  // The band [j / ratio, j * ratio] is capped at kMaxHalf bins either side (a median of ~2000
  // Exp(1) values is already within ~3 % of the truth), and its median is recomputed only when j
  // has moved by 1/8 of the band: O(m log m) overall on long spectra.
  constexpr int kMaxHalf = 1024;
  std::vector<double> window_values;
  int last_bin = -1, last_width = 1;
  double last = 0;
  for (int bin = 1; bin < num_bins; ++bin) {
    if (last_bin >= 0 && (bin - last_bin) * 8 < last_width) {
      background[bin] = last;
      continue;
    }
    int lo = static_cast<int>(std::floor(bin / ratio));
    int hi = static_cast<int>(std::ceil(bin * ratio));
    if (hi - lo + 1 < min_bins) {
      lo = bin - min_bins / 2;
      hi = bin + min_bins / 2;
    }
    lo = std::max({lo, 1, bin - kMaxHalf});
    hi = std::min({hi, num_bins - 1, bin + kMaxHalf});
    window_values.assign(spectrum.psd.begin() + lo, spectrum.psd.begin() + hi + 1);
    std::nth_element(window_values.begin(), window_values.begin() + window_values.size() / 2,
                     window_values.end());
    last = window_values[window_values.size() / 2] / chi_square_median;
    last_bin = bin;
    last_width = hi - lo + 1;
    background[bin] = last;
  }
  if (num_bins > 1) background[0] = background[1];
  return background;
}

}  // namespace fogpipe::model
