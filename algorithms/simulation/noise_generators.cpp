#include "algorithms/simulation/noise_generators.h"

#include <cmath>

#include "algorithms/common/units.h"

namespace fogpipe::simulation {

Eigen::VectorXd WhiteRateNoise(Eigen::Index n, double sample_rate_hz, double n_rad_sqrt_s,
                               RandomSource* rng) {
  return rng->Normals(n) * (n_rad_sqrt_s * std::sqrt(sample_rate_hz));
}

Eigen::VectorXd QuantizationRateNoise(Eigen::Index n, double sample_rate_hz, double q_rad,
                                      RandomSource* rng) {
  Eigen::VectorXd out(n);
  double previous = q_rad * rng->Normal();  // e_{-1}
  for (Eigen::Index k = 0; k < n; ++k) {
    const double current = q_rad * rng->Normal();
    out[k] = (current - previous) * sample_rate_hz;
    previous = current;
  }
  return out;
}

Eigen::VectorXd QuantizeAngle(const Eigen::VectorXd& rate_rad_s, double sample_rate_hz,
                              double step_rad) {
  const double dt = 1.0 / sample_rate_hz;
  Eigen::VectorXd out(rate_rad_s.size());
  // Neumaier-compensated running sum: on a 24 h record the angle reaches many radians while the
  // per-sample increment may be below 1e-9 rad; plain summation would move the rounding grid.
  double angle = 0.0;
  double compensation = 0.0;
  double previous_count = 0.0;
  for (Eigen::Index k = 0; k < rate_rad_s.size(); ++k) {
    const double increment = rate_rad_s[k] * dt;
    const double sum = angle + increment;
    compensation += std::abs(angle) >= std::abs(increment) ? (angle - sum) + increment
                                                           : (increment - sum) + angle;
    angle = sum;
    const double count = std::round((angle + compensation) / step_rad);
    out[k] = (count - previous_count) * step_rad * sample_rate_hz;
    previous_count = count;
  }
  return out;
}

Eigen::VectorXd RateRandomWalk(Eigen::Index n, double sample_rate_hz, double k_rad_s_sqrt_s,
                               RandomSource* rng) {
  const double step_std = k_rad_s_sqrt_s / std::sqrt(sample_rate_hz);
  Eigen::VectorXd out(n);
  double x = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    x += step_std * rng->Normal();
    out[k] = x;
  }
  return out;
}

Eigen::VectorXd RateRamp(Eigen::Index n, double sample_rate_hz, double r_rad_s2) {
  return Eigen::VectorXd::LinSpaced(n, 0.0, static_cast<double>(n - 1)) *
         (r_rad_s2 / sample_rate_hz);
}

Eigen::VectorXd GaussMarkov(Eigen::Index n, double sample_rate_hz, double sigma_rad_s,
                            double correlation_time_s, RandomSource* rng) {
  const double phi = std::exp(-1.0 / (sample_rate_hz * correlation_time_s));
  // 1 - phi^2 via expm1 keeps precision when Tc spans many samples (phi close to 1).
  const double drive =
      sigma_rad_s * std::sqrt(-std::expm1(-2.0 / (sample_rate_hz * correlation_time_s)));
  Eigen::VectorXd out(n);
  if (n == 0) return out;
  double x = sigma_rad_s * rng->Normal();
  out[0] = x;
  for (Eigen::Index k = 1; k < n; ++k) {
    x = phi * x + drive * rng->Normal();
    out[k] = x;
  }
  return out;
}

Eigen::VectorXd SinusoidalRate(Eigen::Index n, double sample_rate_hz, double frequency_hz,
                               double amplitude_rad_s, double phase_rad) {
  Eigen::VectorXd out(n);
  const double omega = 2.0 * units::kPi * frequency_hz / sample_rate_hz;  // rad per sample
  for (Eigen::Index k = 0; k < n; ++k) {
    // omega k carries ~1e-16 relative error: under 1e-7 rad of phase even after 1e8 samples.
    out[k] = amplitude_rad_s * std::sin(omega * static_cast<double>(k) + phase_rad);
  }
  return out;
}

}  // namespace fogpipe::simulation
