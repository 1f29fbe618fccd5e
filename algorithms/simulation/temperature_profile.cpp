#include "algorithms/simulation/temperature_profile.h"

#include <cmath>

#include "algorithms/common/units.h"

namespace fogpipe::simulation {
namespace {

// Below this sharpness g is the sine to within s^2 / 3 relative; the limit avoids 0 / 0.
constexpr double kSineSharpness = 1e-6;

double Theta(const TemperatureProfile& p, double t_s) {
  return 2.0 * units::kPi * t_s / p.period_s + p.phase_rad;
}

}  // namespace

bool TemperatureProfile::IsValid(std::string* error) const {
  auto fail = [error](const char* message) {
    if (error) *error = message;
    return false;
  };
  if (!std::isfinite(mean_degC)) return fail("temperature mean must be finite");
  if (!(peak_to_peak_degC >= 0.0) || !std::isfinite(peak_to_peak_degC)) {
    return fail("temperature peak-to-peak must be finite and >= 0");
  }
  if (!(period_s > 0.0) || !std::isfinite(period_s)) {
    return fail("temperature period must be finite and > 0");
  }
  if (!(sharpness >= 0.0) || sharpness > 50.0)
    return fail("temperature sharpness must be in [0, 50]");
  if (!std::isfinite(phase_rad)) return fail("temperature phase must be finite");
  if (!(noise_std_degC >= 0.0) || !std::isfinite(noise_std_degC)) {
    return fail("temperature noise must be finite and >= 0");
  }
  return true;
}

double TrueTemperature(const TemperatureProfile& p, double t_s) {
  const double theta = Theta(p, t_s);
  const double g = p.sharpness < kSineSharpness
                       ? std::sin(theta)
                       : std::tanh(p.sharpness * std::sin(theta)) / std::tanh(p.sharpness);
  return p.mean_degC + 0.5 * p.peak_to_peak_degC * g;
}

double TrueTemperatureRate(const TemperatureProfile& p, double t_s) {
  const double theta = Theta(p, t_s);
  const double omega = 2.0 * units::kPi / p.period_s;
  double dg = std::cos(theta);
  if (p.sharpness >= kSineSharpness) {
    const double sech = 1.0 / std::cosh(p.sharpness * std::sin(theta));
    dg *= p.sharpness * sech * sech / std::tanh(p.sharpness);
  }
  return 0.5 * p.peak_to_peak_degC * omega * dg;
}

double MaxAbsTemperatureRate(const TemperatureProfile& p) {
  const double omega = 2.0 * units::kPi / p.period_s;
  const double gain = p.sharpness < kSineSharpness ? 1.0 : p.sharpness / std::tanh(p.sharpness);
  return 0.5 * p.peak_to_peak_degC * omega * gain;
}

Eigen::VectorXd SampleTrueTemperature(const TemperatureProfile& profile, Eigen::Index n,
                                      double sample_rate_hz) {
  Eigen::VectorXd out(n);
  for (Eigen::Index k = 0; k < n; ++k) out[k] = TrueTemperature(profile, k / sample_rate_hz);
  return out;
}

Eigen::VectorXd SampleTrueTemperatureRate(const TemperatureProfile& profile, Eigen::Index n,
                                          double sample_rate_hz) {
  Eigen::VectorXd out(n);
  for (Eigen::Index k = 0; k < n; ++k) out[k] = TrueTemperatureRate(profile, k / sample_rate_hz);
  return out;
}

}  // namespace fogpipe::simulation
