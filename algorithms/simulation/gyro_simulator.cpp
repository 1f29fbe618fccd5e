#include "algorithms/simulation/gyro_simulator.h"

#include <cmath>
#include <sstream>

#include "algorithms/common/units.h"
#include "algorithms/simulation/flicker_noise.h"
#include "algorithms/simulation/noise_generators.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::simulation {
namespace {

// Random streams: one per (axis, term, occurrence); the aux temperature has one stream shared by
// all axes of a file, since they sit in the same chamber.
constexpr std::uint64_t kTemperatureStream = 0x7E3D'0000'0000ULL;

RandomSource StreamFor(const GyroSimulatorOptions& o, Term term, size_t occurrence = 0) {
  const std::uint64_t stream = (static_cast<std::uint64_t>(o.axis) + 1) * 1'000'000ULL +
                               static_cast<std::uint64_t>(term) * 1'000ULL + occurrence;
  return RandomSource(DeriveSeed(o.seed, stream));
}

bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

bool FiniteNonNegative(double x) { return std::isfinite(x) && x >= 0.0; }

}  // namespace

const char* ToString(QuantizationModel model) {
  return model == QuantizationModel::kAngleQuantizer ? "angle_quantizer" : "white_angle_noise";
}

std::vector<Term> GyroErrorModel::Terms() const {
  std::vector<Term> terms;
  if (n_rad_sqrt_s > 0.0) terms.push_back(Term::kWhite);
  if (q_rad > 0.0) terms.push_back(Term::kQuantization);
  if (b_rad_s > 0.0) terms.push_back(Term::kBiasInstability);
  if (k_rad_s_sqrt_s > 0.0) terms.push_back(Term::kRateRandomWalk);
  if (r_rad_s2 != 0.0) terms.push_back(Term::kRateRamp);
  if (!gauss_markov.empty()) terms.push_back(Term::kGaussMarkov);
  if (!sinusoids.empty()) terms.push_back(Term::kSinusoid);
  if (temperature) terms.push_back(Term::kTemperature);
  if (temperature_rate) terms.push_back(Term::kTemperatureRate);
  if (!bias_steps.empty()) terms.push_back(Term::kBiasStep);
  if (warmup) terms.push_back(Term::kWarmup);
  return terms;
}

Eigen::Index GyroSimulatorOptions::NumSamples() const {
  return static_cast<Eigen::Index>(std::llround(duration_s * sample_rate_hz));
}

bool GyroSimulatorOptions::IsValid(std::string* error) const {
  if (!(sample_rate_hz > 0.0) || !std::isfinite(sample_rate_hz)) {
    return Fail(error, "sample_rate_hz must be finite and > 0");
  }
  if (!(duration_s > 0.0) || !std::isfinite(duration_s)) {
    return Fail(error, "duration_s must be finite and > 0");
  }
  if (NumSamples() < 2) return Fail(error, "the recording needs at least 2 samples");
  if (axis < 0) return Fail(error, "axis must be >= 0");
  const GyroErrorModel& e = errors;
  if (!std::isfinite(e.bias_rad_s)) return Fail(error, "bias must be finite");
  if (!FiniteNonNegative(e.n_rad_sqrt_s)) return Fail(error, "white: N must be finite and >= 0");
  if (!FiniteNonNegative(e.q_rad)) return Fail(error, "quantization: Q must be finite and >= 0");
  if (!FiniteNonNegative(e.b_rad_s)) {
    return Fail(error, "bias_instability: B must be finite and >= 0");
  }
  if (!FiniteNonNegative(e.k_rad_s_sqrt_s)) {
    return Fail(error, "rate_random_walk: K must be finite and >= 0");
  }
  if (!std::isfinite(e.r_rad_s2)) return Fail(error, "rate_ramp: R must be finite");
  for (const GaussMarkovTerm& g : e.gauss_markov) {
    if (!FiniteNonNegative(g.sigma_rad_s) || !(g.correlation_time_s > 0.0) ||
        !std::isfinite(g.correlation_time_s)) {
      return Fail(error, "gauss_markov: sigma must be >= 0 and the correlation time > 0");
    }
  }
  for (const SinusoidTerm& s : e.sinusoids) {
    if (!(s.frequency_hz > 0.0) || !(s.frequency_hz < 0.5 * sample_rate_hz)) {
      return Fail(error, "sinusoid: frequency must be in (0, sample_rate_hz / 2)");
    }
    if (!std::isfinite(s.amplitude_rad_s) || !std::isfinite(s.phase_rad)) {
      return Fail(error, "sinusoid: amplitude and phase must be finite");
    }
  }
  if ((e.temperature || e.temperature_rate) && !temperature) {
    return Fail(error, "temperature effects need an aux temperature profile");
  }
  if (e.temperature && (!std::isfinite(e.temperature->coefficient_rad_s_per_degC) ||
                        !std::isfinite(e.temperature->reference_degC))) {
    return Fail(error, "temperature: coefficient and reference must be finite");
  }
  if (e.temperature_rate && !std::isfinite(e.temperature_rate->coefficient_rad_s_per_degC_per_s)) {
    return Fail(error, "temperature_rate: coefficient must be finite");
  }
  for (const BiasStep& s : e.bias_steps) {
    if (!std::isfinite(s.time_s) || !std::isfinite(s.size_rad_s)) {
      return Fail(error, "bias_step: time and size must be finite");
    }
  }
  if (e.warmup &&
      (!std::isfinite(e.warmup->amplitude_rad_s) || !(e.warmup->time_constant_s > 0.0) ||
       !std::isfinite(e.warmup->time_constant_s))) {
    return Fail(error, "warmup: amplitude must be finite and the time constant > 0");
  }
  if (latitude_deg && !(std::abs(*latitude_deg) <= 90.0)) {
    return Fail(error, "latitude_deg must be in [-90, 90]");
  }
  std::string why;
  if (!input_rate.IsValid(&why)) return Fail(error, why);
  if (temperature && !temperature->IsValid(&why)) return Fail(error, why);
  return true;
}

