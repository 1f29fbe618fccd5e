// Fixed-interval Rauch-Tung-Striebel smoother for the AR(p) Kalman filter (Rauch, Tung & Striebel
// 1965, AIAA J. 3(8)).
//
// The smoother is run in its adjoint ("modified Bryson-Frazier") form, which gives the same
// estimates as the RTS recursion x(k|N) = x(k|k) + C(k) (x(k+1|N) - x(k+1|k)) in exact arithmetic
// (Bierman 1977, "Factorization Methods for Discrete Sequential Estimation", ch. X; de Jong 1989,
// J. Am. Stat. Assoc. 84; Durbin & Koopman 2012, sec. 4.4):
//
//   r(k-1) = H' e(k) / S(k) + L(k)' r(k),  r(N) = 0,  L(k) = A (I - G(k) H),
//   x(k|N) = x(k|k-1) + P(k|k-1) r(k-1).
//
// Only x_0 is wanted, and P(k|k-1) H' = S(k) G(k), so x_0(k|N) = z(k) - e(k) + S(k) G(k)' r(k-1):
// the backward pass needs the innovations e(k) (one double per sample, overwritten in place by the
// smoothed values) and the gains, which are constant once the filter has switched to steady state.
// The RTS form would store the p-dimensional filtered state and a covariance per sample.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "algorithms/kalman/riccati.h"

namespace fogpipe::kalman {

/// The gains of a filter run: one column G(k) and S(k) per time-varying step k < switch, then the
/// steady-state gain and innovation variance for every later step.
struct FilterGainHistory {
  long long time_varying_steps = 0;
  std::vector<double> time_varying_gains;  ///< p * time_varying_steps, column k at p * k.
  std::vector<double> time_varying_innovation_variances;  ///< S(k), units of x^2.
  Eigen::VectorXd steady_state_gain;
  double steady_state_innovation_variance = 0.0;
};

/// Backward pass. On entry `innovations_to_smoothed` holds e(k); on return x_0(k|N) + mean.
/// z is the measured series, mean the AR model mean removed before filtering.
void RtsSmoothInPlace(const Eigen::Ref<const Eigen::VectorXd>& z, double mean,
                      const Eigen::VectorXd& phi, const FilterGainHistory& gains,
                      Eigen::VectorXd* innovations_to_smoothed);

/// H P(k|N) H' far from both ends of the record, with the steady-state gain:
/// P(k|N) = P - P N P, N = H'H / S + L' N L, L = A (I - G H) (the same recursion as above for
/// the covariance), N solved by Smith's doubling N <- N + M' N M, M <- M M. Returns NaN if L is not
/// stable (the doubling does not converge within 64 steps).
double SteadyStateSmoothedVariance(const Eigen::VectorXd& phi, const DareSolution& dare);

/// Whether the record contradicts the model in the direction that makes the smoother take noise
/// for signal. Under the state-space model, z(k) - x(k|k) = E[v(k) | z(1..k)] and
/// z(k) - x(k|N) = E[v(k) | z(1..N)], so by the law of total variance their mean squares are
/// R - P(k|k) <= R - P(k|N) at every k (Durbin & Koopman 2012, sec. 4.5.3, smoothed
/// disturbances): the smoother takes at least as much of the measurement for noise as the filter
/// does. When the smoothed residuals' mean square over the record is below the filtered ones',
/// the smoother follows z more closely than its own filter, which a correctly specified model does
/// not do in expectation; on EMD components whose AR model describes band-passed noise as signal
/// it does, and the smoother then loses to the filter (docs/filtering.md, "S5"). Both series
/// include the model mean; the means of the residual mean squares are returned in
/// *filtered_residual_ms and *smoothed_residual_ms (units of z^2).
bool SmootherContradictsModel(const Eigen::Ref<const Eigen::VectorXd>& z,
                              const Eigen::VectorXd& filtered, const Eigen::VectorXd& smoothed,
                              double* filtered_residual_ms, double* smoothed_residual_ms);

}  // namespace fogpipe::kalman
