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
      long m = p35;
      while (m < n) m <<= 1;
      best = std::min(best, m);
    }
  return best;
}

}  // namespace

long FastFftSizeAtMost(long n) {
  long best = 1;
  for (long p5 = 1; p5 <= n; p5 *= 5)
    for (long p35 = p5; p35 <= n; p35 *= 3) {
      long m = p35;
      while (2 * m <= n) m <<= 1;
      best = std::max(best, m);
    }
  return best;
}

bool IsFastFftSize(long n) {
  if (n < 1) return false;
  for (long p : {2L, 3L, 5L})
    while (n % p == 0) n /= p;
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
  const long m = NextFastSize(2 * n - 1);
  std::vector<std::complex<double>> chirp(n), a(m, 0.0), b(m, 0.0), fa, fb, conv;
  for (long j = 0; j < n; ++j) {
    const long long q = (static_cast<long long>(j) * j) % (2LL * n);
    chirp[j] = std::polar(1.0, units::kPi * static_cast<double>(q) / static_cast<double>(n));
    a[j] = x[j] * std::conj(chirp[j]);
    b[j] = chirp[j];
    if (j > 0) b[m - j] = chirp[j];
  }
  Eigen::FFT<double> fft;
  fft.fwd(fa, a);
  fft.fwd(fb, b);
  for (long k = 0; k < m; ++k) fa[k] *= fb[k];
  fft.inv(conv, fa);  // Eigen's inverse is scaled by 1 / m
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
  const double e = 0.5 * std::erfc(-z / std::sqrt(2.0)) - p;
  const double u = e * kSqrt2Pi * std::exp(0.5 * z * z);
  return z - u / (1 + 0.5 * z * u);
}

}  // namespace

Spectrum Periodogram(const Eigen::VectorXd& x, double fs, int pad_factor) {
  Spectrum s;
  const long n = x.size();
  if (n < 2) return s;
  const long nfft = NextFastSize(std::max<long>(n, static_cast<long>(pad_factor) * n));
  std::vector<double> in(nfft, 0.0);
  const double mean = x.mean();
  for (long i = 0; i < n; ++i) in[i] = x[i] - mean;
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);  // real input: bins 0 .. nfft/2 only
  std::vector<std::complex<double>> out;
  fft.fwd(out, in);
  const int half = nfft / 2;
  s.frequency_hz.resize(half + 1);
  s.psd.resize(half + 1);
  const double scale = 2.0 / (fs * static_cast<double>(n));  // one-sided, rectangular window
  for (int k = 0; k <= half; ++k) {
    s.frequency_hz[k] = fs * k / nfft;
    s.psd[k] = std::norm(out[k]) * scale * ((k == 0 || k == half) ? 0.5 : 1.0);
  }
  s.dof = 2.0;
  s.segment_length = static_cast<int>(n);
  return s;
}

Spectrum WelchPsd(const Eigen::VectorXd& x, double fs, int seg) {
  Spectrum s;
  const long n = x.size();
  seg = static_cast<int>(std::min<long>(seg, n));
  if (seg < 8) return s;
  const int step = seg / 2;
  const long count = (n - seg) / step + 1;
  std::vector<double> w(seg);
  double w2 = 0;
  for (int i = 0; i < seg; ++i) {
    w[i] = 0.5 - 0.5 * std::cos(2 * units::kPi * i / seg);  // periodic Hann
    w2 += w[i] * w[i];
  }
  const int half = seg / 2;
  s.frequency_hz.resize(half + 1);
  s.psd.assign(half + 1, 0.0);
  for (int k = 0; k <= half; ++k) s.frequency_hz[k] = fs * k / seg;
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);  // real input: bins 0 .. nfft/2 only
  std::vector<double> in(seg);
  std::vector<std::complex<double>> out;
  for (long c = 0; c < count; ++c) {
    const long start = c * step;
    const double mean = x.segment(start, seg).mean();
    for (int i = 0; i < seg; ++i) in[i] = (x[start + i] - mean) * w[i];
    fft.fwd(out, in);
    for (int k = 0; k <= half; ++k) s.psd[k] += std::norm(out[k]);
  }
  const double scale = 2.0 / (fs * w2 * static_cast<double>(count));
  for (int k = 0; k <= half; ++k) s.psd[k] *= scale * ((k == 0 || k == half) ? 0.5 : 1.0);
  const double kk = static_cast<double>(count);
  s.dof = count == 1 ? 2.0 : 36.0 * kk * kk / (19.0 * kk - 1.0);
  s.segment_length = seg;
  return s;
}

double ChiSquareMedianOverNu(double nu) {
  const double a = 2.0 / (9.0 * nu);
  return std::pow(1.0 - a, 3.0);
}

double WilsonHilfertyZ(double ratio, double nu) {
  const double a = 2.0 / (9.0 * nu);
  return (std::cbrt(std::max(ratio, 0.0)) - (1.0 - a)) / std::sqrt(a);
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
  const double a = z * (8.0 * nu + 3.0) / (8.0 * nu + 1.0);
  return (z < 0 ? -1.0 : 1.0) * std::sqrt(nu * std::expm1(a * a / nu));
}

double BonferroniCriticalZ(int count, double alpha) {
  return NormalQuantile(1.0 - alpha / (2.0 * std::max(count, 1)));
}

double BonferroniCriticalZOneSided(int count, double alpha) {
  return NormalQuantile(1.0 - alpha / std::max(count, 1));
}

std::vector<double> BandMedianBackground(const Spectrum& s, double ratio, int min_bins) {
  const int m = static_cast<int>(s.psd.size());
  std::vector<double> bg(m, 0.0);
  const double med = ChiSquareMedianOverNu(s.dof);
  // The band [j / ratio, j * ratio] is capped at kMaxHalf bins either side (a median of ~2000
  // Exp(1) values is already within ~3 % of the truth), and its median is recomputed only when j
  // has moved by 1/8 of the band: O(m log m) overall on long spectra.
  constexpr int kMaxHalf = 1024;
  std::vector<double> buf;
  int last_j = -1, last_width = 1;
  double last = 0;
  for (int j = 1; j < m; ++j) {
    if (last_j >= 0 && (j - last_j) * 8 < last_width) {
      bg[j] = last;
      continue;
    }
    int lo = static_cast<int>(std::floor(j / ratio));
    int hi = static_cast<int>(std::ceil(j * ratio));
    if (hi - lo + 1 < min_bins) {
      lo = j - min_bins / 2;
      hi = j + min_bins / 2;
    }
    lo = std::max({lo, 1, j - kMaxHalf});
    hi = std::min({hi, m - 1, j + kMaxHalf});
    buf.assign(s.psd.begin() + lo, s.psd.begin() + hi + 1);
    std::nth_element(buf.begin(), buf.begin() + buf.size() / 2, buf.end());
    last = buf[buf.size() / 2] / med;
    last_j = j;
    last_width = hi - lo + 1;
    bg[j] = last;
  }
  if (m > 1) bg[0] = bg[1];
  return bg;
}

}  // namespace fogpipe::model
