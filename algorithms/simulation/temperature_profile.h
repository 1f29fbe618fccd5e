// The aux temperature of a simulated recording: a chamber-like cycle plus sensor noise.
//
// Thermal tests cycle a climatic chamber between two plateaus. The true temperature here is a
// smoothed trapezoid with a closed-form derivative,
//   T(t) = mean + (p-p / 2) g(theta),  theta = 2 pi t / period + phase,
//   g = tanh(s sin theta) / tanh(s)   (s > 0),   g = sin theta   (s = 0),
// where the sharpness s flattens the plateaus (s = 0: a sine; s = 2: ramps joined by rounded
// plateaus; s -> inf: a square wave). g spans exactly [-1, 1], so the peak-to-peak is exact.
// The temperature channel exists whether or not a thermal effect is simulated, so that `fogpipe
// compare` meets the same aux channels on effect-free recordings (its false alarms are measured
// there) as on thermal ones. Thermal effects use the true (noise-free) temperature and its
// analytic derivative; only the recorded channel carries the sensor noise.
#pragma once

#include <Eigen/Core>
#include <string>

#include "algorithms/simulation/random.h"

namespace fogpipe::simulation {

struct TemperatureProfile {
  double mean_degC = 25.0;
  /// Peak-to-peak swing of the true temperature.
  double peak_to_peak_degC = 8.0;
  double period_s = 5400.0;
  /// Plateau flatness s >= 0 (0 = sine).
  double sharpness = 2.0;
  /// Phase of the cycle at t = 0 (0: at the mean, rising).
  double phase_rad = 0.0;
  /// Standard deviation of the white sensor noise on the recorded channel.
  double noise_std_degC = 0.005;

  bool IsValid(std::string* error) const;
};

/// True temperature at time t_s.
double TrueTemperature(const TemperatureProfile& profile, double t_s);
/// True dT/dt at time t_s, in degC/s.
double TrueTemperatureRate(const TemperatureProfile& profile, double t_s);
/// max over t of |dT/dt| (degC/s), reached when the cycle crosses its mean:
/// (p-p / 2) (2 pi / period) s / tanh(s)  (-> (p-p / 2) (2 pi / period) for the sine).
double MaxAbsTemperatureRate(const TemperatureProfile& profile);

/// The true temperature sampled at t_k = k / sample_rate_hz.
Eigen::VectorXd SampleTrueTemperature(const TemperatureProfile& profile, Eigen::Index n,
                                      double sample_rate_hz);
/// The true temperature rate (degC/s) sampled at t_k.
Eigen::VectorXd SampleTrueTemperatureRate(const TemperatureProfile& profile, Eigen::Index n,
                                          double sample_rate_hz);

}  // namespace fogpipe::simulation
