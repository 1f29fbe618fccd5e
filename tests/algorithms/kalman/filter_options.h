// Test support: AR models and filter option sets of the kalman tests.
#pragma once

#include <Eigen/Core>
#include <initializer_list>

#include "algorithms/kalman/ar_kalman.h"

namespace fogpipe::kalman::testing {

inline Eigen::VectorXd Phi(std::initializer_list<double> v) {
  Eigen::VectorXd phi(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double c : v) phi[i++] = c;
  return phi;
}

inline ArKalmanOptions Explicit(double q, double r) {
  ArKalmanOptions o;
  o.q = q;
  o.r = r;
  return o;
}

// The paper's start, P(0|0) = var(z) I (docs/method.md, eq. 7), the default.
inline ArKalmanOptions PaperStart(double q, double r) {
  ArKalmanOptions o = Explicit(q, r);
  o.initial_covariance = InitialCovariance::kSampleVariance;
  return o;
}

// The steady-state start, P(0|0) = the DARE's P(k|k).
inline ArKalmanOptions SteadyStart(double q, double r) {
  ArKalmanOptions o = Explicit(q, r);
  o.initial_covariance = InitialCovariance::kSteadyState;
  return o;
}

}  // namespace fogpipe::kalman::testing
