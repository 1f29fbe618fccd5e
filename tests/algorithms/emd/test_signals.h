// Deterministic test signals for the EMD tests and benchmark: seeded std::mt19937_64 and our own
// Box-Muller transform (std::normal_distribution is implementation-defined).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <random>

namespace fogpipe::emd::testing {

/// N(0, 1) white noise, identical on every platform for a given seed.
inline Eigen::VectorXd WhiteNoise(int n, uint64_t seed) {
  std::mt19937_64 engine(seed);
  // 53 random bits -> uniform in (0, 1]; 1 - u avoids log(0).
  auto uniform = [&engine]() { return ((engine() >> 11) + 1.0) * 0x1.0p-53; };
  Eigen::VectorXd x(n);
  const double two_pi = 6.283185307179586476925;
  for (int i = 0; i < n; i += 2) {
    const double radius = std::sqrt(-2.0 * std::log(uniform()));
    const double angle = two_pi * uniform();
    x[i] = radius * std::cos(angle);
    if (i + 1 < n) x[i + 1] = radius * std::sin(angle);
  }
  return x;
}

/// A gyro-like rate record: white noise (angle random walk), a random walk (rate random walk), a
/// slow sinusoid (thermal cycling) and a ramp, in rad/s-like magnitudes.
inline Eigen::VectorXd GyroLike(int n, uint64_t seed) {
  const Eigen::VectorXd w = WhiteNoise(n, seed);
  const Eigen::VectorXd v = WhiteNoise(n, seed + 1);
  Eigen::VectorXd x(n);
  double walk = 0.0;
  for (int i = 0; i < n; ++i) {
    walk += 1e-3 * v[i];
    x[i] = 7.3e-5 + 1e-4 * w[i] + 1e-5 * walk + 2e-5 * std::sin(2e-3 * i) + 1e-9 * i;
  }
  return x;
}

}  // namespace fogpipe::emd::testing
