#include "algorithms/simulation/deterministic_effects.h"

#include <cmath>

namespace fogpipe::simulation {

Eigen::VectorXd TemperatureEffectRate(const TemperatureEffect& effect,
                                      const TemperatureProfile& temperature, Eigen::Index n,
                                      double sample_rate_hz) {
  return (SampleTrueTemperature(temperature, n, sample_rate_hz).array() - effect.reference_degC) *
         effect.coefficient_rad_s_per_degC;
}

Eigen::VectorXd TemperatureRateEffectRate(const TemperatureRateEffect& effect,
                                          const TemperatureProfile& temperature, Eigen::Index n,
                                          double sample_rate_hz) {
  return SampleTrueTemperatureRate(temperature, n, sample_rate_hz) *
         effect.coefficient_rad_s_per_degC_per_s;
}

Eigen::VectorXd BiasStepRate(const BiasStep& step, Eigen::Index n, double sample_rate_hz) {
  Eigen::VectorXd out(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    out[k] = k / sample_rate_hz >= step.time_s ? step.size_rad_s : 0.0;
  }
  return out;
}

Eigen::VectorXd WarmupRate(const Warmup& warmup, Eigen::Index n, double sample_rate_hz) {
  Eigen::VectorXd out(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    out[k] = warmup.amplitude_rad_s * std::exp(-(k / sample_rate_hz) / warmup.time_constant_s);
  }
  return out;
}

}  // namespace fogpipe::simulation
