#include "algorithms/simulation/navigation_grade.h"

#include <cmath>

#include "algorithms/common/units.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::simulation {
namespace {

constexpr std::uint64_t kLevelStream = 0x4C45'5645'4C53ULL;        // base levels
constexpr std::uint64_t kTemperatureStream = 0x5445'4D50'0000ULL;  // chamber cycle
constexpr std::uint64_t kTermStream = 0x4144'4400'0000ULL;         // added terms
constexpr std::uint64_t kPaperDriftStream = 0x5441'4235'0000ULL;   // Table 5 ratios

double LogUniform(RandomSource* rng, double lo, double hi) {
  return std::exp(rng->Uniform(std::log(lo), std::log(hi)));
}

double RandomSign(RandomSource* rng) { return rng->Uniform() < 0.5 ? -1.0 : 1.0; }

double DrawN(RandomSource* rng) { return units::DegPerSqrtHourToArw(rng->Uniform(0.003, 0.008)); }
double DrawB(RandomSource* rng) { return units::DegPerHourToBias(rng->Uniform(0.002, 0.006)); }
double DrawK(RandomSource* rng) {
  return units::DegPerHourSqrtHourToRrw(rng->Uniform(0.002, 0.010));
}
double DrawQ(RandomSource* rng) { return units::ArcsecToQuantization(rng->Uniform(0.05, 0.2)); }

size_t Occurrences(Term term, const GyroErrorModel& e) {
  switch (term) {
    case Term::kGaussMarkov:
      return e.gauss_markov.size();
    case Term::kSinusoid:
      return e.sinusoids.size();
    case Term::kBiasStep:
      return e.bias_steps.size();
    default:
      return 0;
  }
}

}  // namespace

double BiasInstabilityFloor(double b_rad_s) {
  return std::sqrt(2.0 * std::log(2.0) / units::kPi) * b_rad_s;
}

TemperatureProfile NavigationGradeTemperature(std::uint64_t seed) {
  RandomSource rng(DeriveSeed(seed, kTemperatureStream));
  TemperatureProfile t;
  t.mean_degC = 25.0;
  t.peak_to_peak_degC = rng.Uniform(6.0, 12.0);
  t.period_s = rng.Uniform(3600.0, 7200.0);
  t.sharpness = 2.0;
  t.phase_rad = rng.Uniform(0.0, 2.0 * units::kPi);
  t.noise_std_degC = 0.005;
  return t;
}

GyroSimulatorOptions PaperOptions(std::uint64_t seed) {
  RandomSource rng(DeriveSeed(seed, kLevelStream));
  GyroSimulatorOptions o;
  o.seed = seed;
  o.sample_rate_hz = 1.0;
  o.duration_s = 3600.0;
  o.errors.n_rad_sqrt_s = DrawN(&rng);
  o.errors.b_rad_s = DrawB(&rng);
  o.errors.k_rad_s_sqrt_s = DrawK(&rng);
  o.errors.q_rad = DrawQ(&rng);
  o.errors.bias_rad_s = units::DegPerHourToBias(rng.Uniform(-0.05, 0.05));
  return o;
}

GyroSimulatorOptions NavigationGradeOptions(std::uint64_t seed) {
  GyroSimulatorOptions o = PaperOptions(seed);  // same levels for the same seed
  o.sample_rate_hz = 10.0;
  o.duration_s = 6.0 * 3600.0;
  o.temperature = NavigationGradeTemperature(seed);
  return o;
}

GyroSimulatorOptions PaperDriftOptions(std::uint64_t seed) {
  GyroSimulatorOptions o = PaperOptions(seed);
  RandomSource rng(DeriveSeed(seed, kPaperDriftStream));
  // Ratios to N in the units Table 5 prints (deg/sqrt(h), deg/h, deg/h/sqrt(h)); see the header.
  const double n_deg_sqrt_h = units::ArwToDegPerSqrtHour(o.errors.n_rad_sqrt_s);
  o.errors.k_rad_s_sqrt_s =
      units::DegPerHourSqrtHourToRrw(rng.Uniform(350.0, 411.0) * n_deg_sqrt_h);
  o.errors.b_rad_s = units::DegPerHourToBias(rng.Uniform(4.99, 7.07) * n_deg_sqrt_h);
  return o;
}

