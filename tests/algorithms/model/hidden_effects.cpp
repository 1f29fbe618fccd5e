#include "hidden_effects.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "algorithms/allan/allan.h"
#include "algorithms/allan/noise_model.h"
#include "algorithms/simulation/navigation_grade.h"

namespace fogpipe::model::testing {
namespace {

double Uniform01(std::uint64_t seed, simulation::Term term) {
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0x6B5A1CULL + static_cast<std::uint64_t>(term));
  return static_cast<double>(g() >> 11) * 0x1.0p-53;
}

double Sign(double x) { return x < 0 ? -1.0 : 1.0; }

// Taus: 10 per decade up to record / 8, the longest tau of the compare's Allan view
// (ViewOptions::max_tau_fraction), where the overlapping estimate still has EDF >= ~4.
std::vector<long long> SignatureFactors(long n) {
  allan::TauGridOptions grid;
  grid.kind = allan::TauGridKind::kDecade;
  grid.per_decade = 10;
  return allan::AveragingFactors(grid, n / 8);
}

AllanSignature PeakOf(const std::vector<double>& tau, const std::vector<double>& avar,
                      const simulation::GyroErrorModel& errors);

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
        s.amplitude_rad_s = Sign(s.amplitude_rad_s) * k(t, 1.4, 2.2) *
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
            k(t, 9, 12) * NoiseAllanDeviation(e, 0.371 * o.temperature->period_s) / 0.725;
        e.temperature_rate->coefficient_rad_s_per_degC_per_s =
            Sign(e.temperature_rate->coefficient_rad_s_per_degC_per_s) * amp /
            simulation::MaxAbsTemperatureRate(*o.temperature);
        break;
      }
      case Term::kBiasStep: {
        auto& b = e.bias_steps.back();
        b.size_rad_s = Sign(b.size_rad_s) * k(t, 20, 26) * std::sqrt(2.0) *
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

void ScaleEffect(simulation::Term effect, double factor, simulation::GyroSimulatorOptions* o) {
  using simulation::Term;
  auto& e = o->errors;
  switch (effect) {
    case Term::kSinusoid:
      e.sinusoids.back().amplitude_rad_s *= factor;
      break;
    case Term::kGaussMarkov:
      e.gauss_markov.back().sigma_rad_s *= factor;
      break;
    case Term::kTemperature:
      e.temperature->coefficient_rad_s_per_degC *= factor;
      break;
    case Term::kTemperatureRate:
      e.temperature_rate->coefficient_rad_s_per_degC_per_s *= factor;
      break;
    case Term::kBiasStep:
      e.bias_steps.back().size_rad_s *= factor;
      break;
    case Term::kWarmup:
      e.warmup->amplitude_rad_s *= factor;
      break;
    default:
      break;
  }
}

AllanSignature PeakAllanSignature(const simulation::GyroSimulatorOptions& o,
                                  simulation::Term effect) {
  using simulation::Term;
  // The effect alone: every other term of the error model removed (the last instance of a term
  // that may occur several times is the one kept).
  simulation::GyroSimulatorOptions alone = o;
  simulation::GyroErrorModel& a = alone.errors;
  a = simulation::GyroErrorModel{};
  const auto& e = o.errors;
  switch (effect) {
    case Term::kSinusoid:
      a.sinusoids = {e.sinusoids.back()};
      break;
    case Term::kGaussMarkov:
      a.gauss_markov = {e.gauss_markov.back()};
      break;
    case Term::kTemperature:
      a.temperature = e.temperature;
      break;
    case Term::kTemperatureRate:
      a.temperature_rate = e.temperature_rate;
      break;
    case Term::kBiasStep:
      a.bias_steps = {e.bias_steps.back()};
      break;
    case Term::kWarmup:
      a.warmup = e.warmup;
      break;
    default:
      break;
  }
  const long n = static_cast<long>(o.NumSamples());
  const double fs = o.sample_rate_hz;
  if (effect != Term::kGaussMarkov)
    return PeakAllanSignatureOfSeries(simulation::SimulateGyro(alone).rate_rad_s, fs, o.errors);
  // A stochastic term: its expected Allan variance (IEEE Std 952-1997 Annex C), not one
  // realisation's.
  std::vector<double> tau, avar;
  allan::TermParams p;
  p.amplitude = a.gauss_markov[0].sigma_rad_s;
  p.correlation_time_s = a.gauss_markov[0].correlation_time_s;
  for (long long k : SignatureFactors(n)) {
    tau.push_back(k / fs);
    avar.push_back(allan::TermAllanVariance(allan::Term::kGaussMarkov, p, tau.back()));
  }
  return PeakOf(tau, avar, o.errors);
}

AllanSignature PeakAllanSignatureOfSeries(const Eigen::VectorXd& effect, double fs,
                                          const simulation::GyroErrorModel& errors) {
  allan::AllanOptions ao;
  ao.grid.kind = allan::TauGridKind::kExplicit;
  ao.grid.explicit_m = SignatureFactors(effect.size());
  ao.confidence_intervals = false;
  const allan::AllanResult r = allan::ComputeAllan(effect, fs, ao);
  std::vector<double> tau, avar;
  for (size_t i = 0; i < r.table.size(); ++i) {
    tau.push_back(r.table.tau_s[i]);
    avar.push_back(r.table.sigma[i] * r.table.sigma[i]);
  }
  return PeakOf(tau, avar, errors);
}

HiddenCase MakeHiddenCase(const simulation::GyroSimulatorOptions& options) {
  HiddenCase c;
  c.recording = simulation::SimulateGyro(options);
  c.input.rate_rad_s = &c.recording.rate_rad_s;
  c.input.sample_rate_hz = options.sample_rate_hz;
  c.input.aux.push_back({"temperature", "degC", c.recording.temperature_degC});
  return c;
}

HiddenCase MakeHiddenCase(std::uint64_t seed, const std::vector<simulation::Term>& effects) {
  return MakeHiddenCase(HiddenEffectOptions(seed, effects));
}

void AddNarrowBand(double f0, double zeta, double peak_ratio, std::uint64_t seed, HiddenCase* c) {
  Eigen::VectorXd& y = c->recording.rate_rad_s;
  const double fs = c->input.sample_rate_hz;
  // AR(2) resonator with poles r exp(+-i w0): r = exp(-zeta w0 / fs) gives the half-power
  // bandwidth 2 zeta f0 of the continuous resonance (zeta << 1).
  const double w0 = 2.0 * 3.14159265358979323846 * f0 / fs;
  const double r = std::exp(-zeta * w0);
  const double a1 = 2.0 * r * std::cos(w0), a2 = -r * r;
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0xBA4DULL);
  std::normal_distribution<double> e(0.0, 1.0);
  Eigen::VectorXd x(y.size());
  double x1 = 0, x2 = 0;
  for (long i = -4096; i < y.size(); ++i) {  // burn-in: the resonator's transient
    const double v = a1 * x1 + a2 * x2 + e(g);
    x2 = x1;
    x1 = v;
    if (i >= 0) x[i] = v;
  }
  // Power = peak PSD x equivalent noise bandwidth (pi zeta f0) for a peak of k times 2 N^2.
  const double n = c->recording.truth.options.errors.n_rad_sqrt_s;
  const double power = peak_ratio * 2.0 * n * n * 3.14159265358979323846 * zeta * f0;
  const double var = (x.array() - x.mean()).square().mean();
  y += x * std::sqrt(power / var);
}

