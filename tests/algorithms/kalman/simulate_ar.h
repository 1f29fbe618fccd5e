// Test support: seeded simulation of an AR(p) signal observed in white noise, z = x + v,
// x(k) = sum_i phi_i x(k-i) + w(k), w ~ N(0, q), v ~ N(0, r). Normals from
// fogpipe::simulation::RandomSource (seeded std::mt19937_64 + Marsaglia's polar method), so the
// realisations are the same on every platform.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

#include "algorithms/simulation/random.h"

namespace fogpipe::kalman::testing {

struct ArSimulation {
  Eigen::VectorXd x;  ///< The true AR signal.
  Eigen::VectorXd z;  ///< The measurement x + v.
};

/// n samples after a burn-in of `burn_in` samples (so the AR signal is stationary).
inline ArSimulation SimulateArPlusNoise(const Eigen::VectorXd& phi, double q, double r, long long n,
                                        std::uint64_t seed, long long burn_in = 10000) {
  simulation::RandomSource source(seed);
  const Eigen::Index p = phi.size();
  Eigen::VectorXd hist = Eigen::VectorXd::Zero(p);  // x(k-1), ..., x(k-p)
  ArSimulation sim;
  sim.x.resize(n);
  sim.z.resize(n);
  const double sq = std::sqrt(q), sr = std::sqrt(r);
  for (long long k = -burn_in; k < n; ++k) {
    const double xk = phi.dot(hist) + sq * source.Normal();
    for (Eigen::Index i = p - 1; i >= 1; --i) hist[i] = hist[i - 1];
    hist[0] = xk;
    const double zk = xk + sr * source.Normal();
    if (k >= 0) {
      sim.x[k] = xk;
      sim.z[k] = zk;
    }
  }
  return sim;
}

/// Relative standard error of a sample variance of a zero-mean stationary series e with n samples,
/// accounting for autocorrelation (Bartlett 1946): var(s^2) / sigma^4 ~= (2 / n) sum_h rho(h)^2,
/// the sum over all lags, estimated up to max_lag.
inline double RelativeStandardErrorOfVariance(const Eigen::VectorXd& e, int max_lag) {
  const Eigen::Index n = e.size();
  const double c0 = e.squaredNorm() / n;
  double sum = 1.0;
  for (int h = 1; h <= max_lag; ++h) {
    const double ch = e.head(n - h).dot(e.tail(n - h)) / n;
    sum += 2.0 * (ch / c0) * (ch / c0);
  }
  return std::sqrt(2.0 * sum / n);
}

}  // namespace fogpipe::kalman::testing
