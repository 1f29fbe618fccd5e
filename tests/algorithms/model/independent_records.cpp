#include "independent_records.h"

#include <cmath>
#include <random>

#include "hidden_effects.h"

namespace fogpipe::model::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadPerDegH = kPi / 180.0 / 3600.0;
constexpr double kRadPerDegSqrtH = kPi / 180.0 / 60.0;
constexpr double kRadPerDegHSqrtH = kPi / 180.0 / 3600.0 / 60.0;
constexpr double kRadPerArcsec = kPi / 180.0 / 3600.0;

std::mt19937_64 Stream(std::uint64_t seed, std::uint64_t stream) {
  return std::mt19937_64(seed * 0x9E3779B97F4A7C15ULL + stream);
}

// A first-order Gauss-Markov series of variance s2 and correlation time tc, from its stationary
// law.
void AddGaussMarkov(double s2, double tc_s, double fs, std::mt19937_64* g, Eigen::VectorXd* x) {
  std::normal_distribution<double> e(0.0, 1.0);
  const double phi = std::exp(-1.0 / (tc_s * fs)), s = std::sqrt(s2);
  double state = s * e(*g);
  for (long i = 0; i < x->size(); ++i) {
    state = phi * state + s * std::sqrt(1.0 - phi * phi) * e(*g);
    (*x)[i] += state;
  }
}

}  // namespace

CompareInput IndependentRecord::Input() const {
  CompareInput input;
  input.rate_rad_s = &rate_rad_s;
  input.sample_rate_hz = fs;
  input.aux = aux;
  return input;
}

double IndependentNoiseAllanDeviation(const IndependentRecord& r, double tau) {
  return std::sqrt(3.0 * r.q_rad * r.q_rad / (tau * tau) + r.n_rad_sqrt_s * r.n_rad_sqrt_s / tau +
                   2.0 * std::log(2.0) / kPi * r.b_rad_s * r.b_rad_s +
                   r.k_rad_s_sqrt_s * r.k_rad_s_sqrt_s * tau / 3.0);
}

IndependentRecord MakeIndependentRecord(std::uint64_t seed,
                                        const IndependentRecordOptions& options) {
  IndependentRecord r;
  const double fs = r.fs;
  const long n = static_cast<long>(6 * 3600 * fs);
  std::mt19937_64 levels = Stream(seed, 0x1E7E15ULL);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  r.n_rad_sqrt_s = (0.003 + 0.005 * u(levels)) * kRadPerDegSqrtH;
  r.b_rad_s = (0.002 + 0.004 * u(levels)) * kRadPerDegH;
  r.k_rad_s_sqrt_s = (0.002 + 0.008 * u(levels)) * kRadPerDegHSqrtH;
  r.q_rad = (0.05 + 0.15 * u(levels)) * kRadPerArcsec;
  r.bias_rad_s = (-0.05 + 0.1 * u(levels)) * kRadPerDegH;

  // Noise: white, flicker (Gauss-Markov sum, see the header), random walk.
  std::mt19937_64 noise = Stream(seed, 0x4015EULL);
  std::normal_distribution<double> e(0.0, 1.0);
  Eigen::VectorXd rate = Eigen::VectorXd::Constant(n, r.bias_rad_s);
  const double log_spacing = std::log(10.0) / 3.0;
  for (int j = 0; j <= 13; ++j)
    AddGaussMarkov(log_spacing * r.b_rad_s * r.b_rad_s / kPi, std::pow(10.0, j / 3.0), fs, &noise,
                   &rate);
  double walk = 0;
  for (long i = 0; i < n; ++i) {
    walk += r.k_rad_s_sqrt_s / std::sqrt(fs) * e(noise);
    rate[i] += r.n_rad_sqrt_s * std::sqrt(fs) * e(noise) + walk;
  }

  // Temperature: a chamber cycle and a slow wander, recorded with sensor noise.
  std::mt19937_64 chamber = Stream(seed, 0x7E3FULL);
  const double peak_to_peak = 6.0 + 6.0 * u(chamber), period_s = 3600.0 + 3600.0 * u(chamber);
  const double cycle_phase = 2.0 * kPi * u(chamber);
  r.temperature_truth_degc = Eigen::VectorXd::Zero(n);
  AddGaussMarkov(0.2 * 0.2, 1800.0, fs, &chamber, &r.temperature_truth_degc);
  for (long i = 0; i < n; ++i)
    r.temperature_truth_degc[i] +=
        25.0 + 0.5 * peak_to_peak * std::sin(2.0 * kPi * i / (fs * period_s) + cycle_phase);
  Eigen::VectorXd temperature = r.temperature_truth_degc;
  for (long i = 0; i < n; ++i) temperature[i] += 0.005 * e(chamber);

  if (options.am_signature > 0) {
    std::mt19937_64 line = Stream(seed, 0xA31EULL);
    AmLineTruth am;
    am.frequency_hz = std::exp(std::log(0.1) + (std::log(3.0) - std::log(0.1)) * u(line));
    am.phase_rad = 2.0 * kPi * u(line);
    am.depth = 0.3 + 0.4 * u(line);
    const double sign = u(line) < 0.5 ? -1.0 : 1.0;
    am.reference_degc = r.temperature_truth_degc.mean();
    const Eigen::ArrayXd x = r.temperature_truth_degc.array() - am.reference_degc;
    const double sd_x = std::sqrt(x.square().mean());
    const double record_s = static_cast<double>(n) / fs;
    // The noise's one-sided PSD at f: white, and the quantizer's angle error (white, variance
    // s^2 = q^2 / 6 with the dither) differenced into a rate, 8 s^2 fs sin^2(pi f / fs).
    const double step = r.q_rad * std::sqrt(12.0), dither_variance = step * step / 6.0;
    const double psd =
        2.0 * r.n_rad_sqrt_s * r.n_rad_sqrt_s +
        8.0 * dither_variance * fs * std::pow(std::sin(kPi * am.frequency_hz / fs), 2);
    am.modulation_rad_s_per_degc = sign * options.am_signature * std::sqrt(psd / record_s) / sd_x;
    am.amplitude_rad_s = std::abs(am.modulation_rad_s_per_degc) * 0.5 * peak_to_peak / am.depth;
    for (long i = 0; i < n; ++i)
      rate[i] += (am.amplitude_rad_s + am.modulation_rad_s_per_degc * x[i]) *
                 std::sin(2.0 * kPi * am.frequency_hz * i / fs + am.phase_rad);
    r.am = am;
  }

  // The angle quantizer.
  const double step = r.q_rad * std::sqrt(12.0);
  std::mt19937_64 dither = Stream(seed, 0xD17EULL);
  r.rate_rad_s.resize(n);
  double angle = 0, previous = 0;
  for (long i = 0; i < n; ++i) {
    angle += rate[i] / fs;
    const double offset = options.quantizer == Quantizer::kDithered ? u(dither) - 0.5 : 0.0;
    const double quantized = step * std::round(angle / step + offset);
    r.rate_rad_s[i] = (quantized - previous) * fs;
    previous = quantized;
  }

  r.aux.push_back({"temperature", "degC", temperature});
  r.aux.push_back({"supply_voltage", "V", SupplyVoltage(seed, n, fs).recorded});
  r.aux.push_back({"magnetic_field", "uT", MagneticField(seed, n, fs).recorded});
  return r;
}

}  // namespace fogpipe::model::testing