void AddPressureBias(double k, std::uint64_t seed, HiddenCase* c) {
  Eigen::VectorXd& y = c->recording.rate_rad_s;
  const long n = y.size();
  const double fs = c->input.sample_rate_hz;
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0x9E55ULL);
  std::normal_distribution<double> e(0.0, 1.0);
  // First-order Gauss-Markov wander, correlation time 600 s, started from its stationary law.
  const double phi = std::exp(-1.0 / (600.0 * fs));
  Eigen::VectorXd p(n);
  double x = e(g);
  for (long i = 0; i < n; ++i) {
    x = phi * x + std::sqrt(1.0 - phi * phi) * e(g);
    p[i] = x;
  }
  p.array() -= p.mean();
  p /= std::sqrt(p.squaredNorm() / static_cast<double>(n));
  y += p * (k * NoiseAllanDeviation(c->recording.truth.options.errors, 1000.0));
  c->input.aux.push_back({"pressure", "hPa", (1013.0 + 5.0 * p.array()).matrix()});
}

Term AnalysisTerm(simulation::Term t) { return *ParseTerm(simulation::ToString(t)); }

namespace {

AllanSignature PeakOf(const std::vector<double>& tau, const std::vector<double>& avar,
                      const simulation::GyroErrorModel& errors) {
  AllanSignature best;
  for (size_t i = 0; i < tau.size(); ++i) {
    const double noise = NoiseAllanDeviation(errors, tau[i]);
    const double ratio = std::sqrt(avar[i]) / noise;
    if (ratio > best.ratio) best = {tau[i], std::sqrt(avar[i]), noise, ratio};
  }
  return best;
}

// A first-order Gauss-Markov series of unit variance (correlation time tc), started from its
// stationary law.
Eigen::VectorXd UnitGaussMarkov(double tc_s, long n, double fs, std::mt19937_64* g) {
  std::normal_distribution<double> e(0.0, 1.0);
  const double phi = std::exp(-1.0 / (tc_s * fs));
  Eigen::VectorXd x(n);
  double state = e(*g);
  for (long i = 0; i < n; ++i) {
    state = phi * state + std::sqrt(1.0 - phi * phi) * e(*g);
    x[i] = state;
  }
  return x;
}

Eigen::VectorXd WhiteNoise(double sigma, long n, std::mt19937_64* g) {
  std::normal_distribution<double> e(0.0, sigma);
  Eigen::VectorXd x(n);
  for (long i = 0; i < n; ++i) x[i] = e(*g);
  return x;
}

}  // namespace

