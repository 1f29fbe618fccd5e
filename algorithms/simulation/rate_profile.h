// Rate-table input profiles: the true input rate a perfect gyro would read, for tests in which the
// truth moves (filter sweeps judged against the true rate). A profile is a sum of components, so
// steps, ramps and sinusoids compose freely. Values are the instantaneous rate at t (SI, rad/s).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace fogpipe::simulation {

struct RateComponent {
  enum class Kind {
    kConstant,  ///< value_rad_s for all t.
    kStep,      ///< adds value_rad_s for t >= start_s.
    kRamp,      ///< adds slope_rad_s2 * (clamp(t, start_s, end_s) - start_s): rises, then holds.
    kSine,      ///< adds value_rad_s * sin(2 pi frequency_hz t + phase_rad).
  };
  Kind kind = Kind::kConstant;
  double value_rad_s = 0.0;
  double start_s = 0.0;
  double end_s = 0.0;
  double slope_rad_s2 = 0.0;
  double frequency_hz = 0.0;
  double phase_rad = 0.0;
};

struct RateProfile {
  std::vector<RateComponent> components;  ///< Summed; empty means a rate of 0.
  bool IsValid(std::string* error) const;
};

/// The "kind" name used in text and JSON: "constant", "step", "ramp", "sine".
const char* ToString(RateComponent::Kind kind);

/// The input rate at t_s (rad/s).
double EvaluateRateProfile(const RateProfile& profile, double t_s);
/// The input rate at t_k = k / sample_rate_hz.
Eigen::VectorXd SampleRateProfile(const RateProfile& profile, Eigen::Index n,
                                  double sample_rate_hz);

/// Parses the CLI spelling, components separated by commas, rates in deg/h:
///   constant:W                    W deg/h from t = 0
///   step:T:S                      a step of S deg/h at T s
///   ramp:T0:T1:SLOPE              SLOPE deg/h per s from T0 s to T1 s, then held
///   sine:F:A[:PHASE]              A deg/h at F Hz, phase in deg (default 0)
/// e.g. "step:600:10,ramp:1200:1800:0.01,sine:0.01:5". An empty text gives an empty profile.
/// Returns false and sets *error (naming the component) on any malformed component.
bool ParseRateProfile(const std::string& text, RateProfile* profile, std::string* error);

/// The inverse of ParseRateProfile: the CLI spelling with 17 significant digits, so that parsing it
/// gives back the same profile to within one rounding of the deg/h <-> rad/s factor.
std::string FormatRateProfile(const RateProfile& profile);

}  // namespace fogpipe::simulation
