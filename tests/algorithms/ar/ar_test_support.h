// Test support for the AR tests: seeded Gaussian noise and AR(p) simulation with burn-in.
// The noise comes from algorithms/simulation (written apart from the AR code).
// Header-only; used only by tests/algorithms/ar and tests/benchmarks/ar_benchmark.cpp.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

#include "algorithms/simulation/random.h"

namespace fogpipe::ar::testing {

/// The paper's imf6 AR(4) (Liu et al. 2018, Table 2, a_i negated): two lightly damped resonators,
/// roots of modulus 0.9965 and 0.9706 at periods of ~66 and ~61 samples.
inline Eigen::VectorXd PaperImf6Phi() {
  Eigen::VectorXd phi(4);
  phi << 3.9151, -5.7665, 3.7869, -0.9356;
  return phi;
}

/// Seeded Gaussian noise from the project's simulator (simulation::RandomSource: std::mt19937_64 +
/// Marsaglia's polar method, portable unlike std::normal_distribution).
inline Eigen::VectorXd WhiteNoise(Eigen::Index n, double sigma, std::uint64_t seed) {
  simulation::RandomSource normal(seed);
  return sigma * normal.Normals(n);
}

/// x_t = mean + s_t, s_t = sum phi_i s_{t-i} + sigma e_t, after `burn_in` discarded samples that
/// start from zero, so the start-up transient has decayed (choose burn_in >> 1 / (1 - max |root|)).
inline Eigen::VectorXd SimulateAr(const Eigen::VectorXd& phi, double sigma, Eigen::Index n,
                                  std::uint64_t seed, Eigen::Index burn_in = 20000,
                                  double mean = 0.0) {
  const Eigen::Index p = phi.size();
  simulation::RandomSource normal(seed);
  Eigen::VectorXd s = Eigen::VectorXd::Zero(n + burn_in);
  for (Eigen::Index t = 0; t < n + burn_in; ++t) {
    double v = sigma * normal.Normal();
    for (Eigen::Index i = 1; i <= p && i <= t; ++i) v += phi(i - 1) * s(t - i);
    s(t) = v;
  }
  return s.tail(n).array() + mean;
}

/// Autocovariances gamma(0..max_lag) of the stationary AR(p) with unit innovation variance, summed
/// from its MA(infinity) weights psi (Box, Jenkins & Reinsel eq. 3.1.x): gamma(k) = sum_j psi_j
/// psi_{j+k}. Independent of any Levinson / Yule-Walker code. Truncated where |psi| < 1e-18 max.
inline Eigen::VectorXd TheoreticalAutocovariance(const Eigen::VectorXd& phi, int max_lag) {
  const Eigen::Index p = phi.size();
  const Eigen::Index len = 400000;
  Eigen::VectorXd psi = Eigen::VectorXd::Zero(len);
  psi(0) = 1.0;
  Eigen::Index used = len;
  for (Eigen::Index k = 1; k < len; ++k) {
    double v = 0.0;
    for (Eigen::Index i = 1; i <= p && i <= k; ++i) v += phi(i - 1) * psi(k - i);
    psi(k) = v;
    if (k > 10 * p + 1000 && psi.segment(k - p, p + 1).cwiseAbs().maxCoeff() < 1e-18) {
      used = k + 1;
      break;
    }
  }
  Eigen::VectorXd gamma(max_lag + 1);
  for (int k = 0; k <= max_lag; ++k) gamma(k) = psi.head(used - k).dot(psi.segment(k, used - k));
  return gamma;
}

}  // namespace fogpipe::ar::testing
