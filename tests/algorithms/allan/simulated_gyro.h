// Test-only wrapper over algorithms/simulation (the project's simulator, written independently of
// this domain): rate noise with known IEEE 952 terms, each term from its own seeded stream.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <unsupported/Eigen/FFT>
#include <vector>

#include "algorithms/simulation/flicker_noise.h"
#include "algorithms/simulation/noise_generators.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::allan::testing {

/// How the bias-instability (flicker) term is sampled.
enum class FlickerSampling {
  /// Kasdin's discrete 1/f filter (the project's simulator, flicker_noise.h). Its Allan variance is
  /// the IEEE floor only for m >> 1: 1.44x at m = 1, 1.15x at 2, 1.05x at 4, 1.015x at 8.
  kKasdin,
  /// What an integrating gyro outputs: each sample the mean over its period of continuous rate
  /// noise with PSD B^2 / (2 pi f); its Allan variance is the IEEE floor at every m
  /// (IntegratedFlickerRate). This is the process the fit's model and covariance describe.
  kIntegrated,
};

/// SI amplitudes of the five IEEE terms.
struct GyroTruth {
  double q_rad = 0.0, n_rad_sqrt_s = 0.0, b_rad_s = 0.0, k_rad_s_sqrt_s = 0.0, r_rad_s2 = 0.0;
  FlickerSampling flicker = FlickerSampling::kKasdin;
};

/// Autocovariance, per unit B^2 [(rad/s)^2], of the sample-to-sample increments
/// d_k = y_k - y_{k-1} of the integrated flicker rate at lag l (samples). With phase x (the
/// integrated rate, t0 = 1) y_k = x_{k+1} - x_k, so d_k is the second difference of x and
/// gamma(l) = sum_{j=-2..2} (1, -4, 6, -4, 1)_j R(l + j), R(u) = u^2 ln|u| / (2 pi) the generalised
/// autocovariance of flicker-FM phase (Greenhall & Riley 2003, eq. 7; its Allan variance is
/// gamma(0) / 2 = (2 ln2 / pi) B^2 at m = 1). For |l| >= 32 the fourth difference cancels
/// catastrophically in double precision; there the central-difference expansion
/// delta^4 = D^4 + D^6 / 6 + D^8 / 80 + 17 D^10 / 30240 applied to u^2 ln u (D^4 = -2 / u^2,
/// D^6 = -12 / u^4, D^8 = -240 / u^6, D^10 = -10080 / u^8) gives
/// gamma = -(1/pi) (1/l^2 + 1/l^4 + 1.5/l^6 + (17/6)/l^8), relative error < 1e-11 there (the
/// direct difference below 32: < 2e-9).
inline double FlickerIncrementCovariance(double lag) {
  const double l = std::abs(lag);
  if (l >= 32.0) {
    const double u = 1.0 / (l * l);
    return -(u + u * u + 1.5 * u * u * u + 17.0 / 6.0 * u * u * u * u) / 3.14159265358979323846;
  }
  const auto r = [](double v) {
    return v == 0.0 ? 0.0 : v * v * std::log(std::abs(v)) / (2.0 * 3.14159265358979323846);
  };
  return r(l - 2.0) - 4.0 * r(l - 1.0) + 6.0 * r(l) - 4.0 * r(l + 1.0) + r(l + 2.0);
}

