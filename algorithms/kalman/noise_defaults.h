// Default process and measurement noise for the AR Kalman filter, without double counting.
//
// The AR model handed to the filter was fitted to the measured series z = x + v (x: the signal the
// AR model describes, v: white measurement noise of variance R). Its innovation variance
// sigma_e^2 is the one-step prediction-error variance of z, so it already contains the measurement
// noise: for z, the one-step prediction error is x's unpredictable part plus v's. The naive choice
// q = sigma_e^2 together with R = white-noise level therefore counts the noise twice; the filter's
// model then implies a prediction-error variance of z of at least sigma_e^2 + R (H P H' >= q since
// P = A P(k|k) A' + Q), more than the data show.
//
// The rule used here keeps the model consistent with both numbers the data give:
//   1. R = the white-noise floor of z (per-sample variance), e.g. from the Allan deviation's
//      angle-random-walk coefficient, R = N^2 f_s (WhiteNoiseVarianceFromArw);
//   2. q is the value for which the Kalman filter's steady-state innovation variance equals the AR
//      innovation variance:  S(q) = H P(q) H' + R = sigma_e^2,  P(q) the DARE solution (riccati.h).
// S(q) is the exact one-step prediction-error variance of z under the state-space model (the
// innovations form of the steady-state Kalman filter; Anderson & Moore 1979, "Optimal Filtering",
// ch. 4), so the rule is the moment match between the model and the AR fit. S is increasing in q
// and S(q) >= q + R, so the root lies in [0, sigma_e^2 - R] and is found by the Illinois (modified
// regula falsi) method. If sigma_e^2 <= R the data show no prediction error above the white floor:
// q = 0, flagged in the message.
#pragma once

#include <Eigen/Core>
#include <string>

#include "algorithms/common/status.h"
#include "algorithms/kalman/riccati.h"

namespace fogpipe::kalman {

struct DefaultNoiseOptions {
  /// Stop when the bracket on q is below relative_tolerance * q or S(q) matches sigma_e^2 to it.
  double relative_tolerance = 1e-12;
  int max_iterations = 200;
  DareOptions dare;

  bool IsValid(std::string* error) const;
};

struct DefaultNoiseSummary {
  Termination termination = Termination::kInvalidOptions;
  std::string message;
  int iterations = 0;  ///< Root-finding iterations (one DARE solve each).
  bool q_clamped_to_zero = false;
};

struct DefaultNoiseResult {
  double q = 0.0;  ///< Process-noise variance, units of x^2.
  double r = 0.0;  ///< Measurement-noise variance (the white-noise variance given), units of x^2.
  /// H P H' + R at the returned q; equals the AR innovation variance unless q was clamped.
  double implied_innovation_variance = 0.0;
  DefaultNoiseSummary summary;
};

/// The rule above. phi: AR recursion coefficients (x_k = sum phi_i x_{k-i} + e_k);
/// innovation_variance: sigma_e^2 of the AR fit; white_noise_variance: R. Both in units of x^2.
DefaultNoiseResult DefaultNoise(const Eigen::VectorXd& phi, double innovation_variance,
                                double white_noise_variance,
                                const DefaultNoiseOptions& options = DefaultNoiseOptions());

/// Per-sample variance of white rate noise with angle random walk N (rad/sqrt(s)) sampled at
/// f_s (Hz): the Allan variance of white rate noise is N^2 / tau (IEEE Std 952-1997, Annex C) and
/// equals the per-sample variance at tau = 1 / f_s, so R = N^2 f_s, in (rad/s)^2.
double WhiteNoiseVarianceFromArw(double arw_rad_per_sqrt_s, double sample_rate_hz);

}  // namespace fogpipe::kalman
