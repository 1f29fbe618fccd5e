// Test-only wrapper over algorithms/simulation (the project's simulator, written independently of
// this domain): rate noise with known IEEE 952 terms, each term from its own seeded stream.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "algorithms/simulation/flicker_noise.h"
#include "algorithms/simulation/noise_generators.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::allan::testing {

/// SI amplitudes of the five IEEE terms.
struct GyroTruth {
  double q_rad = 0.0, n_rad_sqrt_s = 0.0, b_rad_s = 0.0, k_rad_s_sqrt_s = 0.0, r_rad_s2 = 0.0;
};

/// Rate samples [rad/s] whose Allan variance is the IEEE 952 model of `truth` (see
/// noise_generators.h and flicker_noise.h for the conventions: white angle noise differenced for Q,
/// white rate for N, Kasdin's 1/f filter for B, a random walk for K, the ramp R t).
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
    rate += terms[k].generate(n, sample_rate_hz, terms[k].amplitude, &rng);
  }
  return rate;
}

}  // namespace fogpipe::allan::testing
