// Generators of the stochastic gyro error terms, one sample per rate sample (SI: rad/s).
//
// Conventions are those of IEEE Std 952-1997, Annex C (two-sided PSDs), so that each term has the
// textbook Allan variance sigma^2(tau). Sample k covers [k dt, (k+1) dt) and is stamped t_k = k dt,
// dt = 1 / sample_rate_hz. Bias instability (flicker noise) is in flicker_noise.h.
#pragma once

#include <Eigen/Core>

#include "algorithms/simulation/random.h"

namespace fogpipe::simulation {

/// White rate noise (angle random walk N, rad/sqrt(s)): independent samples of standard deviation
/// N sqrt(fs), i.e. two-sided PSD N^2, so that sigma^2(tau) = N^2 / tau.
Eigen::VectorXd WhiteRateNoise(Eigen::Index n, double sample_rate_hz, double n_rad_sqrt_s,
                               RandomSource* rng);

/// Quantization noise (Q, rad) as white *angle* noise e_k of standard deviation Q, differenced to
/// rate: w_k = (e_k - e_{k-1}) fs, with e_{-1} drawn too so the sequence is stationary. The
/// averaged rate over tau = m dt is (e_{k+m} - e_k) / tau, hence sigma^2(tau) = 3 Q^2 / tau^2
/// exactly (IEEE Std 952-1997 C.2). This is the model behind the Allan figure; a real angle
/// quantizer only reaches it when the angle crosses many steps between samples (see QuantizeAngle).
Eigen::VectorXd QuantizationRateNoise(Eigen::Index n, double sample_rate_hz, double q_rad,
                                      RandomSource* rng);

/// A physical angle quantizer: integrates the rate to angle (starting at 0), rounds the angle to a
/// multiple of step_rad and differences back to rate, so every output sample is an integer multiple
/// of step_rad * fs and the integrated output angle is always on the grid. The quantization error
/// is uniform with variance step^2 / 12 only when the angle moves by well over one step per sample
/// (Widrow & Kollar 2008, ch. 4); then Q = step / sqrt(12). With slow angles the error is
/// correlated and the Allan curve departs from 3 Q^2 / tau^2.
Eigen::VectorXd QuantizeAngle(const Eigen::VectorXd& rate_rad_s, double sample_rate_hz,
                              double step_rad);

/// Rate random walk (K, rad/s/sqrt(s)): x_k = x_{k-1} + K sqrt(dt) w_k with x_{-1} = 0, i.e. a
/// two-sided PSD K^2 / (2 pi f)^2, so that sigma^2(tau) = K^2 tau / 3.
Eigen::VectorXd RateRandomWalk(Eigen::Index n, double sample_rate_hz, double k_rad_s_sqrt_s,
                               RandomSource* rng);

/// Rate ramp (R, rad/s^2): R t_k, so that sigma^2(tau) = R^2 tau^2 / 2.
Eigen::VectorXd RateRamp(Eigen::Index n, double sample_rate_hz, double r_rad_s2);

/// First-order Gauss-Markov rate (stationary standard deviation sigma, correlation time Tc), by the
/// exact discretisation x_{k+1} = e^{-dt/Tc} x_k + sigma sqrt(1 - e^{-2 dt/Tc}) w_k, started in its
/// stationary distribution (x_0 = sigma w_0). Lag-1 autocorrelation e^{-dt/Tc}.
Eigen::VectorXd GaussMarkov(Eigen::Index n, double sample_rate_hz, double sigma_rad_s,
                            double correlation_time_s, RandomSource* rng);

/// Sinusoidal rate W sin(2 pi f0 t_k + phase).
Eigen::VectorXd SinusoidalRate(Eigen::Index n, double sample_rate_hz, double frequency_hz,
                               double amplitude_rad_s, double phase_rad);

}  // namespace fogpipe::simulation
