// Test-only power-law rate noise with an exactly known Allan variance, for the coverage of
// confidence intervals (allan_coverage_test.cpp).
//
// The rate is a window of n samples of a circular stationary Gaussian process of length L >= 4 n
// (a power of two) with two-sided spectral density, in cycles per sample,
//   S(f) = sum_terms h_alpha (2 sin(pi f))^alpha,  f = k / L, k = 1 .. L - 1 (no DC),
// drawn by FFT: y = IFFT(sqrt(S) FFT(w)), w white with unit variance. (2 sin(pi f))^alpha is the
// discrete power law: alpha = 2 is differenced white phase (white PM), 0 white rate (white FM),
// -2 a random walk (random-walk FM), and 1, -1 the half-integer fractional differences / sums of
// Kasdin & Walter (1992). The lowest frequency 1 / L is the low cutoff every finite record has.
//
// Truth is not estimated from simulations: for the circular process the expectation of every
// overlapping second difference is the same, so the true Allan variance at factor m is the sum
//   AVAR(m) = (1 / L) sum_k S(k / L) |H_m(k / L)|^2 / 2,
//   |H_m(f)|^2 = 4 sin^4(pi f m) / (m^2 sin^2(pi f)),
// where H_m is the transfer function from y to the difference of two adjacent m-averages (its
// magnitude is |1 - e^{-2 pi i f m}|^2 |1 - e^{-2 pi i f m}|^2 / (m^2 |1 - e^{-2 pi i f}|^2)).
// White FM checks it: S = h0 gives AVAR(m) = h0 / m.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <cstdint>
#include <unsupported/Eigen/FFT>
#include <vector>

#include "algorithms/simulation/random.h"

namespace fogpipe::allan::testing {

struct PowerLawTerm {
  int alpha =
      0;  ///< S_y(f) ~ f^alpha: 2 white PM, 1 flicker PM, 0 white FM, -1 flicker FM, -2 RWFM.
  double h = 1.0;  ///< Level h_alpha of the discrete spectrum [rate^2 per cycle/sample].
};

class PowerLawNoise {
 public:
  PowerLawNoise(std::vector<PowerLawTerm> terms, long long n, int oversample = 4)
      : terms_(std::move(terms)), n_(n) {
    length_ = 1;
    while (length_ < oversample * n) length_ *= 2;
    amplitude_.resize(length_);
    spectrum_.resize(length_);
    constexpr double kPi = 3.14159265358979323846;
    for (long long k = 0; k < length_; ++k) {
      double s = 0.0;
      if (k != 0) {
        const double two_sin = 2.0 * std::sin(kPi * static_cast<double>(k) / length_);
        for (const PowerLawTerm& t : terms_) s += t.h * std::pow(std::abs(two_sin), t.alpha);
      }
      spectrum_[k] = s;
      amplitude_[k] = std::sqrt(s);
    }
  }

  long long size() const { return n_; }

  /// n rate samples from the realisation `seed` (the window starts at sample 0 of the circle).
  Eigen::VectorXd Draw(std::uint64_t seed) const {
    fogpipe::simulation::RandomSource rng(seed);
    std::vector<double> white(static_cast<size_t>(length_));
    for (double& v : white) v = rng.Normal();
    Eigen::FFT<double> fft;
    std::vector<std::complex<double>> spectrum;
    fft.fwd(spectrum, white);
    for (long long k = 0; k < length_; ++k) spectrum[k] *= amplitude_[k];
    std::vector<double> y;
    fft.inv(y, spectrum);
    Eigen::VectorXd out(n_);
    for (long long i = 0; i < n_; ++i) out[i] = y[i];
    return out;
  }

  /// The exact Allan variance at averaging factor m [rate^2] (see the header).
  double TrueAllanVariance(long long m) const { return Sum(m, 4, 2, 2.0); }

  /// The exact Hadamard variance (1/6) E[(third difference of m-averages)^2] [rate^2]: the
  /// difference's transfer function is |1 - e^{-2 pi i f m}|^6 / m^2 times the average's, so
  /// |H|^2 / 6 = (8 / 3) sin^6(pi f m) / (m^2 sin^2(pi f)).
  double TrueHadamardVariance(long long m) const { return Sum(m, 6, 2, 8.0 / 3.0); }

  /// The exact modified Allan variance E[(mean over m starts of the phase's second difference at
  /// lag m)^2] / (2 m^2) [rate^2]: the m-start mean adds sin^2(pi f m) / (m^2 sin^2(pi f)) to the
  /// Allan variance's transfer function, 2 sin^6(pi f m) / (m^4 sin^4(pi f)).
  double TrueModifiedAllanVariance(long long m) const {
    const double md = static_cast<double>(m);
    return Sum(m, 6, 4, 2.0) / (md * md);
  }

 private:
  // (1 / L) sum_k S(k / L) c sin^p(pi f m) / (m^2 sin^q(pi f)).
  double Sum(long long m, int p, int q, double c) const {
    constexpr double kPi = 3.14159265358979323846;
    long double sum = 0.0L;
    const double md = static_cast<double>(m);
    for (long long k = 1; k < length_; ++k) {
      const double f = static_cast<double>(k) / length_;
      const double s1 = std::sin(kPi * f * md), s = std::sin(kPi * f);
      sum += spectrum_[k] * c * std::pow(s1, p) / (md * md * std::pow(s, q));
    }
    return static_cast<double>(sum / length_);
  }

 public:
 private:
  std::vector<PowerLawTerm> terms_;
  long long n_ = 0;
  long long length_ = 0;
  std::vector<double> amplitude_, spectrum_;
};

}  // namespace fogpipe::allan::testing
