// The constant-gain (steady-state) AR Kalman loop, the hot path of fogpipe's filtering:
//
//   pred = phi' x(k-1),  e(k) = z(k) - mean - pred,  x(k) = A x(k-1) + G e(k),  out(k) = x_0(k) +
//   mean
//
// with A the companion matrix (a shift plus one dot product). No Eigen temporaries per sample;
// orders 1..8 use fixed-size kernels whose state lives in registers.
//
// Latency, not arithmetic, limits this loop: every prediction needs the previous update. The fixed
// kernels therefore carry pred(k+1) = phi_0 pred(k) + c(k-1) + kappa e(k), with
// kappa = phi' G and c(k-1) = sum_{i>=1} phi_i x_{i-1}(k-1) (known one step early), which is
// phi' x(k) regrouped: x_0(k) = pred(k) + G_0 e(k) and x_i(k) = x_{i-1}(k-1) + G_i e(k). The state
// itself is updated exactly as in the time-varying filter.
#pragma once

#include <Eigen/Core>

namespace fogpipe::kalman {

/// Runs the loop over n samples of z. `state` (size p) is X(k-1|k-1) on entry and X(n-1|n-1) on
/// return. `filtered` receives n estimates of x(k); `innovations`, if not null, the n e(k) (for
/// the smoother). phi and gain have size p >= 1.
void SteadyStateFilter(const double* z, long long n, double mean, const Eigen::VectorXd& phi,
                       const Eigen::VectorXd& gain, Eigen::VectorXd* state, double* filtered,
                       double* innovations);

}  // namespace fogpipe::kalman
