// Test-only generator of gyro rate noise with known IEEE 952 terms (until algorithms/simulation
// lands on main). Deterministic: std::mt19937_64 with an explicit seed and our own Box-Muller.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <random>
#include <unsupported/Eigen/FFT>
#include <vector>

namespace fogpipe::allan::testing {

class NormalSource {
 public:
  explicit NormalSource(std::uint64_t seed) : engine_(seed) {}
  double Next() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    // Uniforms in (0, 1] from the top 53 bits.
    const double u1 = (static_cast<double>(engine_() >> 11) + 1.0) * 0x1.0p-53;
    const double u2 = (static_cast<double>(engine_() >> 11) + 1.0) * 0x1.0p-53;
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double phi = 2.0 * 3.14159265358979323846 * u2;
    spare_ = r * std::sin(phi);
    has_spare_ = true;
    return r * std::cos(phi);
  }

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

/// SI amplitudes of the five IEEE terms.
struct GyroTruth {
  double q_rad = 0.0, n_rad_sqrt_s = 0.0, b_rad_s = 0.0, k_rad_s_sqrt_s = 0.0, r_rad_s2 = 0.0;
};

/// Rate samples [rad/s] at sample_rate_hz whose Allan variance is the IEEE 952 model of `truth`:
///  - Q: white angle noise of standard deviation Q, differentiated (sigma^2 = 3 Q^2 / tau^2 exactly
///    for the overlapping estimator);
///  - N: white rate noise of standard deviation N / sqrt(dt) (two-sided PSD N^2);
///  - B: Kasdin's (1992) 1/f filter h_0 = 1, h_k = h_{k-1} (k - 1/2) / k on white noise of standard
///    deviation B (two-sided PSD B dt / (2 sin(pi f dt)) ~ B^2 / (2 pi f), IEEE 952's flicker form,
///    whose Allan variance is the flat (2 ln2 / pi) B^2), applied by FFT convolution;
///  - K: random walk of rate with steps K sqrt(dt) (sigma^2 = K^2 tau / 3 + K^2 dt / (6 m));
///  - R: the deterministic ramp R t.
inline Eigen::VectorXd SimulateGyro(const GyroTruth& truth, long long n, double sample_rate_hz,
                                    std::uint64_t seed) {
  const double dt = 1.0 / sample_rate_hz;
  NormalSource normal(seed);
  Eigen::VectorXd rate = Eigen::VectorXd::Zero(n);
  double previous_angle = truth.q_rad * normal.Next();
  double walk = 0.0;
  for (long long i = 0; i < n; ++i) {
    const double angle = truth.q_rad * normal.Next();
    walk += truth.k_rad_s_sqrt_s * std::sqrt(dt) * normal.Next();
    rate[i] = (angle - previous_angle) / dt + truth.n_rad_sqrt_s / std::sqrt(dt) * normal.Next() +
              walk + truth.r_rad_s2 * (static_cast<double>(i) * dt);
    previous_angle = angle;
  }
  if (truth.b_rad_s > 0.0) {
    size_t size = 1;
    while (size < static_cast<size_t>(2 * n)) size <<= 1;
    std::vector<double> h(size, 0.0), w(size, 0.0);
    h[0] = 1.0;
    for (long long k = 1; k < n; ++k) h[k] = h[k - 1] * (static_cast<double>(k) - 0.5) / k;
    for (long long k = 0; k < n; ++k) w[k] = truth.b_rad_s * normal.Next();
    Eigen::FFT<double> fft;
    std::vector<std::complex<double>> hf, wf;
    fft.fwd(hf, h);
    fft.fwd(wf, w);
    for (size_t k = 0; k < hf.size(); ++k) wf[k] *= hf[k];
    std::vector<double> flicker;
    fft.inv(flicker, wf);
    for (long long i = 0; i < n; ++i) rate[i] += flicker[i];
  }
  return rate;
}

}  // namespace fogpipe::allan::testing
