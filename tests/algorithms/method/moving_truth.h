// The moving-truth scenario grid that filters are judged by (docs/method.md, "Cautions": a
// filter that narrows the bandwidth looks better on static data whatever it does to the signal):
// 1 h records at 10 Hz whose true rate moves (steps, ramps, sines), white angle random walk
// N = 0.01 / 0.05 / 0.2 deg/sqrt(h), any number of seeds; and the RMS error of an estimate
// against the truth. Header-only so that every test of a filter can use it.
//
//   for (const MovingTruthRecord& r : MovingTruthGrid({1, 2, 3, 4, 5})) {
//     MethodResult m = RunMethod(r.rate_rad_s, r.sample_rate_hz, options);
//     double rms = RmsAgainstTruth(m.method1, m.preprocessed, r.true_rate_rad_s);
//   }
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "algorithms/common/units.h"
#include "algorithms/method/preprocess.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/rate_profile.h"

namespace fogpipe::method::testing {

struct MovingTruthScenario {
  std::string name;          ///< "steps", "ramps", "sines"
  std::string profile_text;  ///< simulation::ParseRateProfile spelling, deg/h
};

/// The three true-rate shapes. Amplitudes of 20-35 deg/h: between 0.5 and 10 x the per-sample
/// noise of the three N levels at 10 Hz (N sqrt(fs) = 1.9, 9.5, 38 deg/h).
inline const std::vector<MovingTruthScenario>& MovingTruthScenarios() {
  static const std::vector<MovingTruthScenario> s = {
      {"steps", "step:600:20,step:1500:-35,step:2400:25"},
      {"ramps", "ramp:300:1300:0.02,ramp:2000:3000:-0.03"},
      {"sines", "sine:0.002:20,sine:0.011:8"}};
  return s;
}

/// White angle random walk levels, deg/sqrt(h).
inline const std::vector<double>& MovingTruthNoiseLevels() {
  static const std::vector<double> n = {0.01, 0.05, 0.2};
  return n;
}

struct MovingTruthRecord {
  std::string scenario;
  double n_deg_sqrt_h = 0.0;
  std::uint64_t seed = 0;
  double sample_rate_hz = 10.0;
  Eigen::VectorXd rate_rad_s;       ///< what the gyro outputs
  Eigen::VectorXd true_rate_rad_s;  ///< the true rate
};

/// One record: 1 h at 10 Hz, true rate from the scenario, white noise N, nothing else.
inline MovingTruthRecord MakeMovingTruthRecord(const MovingTruthScenario& scenario,
                                               double n_deg_sqrt_h, std::uint64_t seed) {
  simulation::GyroSimulatorOptions o;
  o.sample_rate_hz = 10.0;
  o.duration_s = 3600.0;
  o.seed = seed;
  o.errors.n_rad_sqrt_s = units::DegPerSqrtHourToArw(n_deg_sqrt_h);
  std::string error;
  if (!simulation::ParseRateProfile(scenario.profile_text, &o.input_rate, &error)) {
    throw std::invalid_argument("moving truth profile: " + error);
  }
  simulation::SimulatedRecording sim = simulation::SimulateGyro(o);
  if (sim.rate_rad_s.size() == 0) throw std::runtime_error(sim.summary.message);
  MovingTruthRecord r;
  r.scenario = scenario.name;
  r.n_deg_sqrt_h = n_deg_sqrt_h;
  r.seed = seed;
  r.sample_rate_hz = o.sample_rate_hz;
  r.rate_rad_s = std::move(sim.rate_rad_s);
  r.true_rate_rad_s = std::move(sim.true_rate_rad_s);
  return r;
}

/// Every scenario x noise level x seed, in that nesting order. The seed of a record mixes the
/// given seed with its scenario and level, so records never share noise.
inline std::vector<MovingTruthRecord> MovingTruthGrid(const std::vector<std::uint64_t>& seeds) {
  std::vector<MovingTruthRecord> out;
  const auto& scenarios = MovingTruthScenarios();
  const auto& levels = MovingTruthNoiseLevels();
  for (std::size_t s = 0; s < scenarios.size(); ++s) {
    for (std::size_t l = 0; l < levels.size(); ++l) {
      for (std::uint64_t seed : seeds) {
        out.push_back(MakeMovingTruthRecord(scenarios[s], levels[l], seed * 100 + s * 10 + l));
      }
    }
  }
  return out;
}

/// RMS of (estimate + the removed mean) - truth over the analysed samples, units of the truth.
/// `estimate` is a mean-removed output of the method (method 1, method 2, a reference filter, or
/// the preprocessed signal itself for raw), `pre` the preprocessing it came from.
inline double RmsAgainstTruth(const Eigen::VectorXd& estimate, const Preprocessed& pre,
                              const Eigen::VectorXd& truth) {
  const Eigen::Index n = estimate.size();
  const Eigen::Index dropped = pre.summary.dropped_samples;
  return std::sqrt(
      ((estimate.array() + pre.mean_removed) - truth.segment(dropped, n).array()).square().mean());
}

}  // namespace fogpipe::method::testing