/// Flicker rate noise [rad/s] as an integrating gyro samples it: y_k = mean over [k t0, (k+1) t0]
/// of continuous rate noise with two-sided PSD B^2 / (2 pi f). The increments d_k are stationary
/// with autocovariance B^2 gamma(l) (FlickerIncrementCovariance), drawn exactly by circulant
/// embedding (Davies & Harte, Biometrika 74, 1987; Dietrich & Newsam, SIAM J. Sci. Comput. 18,
/// 1997): embed gamma(0..K) in a circulant of size 2K >= 2(n - 1), whose eigenvalues lambda are
/// its FFT; if all are >= 0 (checked: the smallest is lambda_0, about 2 / (pi K) > 0),
/// Re FFT(sqrt(lambda / 2K) (z1 + i z2)) has exactly that covariance. y_0 = 0 and y is their
/// running sum (the flicker level is undefined; every Allan statistic uses increments only).
/// Unlike Kasdin's discrete filter, its Allan variance is the IEEE floor (2 ln2 / pi) B^2 at every
/// averaging factor, m = 1 included, and its Allan covariance is avar_covariance.h's flicker model.
inline Eigen::VectorXd IntegratedFlickerRate(Eigen::Index n, double b_rad_s,
                                             fogpipe::simulation::RandomSource* rng) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(n);
  if (n < 2) return y;
  const Eigen::Index size = fogpipe::simulation::FastFftSize(2 * (n - 1));
  const Eigen::Index half = size / 2;
  Eigen::FFT<double> fft;
  // The eigenvalues depend on the size only; the calibration draws hundreds of equal records.
  static thread_local Eigen::Index cached_size = 0;
  static thread_local std::vector<double> lambda;
  if (cached_size != size) {
    std::vector<std::complex<double>> row(static_cast<size_t>(size)), eig;
    for (Eigen::Index k = 0; k <= half; ++k)
      row[static_cast<size_t>(k)] = FlickerIncrementCovariance(static_cast<double>(k));
    for (Eigen::Index k = half + 1; k < size; ++k)
      row[static_cast<size_t>(k)] = row[static_cast<size_t>(size - k)];
    fft.fwd(eig, row);
    lambda.resize(static_cast<size_t>(size));
    for (size_t j = 0; j < lambda.size(); ++j) {
      if (!(eig[j].real() > 0.0)) {
        std::fprintf(stderr, "IntegratedFlickerRate: circulant embedding not positive at %zu\n", j);
        std::abort();
      }
      lambda[j] = std::sqrt(eig[j].real() / static_cast<double>(size));
    }
    cached_size = size;
  }
  std::vector<std::complex<double>> w(static_cast<size_t>(size)), d;
  for (size_t j = 0; j < w.size(); ++j) {
    const double re = rng->Normal(), im = rng->Normal();
    w[j] = {lambda[j] * re, lambda[j] * im};
  }
  fft.fwd(d, w);
  for (Eigen::Index k = 1; k < n; ++k)
    y[k] = y[k - 1] + b_rad_s * d[static_cast<size_t>(k - 1)].real();
  return y;
}

/// Rate samples [rad/s] whose Allan variance is the IEEE 952 model of `truth` (see
/// noise_generators.h and flicker_noise.h for the conventions: white angle noise differenced for Q,
/// white rate for N, Kasdin's 1/f filter or IntegratedFlickerRate for B (truth.flicker), a random
/// walk for K, the ramp R t).
inline Eigen::VectorXd SimulateGyro(const GyroTruth& truth, long long n, double sample_rate_hz,
                                    std::uint64_t seed) {
  namespace sim = fogpipe::simulation;
  using Generator = Eigen::VectorXd (*)(Eigen::Index, double, double, sim::RandomSource*);
  const struct {
    double amplitude;
    Generator generate;
  } terms[] = {{truth.q_rad, sim::QuantizationRateNoise},
               {truth.n_rad_sqrt_s, sim::WhiteRateNoise},
               {truth.b_rad_s, sim::FlickerRateNoise},
               {truth.k_rad_s_sqrt_s, sim::RateRandomWalk}};
  Eigen::VectorXd rate = sim::RateRamp(n, sample_rate_hz, truth.r_rad_s2);
  for (std::uint64_t k = 0; k < 4; ++k) {
    if (!(terms[k].amplitude > 0.0)) continue;
    sim::RandomSource rng(sim::DeriveSeed(seed, k + 1));  // one stream per term
    if (k == 2 && truth.flicker == FlickerSampling::kIntegrated)
      rate += IntegratedFlickerRate(n, terms[k].amplitude, &rng);
    else
      rate += terms[k].generate(n, sample_rate_hz, terms[k].amplitude, &rng);
  }
  return rate;
}

}  // namespace fogpipe::allan::testing