AuxSignal SupplyVoltage(std::uint64_t seed, long n, double fs) {
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0x5A1E7ULL);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double period_s = 120.0 + 480.0 * u(g), phase = 2.0 * 3.14159265358979323846 * u(g);
  AuxSignal v;
  v.truth = Eigen::VectorXd::Constant(n, 28.0) + 0.1 * UnitGaussMarkov(1800.0, n, fs, &g);
  for (long i = 0; i < n; ++i)
    v.truth[i] += 0.03 * std::sin(2.0 * 3.14159265358979323846 * i / (fs * period_s) + phase);
  v.recorded = v.truth + WhiteNoise(0.001, n, &g);
  return v;
}

AuxSignal MagneticField(std::uint64_t seed, long n, double fs) {
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0x3A6F1ULL);
  AuxSignal b;
  b.truth = Eigen::VectorXd::Constant(n, 48.0) + 0.4 * UnitGaussMarkov(900.0, n, fs, &g);
  b.recorded = b.truth + WhiteNoise(0.02, n, &g);
  return b;
}

void AddInnocentAux(std::uint64_t seed, HiddenCase* c) {
  const long n = c->recording.rate_rad_s.size();
  const double fs = c->input.sample_rate_hz;
  c->input.aux.push_back({"supply_voltage", "V", SupplyVoltage(seed, n, fs).recorded});
  c->input.aux.push_back({"magnetic_field", "uT", MagneticField(seed, n, fs).recorded});
}

namespace {

// The coefficient that gives `shape` (a bias per unit coefficient) the peak Allan signature k,
// with a random sign from its own stream.
double SizeBySignature(const Eigen::VectorXd& shape, double k, std::uint64_t seed,
                       std::uint64_t stream, const HiddenCase& c) {
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + stream);
  const double sign = (g() & 1) ? 1.0 : -1.0;
  const AllanSignature unit =
      PeakAllanSignatureOfSeries(shape, c.input.sample_rate_hz, c.recording.truth.options.errors);
  return sign * k / unit.ratio;
}

}  // namespace

double AddSupplyVoltageBias(double k, std::uint64_t seed, HiddenCase* c) {
  const long n = c->recording.rate_rad_s.size();
  const double fs = c->input.sample_rate_hz;
  const AuxSignal v = SupplyVoltage(seed, n, fs);
  const Eigen::VectorXd shape = (v.truth.array() - v.truth.mean()).matrix();
  const double coefficient = SizeBySignature(shape, k, seed, 0xC0EFULL, *c);
  c->recording.rate_rad_s += coefficient * shape;
  c->input.aux.push_back({"supply_voltage", "V", v.recorded});
  c->input.aux.push_back({"magnetic_field", "uT", MagneticField(seed, n, fs).recorded});
  return coefficient;
}

std::pair<double, double> AddQuadraticTemperatureBias(double k, std::uint64_t seed, HiddenCase* c) {
  const Eigen::VectorXd& temperature = c->recording.temperature_degC;
  const Eigen::ArrayXd x = temperature.array() - temperature.mean();
  const double half_range = 0.5 * (x.maxCoeff() - x.minCoeff());
  const Eigen::VectorXd shape = (x + x.square() / half_range).matrix();
  // The quadratic part is what must be detected for order 2: it is the part sized.
  const double c1 = SizeBySignature((x.square() / half_range).matrix(), k, seed, 0x7E2ULL, *c);
  c->recording.rate_rad_s += c1 * shape;
  return {c1, c1 / half_range};
}

