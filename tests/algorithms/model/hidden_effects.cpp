#include "hidden_effects.h"

#include <cmath>
#include <random>

#include "algorithms/simulation/navigation_grade.h"

namespace fogpipe::model::testing {
namespace {

double Uniform01(std::uint64_t seed, simulation::Term term) {
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0x6B5A1CULL + static_cast<std::uint64_t>(term));
  return static_cast<double>(g() >> 11) * 0x1.0p-53;
}

double Sign(double x) { return x < 0 ? -1.0 : 1.0; }

}  // namespace

double NoiseAllanDeviation(const simulation::GyroErrorModel& e, double tau) {
  const double b2 = 2.0 * std::log(2.0) / 3.14159265358979323846;
  return std::sqrt(3.0 * e.q_rad * e.q_rad / (tau * tau) + e.n_rad_sqrt_s * e.n_rad_sqrt_s / tau +
                   b2 * e.b_rad_s * e.b_rad_s + e.k_rad_s_sqrt_s * e.k_rad_s_sqrt_s * tau / 3.0);
}

simulation::GyroSimulatorOptions HiddenEffectOptions(std::uint64_t seed,
                                                     const std::vector<simulation::Term>& effects) {
  using simulation::Term;
  simulation::GyroSimulatorOptions o = simulation::NavigationGradeOptions(seed);
  for (Term t : effects) simulation::AddNavigationGradeTerm(t, seed, &o);
  auto& e = o.errors;
  const double record = o.duration_s;
  auto k = [&](Term t, double lo, double hi) { return lo + (hi - lo) * Uniform01(seed, t); };
  for (Term t : effects) {
    switch (t) {
      case Term::kSinusoid: {
        auto& s = e.sinusoids.back();
        s.amplitude_rad_s = Sign(s.amplitude_rad_s) * k(t, 2, 4) *
                            NoiseAllanDeviation(e, 0.371 / s.frequency_hz) / 0.725;
        break;
      }
      case Term::kGaussMarkov: {
        auto& g = e.gauss_markov.back();
        g.sigma_rad_s = k(t, 6, 10) * NoiseAllanDeviation(e, 1.89 * g.correlation_time_s) / 0.62;
        break;
      }
      case Term::kTemperature: {
        const double amp =
            k(t, 3, 5) * NoiseAllanDeviation(e, 0.371 * o.temperature->period_s) / 0.725;
        e.temperature->coefficient_rad_s_per_degC =
            Sign(e.temperature->coefficient_rad_s_per_degC) * amp /
            (0.5 * o.temperature->peak_to_peak_degC);
        break;
      }
      case Term::kTemperatureRate: {
        const double amp =
            k(t, 4, 6) * NoiseAllanDeviation(e, 0.371 * o.temperature->period_s) / 0.725;
        e.temperature_rate->coefficient_rad_s_per_degC_per_s =
            Sign(e.temperature_rate->coefficient_rad_s_per_degC_per_s) * amp /
            simulation::MaxAbsTemperatureRate(*o.temperature);
        break;
      }
      case Term::kBiasStep: {
        auto& b = e.bias_steps.back();
        b.size_rad_s = Sign(b.size_rad_s) * k(t, 25, 35) * std::sqrt(2.0) *
                       NoiseAllanDeviation(e, record / 8.0);
        break;
      }
      case Term::kWarmup: {
        e.warmup->amplitude_rad_s = Sign(e.warmup->amplitude_rad_s) * k(t, 50, 70) *
                                    NoiseAllanDeviation(e, e.warmup->time_constant_s);
        break;
      }
      default:
        break;
    }
  }
  return o;
}

HiddenCase MakeHiddenCase(std::uint64_t seed, const std::vector<simulation::Term>& effects) {
  HiddenCase c;
  const auto o = HiddenEffectOptions(seed, effects);
  c.recording = simulation::SimulateGyro(o);
  c.input.rate_rad_s = &c.recording.rate_rad_s;
  c.input.sample_rate_hz = o.sample_rate_hz;
  c.input.aux.push_back({"temperature", "degC", c.recording.temperature_degC});
  return c;
}

Term AnalysisTerm(simulation::Term t) { return *ParseTerm(simulation::ToString(t)); }

}  // namespace fogpipe::model::testing
