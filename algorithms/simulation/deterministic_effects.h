// The deterministic effects of the catalog (SI, rad/s), sampled at t_k = k / sample_rate_hz.
//
// Thermal effects are driven by the true (noise-free) temperature and its analytic derivative
// (temperature_profile.h), so that the truth is exactly known. The temperature_rate term models the
// Shupe effect of a fiber coil: a time-varying radial temperature gradient makes
// counter-propagating waves see different path changes, a bias proportional to dT/dt (Shupe 1980,
// Appl. Opt. 19(5)).
#pragma once

#include <Eigen/Core>

#include "algorithms/simulation/temperature_profile.h"

namespace fogpipe::simulation {

/// `temperature`: bias = coefficient * (T(t) - T_ref).
struct TemperatureEffect {
  double coefficient_rad_s_per_degC = 0.0;
  double reference_degC = 25.0;
};

/// `temperature_rate`: bias = coefficient * dT/dt.
struct TemperatureRateEffect {
  double coefficient_rad_s_per_degC_per_s = 0.0;
};

/// `bias_step`: the bias jumps by size_rad_s at time_s (samples with t_k >= time_s carry it).
struct BiasStep {
  double time_s = 0.0;
  double size_rad_s = 0.0;
};

/// `warmup`: the start-up transient A exp(-t / tau).
struct Warmup {
  double amplitude_rad_s = 0.0;
  double time_constant_s = 600.0;
};

Eigen::VectorXd TemperatureEffectRate(const TemperatureEffect& effect,
                                      const TemperatureProfile& temperature, Eigen::Index n,
                                      double sample_rate_hz);
Eigen::VectorXd TemperatureRateEffectRate(const TemperatureRateEffect& effect,
                                          const TemperatureProfile& temperature, Eigen::Index n,
                                          double sample_rate_hz);
Eigen::VectorXd BiasStepRate(const BiasStep& step, Eigen::Index n, double sample_rate_hz);
Eigen::VectorXd WarmupRate(const Warmup& warmup, Eigen::Index n, double sample_rate_hz);

}  // namespace fogpipe::simulation
