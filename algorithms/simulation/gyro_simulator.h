// A single-axis fiber-optic gyro simulator with ground truth.
//
//   measured rate = true rate + bias + deterministic effects + stochastic terms
//   true rate     = rate-table input profile + Earth-rate projection
//
// Every term of the catalog (catalog.h) has its own random stream derived from (seed, axis, term),
// so adding or removing one term never changes the realisation of the others, and the axes of a
// multi-axis file differ only in their streams. The aux temperature has one stream for all axes.
// Nothing here estimates anything: the simulator shares no code with the analysis domains.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/common/status.h"
#include "algorithms/common/units.h"
#include "algorithms/simulation/catalog.h"
#include "algorithms/simulation/deterministic_effects.h"
#include "algorithms/simulation/rate_profile.h"
#include "algorithms/simulation/temperature_profile.h"

namespace fogpipe::simulation {

using units::kEarthRotationRateRadS;  // algorithms/common/units.h

/// `gauss_markov`: stationary standard deviation and correlation time.
struct GaussMarkovTerm {
  double sigma_rad_s = 0.0;
  double correlation_time_s = 100.0;
};

/// `sinusoid`: W sin(2 pi f0 t + phase).
struct SinusoidTerm {
  double frequency_hz = 0.01;
  double amplitude_rad_s = 0.0;
  double phase_rad = 0.0;
};

/// How the `quantization` term is produced (noise_generators.h).
enum class QuantizationModel {
  /// White angle noise of standard deviation Q, differenced to rate: sigma^2 = 3 Q^2 / tau^2
  /// exactly.
  kWhiteAngleNoise,
  /// A physical angle quantizer with step Q sqrt(12) applied to the total output; matches
  /// 3 Q^2 / tau^2 only when the angle crosses many steps per sample.
  kAngleQuantizer,
};
const char* ToString(QuantizationModel model);

/// Every error term of one gyro axis, SI. A zero magnitude (or an empty list/optional) means the
/// term is absent. IEEE Std 952-1997 Annex C conventions, see noise_generators.h.
struct GyroErrorModel {
  double bias_rad_s = 0.0;    ///< constant bias
  double n_rad_sqrt_s = 0.0;  ///< white: angle random walk N
  double q_rad = 0.0;         ///< quantization Q
  QuantizationModel quantization_model = QuantizationModel::kWhiteAngleNoise;
  double b_rad_s = 0.0;         ///< bias_instability B (Allan floor 0.664 B)
  double k_rad_s_sqrt_s = 0.0;  ///< rate_random_walk K
  double r_rad_s2 = 0.0;        ///< rate_ramp R (may be negative)
  std::vector<GaussMarkovTerm> gauss_markov;
  std::vector<SinusoidTerm> sinusoids;
  std::optional<TemperatureEffect> temperature;
  std::optional<TemperatureRateEffect> temperature_rate;
  std::vector<BiasStep> bias_steps;
  std::optional<Warmup> warmup;

  /// The catalog terms present, in catalog order, each once.
  std::vector<Term> Terms() const;
};

struct GyroSimulatorOptions {
  /// Sampling rate of the recording. Default 10 Hz.
  double sample_rate_hz = 10.0;
  /// Length of the recording; the sample count is round(duration_s * sample_rate_hz).
  double duration_s = 3600.0;
  /// Seed of every random stream.
  std::uint64_t seed = 0;
  /// Axis index of a multi-axis file: selects independent streams for the same seed.
  int axis = 0;
  GyroErrorModel errors;
  /// Rate-table input (rad/s); empty: a static test.
  RateProfile input_rate;
  /// When set, the sensing axis is taken as vertical and reads Omega_e sin(latitude) on top of
  /// the input rate (a static gyro on a level table, axis up).
  std::optional<double> latitude_deg;
  /// The aux temperature channel. Required by the thermal effects.
  std::optional<TemperatureProfile> temperature;

  bool IsValid(std::string* error) const;
  Eigen::Index NumSamples() const;
};

/// Everything that went into a recording, SI, for tests and the JSON sidecar.
struct SimulationTruth {
  GyroSimulatorOptions options;  ///< the exact inputs (model, profiles, seed)
  Eigen::Index num_samples = 0;
  double earth_rate_rad_s = 0.0;  ///< the projection added to the input rate (0 without latitude)
  std::vector<Term> terms;        ///< the catalog terms present
};

struct SimulationSummary {
  Termination termination = Termination::kInvalidOptions;
  std::string message;
  Eigen::Index num_samples = 0;
};

struct SimulatedRecording {
  Eigen::VectorXd rate_rad_s;        ///< what the gyro outputs
  Eigen::VectorXd temperature_degC;  ///< the recorded aux temperature (true + noise); empty if none
  Eigen::VectorXd true_rate_rad_s;   ///< input rate + Earth rate: what a perfect gyro reads
  SimulationTruth truth;
  SimulationSummary summary;
};

/// Simulates one axis. Invalid options give summary.termination == kInvalidOptions and empty
/// vectors; the message says why.
SimulatedRecording SimulateGyro(const GyroSimulatorOptions& options);

}  // namespace fogpipe::simulation