double AddThermalHysteresis(double k, HiddenCase* c) {
  const Eigen::VectorXd& t = c->recording.temperature_degC;
  const double fs = c->input.sample_rate_hz;
  const long n = t.size(), half = static_cast<long>(60 * fs);
  Eigen::VectorXd shape(n);
  for (long i = 0; i < n; ++i) {
    const long a = std::max(0L, i - half), b = std::min(n - 1, i + half);
    const double left = t.segment(a, std::max(1L, i - a + 1)).mean();
    const double right = t.segment(i, std::max(1L, b - i + 1)).mean();
    shape[i] = right >= left ? 1.0 : -1.0;
  }
  const double amplitude =
      k / PeakAllanSignatureOfSeries(shape, fs, c->recording.truth.options.errors).ratio;
  c->recording.rate_rad_s += amplitude * shape;
  return amplitude;
}

Chirp AddChirp(double k, std::uint64_t seed, HiddenCase* c) {
  const long n = c->recording.rate_rad_s.size();
  const double fs = c->input.sample_rate_hz, record = static_cast<double>(n) / fs;
  constexpr double kTwoPi = 2.0 * 3.14159265358979323846;
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0xC41ABULL);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Chirp chirp;
  chirp.f1_hz = 0.8 + 0.8 * u(g);
  chirp.f2_hz = chirp.f1_hz + 1.0;
  const double phase0 = kTwoPi * u(g), sweep = (chirp.f2_hz - chirp.f1_hz) / record;
  Eigen::VectorXd shape(n);
  for (long i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / fs;
    shape[i] = std::sin(phase0 + kTwoPi * (chirp.f1_hz * t + 0.5 * sweep * t * t));
  }
  chirp.amplitude_rad_s = std::abs(SizeBySignature(shape, k, seed, 0xC41ACULL, *c));
  c->recording.rate_rad_s += chirp.amplitude_rad_s * shape;
  return chirp;
}

namespace {

// The piecewise-constant shape with unit-scale jumps at `times` of sizes `sizes`.
Eigen::VectorXd LevelsShape(const std::vector<double>& times, const std::vector<double>& sizes,
                            long n, double fs) {
  Eigen::VectorXd shape = Eigen::VectorXd::Zero(n);
  for (size_t j = 0; j < times.size(); ++j)
    for (long i = static_cast<long>(std::ceil(times[j] * fs)); i < n; ++i) shape[i] += sizes[j];
  return shape;
}

// Scales the jumps to the signature k, adds the bias to the rate and returns the truth.
BiasLevels AddLevels(const std::vector<double>& times, std::vector<double> sizes, double k,
                     std::uint64_t seed, std::uint64_t stream, HiddenCase* c) {
  const long n = c->recording.rate_rad_s.size();
  const double fs = c->input.sample_rate_hz;
  Eigen::VectorXd shape = LevelsShape(times, sizes, n, fs);
  const double scale = std::abs(SizeBySignature(shape, k, seed, stream, *c));
  for (double& size : sizes) size *= scale;
  c->recording.rate_rad_s += scale * shape;
  return {times, sizes};
}

}  // namespace

BiasLevels AddBiasSteps(double k, std::uint64_t seed, HiddenCase* c) {
  const double record = c->recording.rate_rad_s.size() / c->input.sample_rate_hz;
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0x57E95ULL);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int count = 3 + static_cast<int>(g() % 3);
  std::vector<double> times;
  while (static_cast<int>(times.size()) < count) {
    const double t = record * (0.05 + 0.9 * u(g));
    bool apart = true;
    for (double other : times) apart = apart && std::abs(other - t) >= record / 20;
    if (apart) times.push_back(std::round(t * c->input.sample_rate_hz) / c->input.sample_rate_hz);
  }
  std::sort(times.begin(), times.end());
  std::vector<double> sizes;
  for (int j = 0; j < count; ++j) sizes.push_back(((g() & 1) ? 1.0 : -1.0) * (0.6 + 0.8 * u(g)));
  return AddLevels(times, sizes, k, seed, 0x57E96ULL, c);
}

BiasLevels AddTelegraph(double k, double dwell_s, std::uint64_t seed, HiddenCase* c) {
  const double fs = c->input.sample_rate_hz;
  const double record = c->recording.rate_rad_s.size() / fs;
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0x7E1EULL);
  std::exponential_distribution<double> dwell(1.0 / dwell_s);
  double state = (g() & 1) ? 0.5 : -0.5;
  std::vector<double> times, sizes;
  // Start from the stationary chain: the first dwell is exponential too (memoryless).
  for (double t = dwell(g); t < record; t += dwell(g)) {
    const double at = std::ceil(t * fs) / fs;
    if (at >= record) break;
    times.push_back(at);
    sizes.push_back(-2 * state);
    state = -state;
  }
  return AddLevels(times, sizes, k, seed, 0x7E1FULL, c);
}

}  // namespace fogpipe::model::testing