void AddNavigationGradeTerm(Term term, std::uint64_t seed, GyroSimulatorOptions* options) {
  GyroErrorModel& e = options->errors;
  const std::uint64_t stream =
      kTermStream + static_cast<std::uint64_t>(term) * 1000 + Occurrences(term, e);
  RandomSource rng(DeriveSeed(seed, stream));
  const double floor =
      BiasInstabilityFloor(e.b_rad_s > 0.0 ? e.b_rad_s : units::DegPerHourToBias(0.004));
  const double duration = options->duration_s;
  if (NeedsTemperature(term) && !options->temperature) {
    options->temperature = NavigationGradeTemperature(seed);
  }
  switch (term) {
    case Term::kWhite:
      e.n_rad_sqrt_s = DrawN(&rng);
      break;
    case Term::kQuantization:
      e.q_rad = DrawQ(&rng);
      break;
    case Term::kBiasInstability:
      e.b_rad_s = DrawB(&rng);
      break;
    case Term::kRateRandomWalk:
      e.k_rad_s_sqrt_s = DrawK(&rng);
      break;
    case Term::kRateRamp:
      e.r_rad_s2 =
          RandomSign(&rng) * rng.Uniform(3.0, 6.0) * floor * std::sqrt(2.0) / (duration / 10.0);
      break;
    case Term::kGaussMarkov: {
      GaussMarkovTerm g;
      g.sigma_rad_s = rng.Uniform(3.0, 5.0) * floor;
      g.correlation_time_s = LogUniform(&rng, 30.0, 300.0);
      e.gauss_markov.push_back(g);
      break;
    }
    case Term::kSinusoid: {
      SinusoidTerm s;
      s.amplitude_rad_s = rng.Uniform(3.0, 6.0) * floor / 0.725;
      s.frequency_hz = LogUniform(&rng, 1.0 / 300.0, 1.0 / 20.0);
      s.phase_rad = rng.Uniform(0.0, 2.0 * units::kPi);
      e.sinusoids.push_back(s);
      break;
    }
    case Term::kTemperature: {
      TemperatureEffect t;
      t.reference_degC = options->temperature->mean_degC;
      t.coefficient_rad_s_per_degC = RandomSign(&rng) * rng.Uniform(4.0, 8.0) * floor /
                                     (0.5 * options->temperature->peak_to_peak_degC);
      e.temperature = t;
      break;
    }
    case Term::kTemperatureRate: {
      TemperatureRateEffect t;
      t.coefficient_rad_s_per_degC_per_s = RandomSign(&rng) * rng.Uniform(4.0, 8.0) * floor /
                                           MaxAbsTemperatureRate(*options->temperature);
      e.temperature_rate = t;
      break;
    }
    case Term::kBiasStep: {
      BiasStep s;
      s.size_rad_s = RandomSign(&rng) * rng.Uniform(5.0, 10.0) * floor;
      s.time_s = rng.Uniform(0.2, 0.8) * duration;
      e.bias_steps.push_back(s);
      break;
    }
    case Term::kWarmup: {
      Warmup w;
      w.amplitude_rad_s = RandomSign(&rng) * rng.Uniform(10.0, 20.0) * floor;
      w.time_constant_s = rng.Uniform(300.0, 1200.0);
      e.warmup = w;
      break;
    }
    case Term::kNarrowBand:
    case Term::kBiasLevels:
      // Not simulated: the simulator's error model has no band (the compare tests add one
      // themselves); `simulate --add` rejects it.
    case Term::kAngleQuantizer:
      // Not a term of the error model: the simulator's quantizer option makes it
      // (`simulate --angle-quantizer`); `simulate --add` rejects it.
      break;
  }
}

}  // namespace fogpipe::simulation