SimulatedRecording SimulateGyro(const GyroSimulatorOptions& options) {
  SimulatedRecording out;
  out.truth.options = options;
  std::string error;
  if (!options.IsValid(&error)) {
    out.summary.termination = Termination::kInvalidOptions;
    out.summary.message = error;
    return out;
  }
  const Eigen::Index n = options.NumSamples();
  const double fs = options.sample_rate_hz;
  const GyroErrorModel& e = options.errors;

  out.truth.num_samples = n;
  out.truth.terms = e.Terms();
  out.truth.earth_rate_rad_s =
      options.latitude_deg
          ? kEarthRotationRateRadS * std::sin(*options.latitude_deg * units::kRadPerDeg)
          : 0.0;

  out.true_rate_rad_s =
      SampleRateProfile(options.input_rate, n, fs).array() + out.truth.earth_rate_rad_s;
  Eigen::VectorXd& rate = out.rate_rad_s;
  rate = out.true_rate_rad_s.array() + e.bias_rad_s;

  // Stochastic terms.
  if (e.n_rad_sqrt_s > 0.0) {
    RandomSource rng = StreamFor(options, Term::kWhite);
    rate += WhiteRateNoise(n, fs, e.n_rad_sqrt_s, &rng);
  }
  if (e.q_rad > 0.0 && e.quantization_model == QuantizationModel::kWhiteAngleNoise) {
    RandomSource rng = StreamFor(options, Term::kQuantization);
    rate += QuantizationRateNoise(n, fs, e.q_rad, &rng);
  }
  if (e.b_rad_s > 0.0) {
    RandomSource rng = StreamFor(options, Term::kBiasInstability);
    rate += FlickerRateNoise(n, fs, e.b_rad_s, &rng);
  }
  if (e.k_rad_s_sqrt_s > 0.0) {
    RandomSource rng = StreamFor(options, Term::kRateRandomWalk);
    rate += RateRandomWalk(n, fs, e.k_rad_s_sqrt_s, &rng);
  }
  if (e.r_rad_s2 != 0.0) rate += RateRamp(n, fs, e.r_rad_s2);
  for (size_t i = 0; i < e.gauss_markov.size(); ++i) {
    RandomSource rng = StreamFor(options, Term::kGaussMarkov, i);
    rate += GaussMarkov(n, fs, e.gauss_markov[i].sigma_rad_s, e.gauss_markov[i].correlation_time_s,
                        &rng);
  }
  for (const SinusoidTerm& s : e.sinusoids) {
    rate += SinusoidalRate(n, fs, s.frequency_hz, s.amplitude_rad_s, s.phase_rad);
  }

  // Deterministic effects, driven by the true temperature.
  if (e.temperature) rate += TemperatureEffectRate(*e.temperature, *options.temperature, n, fs);
  if (e.temperature_rate) {
    rate += TemperatureRateEffectRate(*e.temperature_rate, *options.temperature, n, fs);
  }
  for (const BiasStep& s : e.bias_steps) rate += BiasStepRate(s, n, fs);
  if (e.warmup) rate += WarmupRate(*e.warmup, n, fs);

  // A physical quantizer acts on the total output angle, so it comes last.
  if (e.q_rad > 0.0 && e.quantization_model == QuantizationModel::kAngleQuantizer) {
    rate = QuantizeAngle(rate, fs, e.q_rad * std::sqrt(12.0));
  }

  if (options.temperature) {
    RandomSource rng(DeriveSeed(options.seed, kTemperatureStream));
    out.temperature_degC = SampleTrueTemperature(*options.temperature, n, fs) +
                           rng.Normals(n) * options.temperature->noise_std_degC;
  }

  if (!rate.allFinite()) {
    out.summary.termination = Termination::kNumericalFailure;
    out.summary.message = "the simulated rate is not finite (check the term magnitudes)";
    out.rate_rad_s.resize(0);
    return out;
  }
  out.summary.termination = Termination::kSuccess;
  std::ostringstream message;
  message << "simulated " << n << " samples with " << out.truth.terms.size() << " catalog terms";
  out.summary.message = message.str();
  out.summary.num_samples = n;
  return out;
}

}  // namespace fogpipe::simulation
