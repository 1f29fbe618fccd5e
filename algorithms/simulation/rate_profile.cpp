#include "algorithms/simulation/rate_profile.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "algorithms/common/units.h"

namespace fogpipe::simulation {
namespace {

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream stream(text);
  while (std::getline(stream, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

bool ParseNumber(const std::string& text, double* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  *value = std::strtod(text.c_str(), &end);
  return errno == 0 && end == text.c_str() + text.size() && std::isfinite(*value);
}

}  // namespace

const char* ToString(RateComponent::Kind kind) {
  switch (kind) {
    case RateComponent::Kind::kConstant:
      return "constant";
    case RateComponent::Kind::kStep:
      return "step";
    case RateComponent::Kind::kRamp:
      return "ramp";
    case RateComponent::Kind::kSine:
      return "sine";
  }
  return "unknown";
}

bool RateProfile::IsValid(std::string* error) const {
  for (const RateComponent& c : components) {
    const bool finite = std::isfinite(c.value_rad_s) && std::isfinite(c.start_s) &&
                        std::isfinite(c.end_s) && std::isfinite(c.slope_rad_s2) &&
                        std::isfinite(c.frequency_hz) && std::isfinite(c.phase_rad);
    if (!finite) {
      if (error) *error = std::string("rate profile ") + ToString(c.kind) + ": non-finite value";
      return false;
    }
    if (c.kind == RateComponent::Kind::kRamp && !(c.end_s >= c.start_s)) {
      if (error) *error = "rate profile ramp: end time before start time";
      return false;
    }
    if (c.kind == RateComponent::Kind::kSine && !(c.frequency_hz > 0.0)) {
      if (error) *error = "rate profile sine: frequency must be > 0";
      return false;
    }
  }
  return true;
}

double EvaluateRateProfile(const RateProfile& profile, double t_s) {
  double rate = 0.0;
  for (const RateComponent& c : profile.components) {
    switch (c.kind) {
      case RateComponent::Kind::kConstant:
        rate += c.value_rad_s;
        break;
      case RateComponent::Kind::kStep:
        if (t_s >= c.start_s) rate += c.value_rad_s;
        break;
      case RateComponent::Kind::kRamp:
        rate += c.slope_rad_s2 * (std::clamp(t_s, c.start_s, c.end_s) - c.start_s);
        break;
      case RateComponent::Kind::kSine:
        rate += c.value_rad_s * std::sin(2.0 * units::kPi * c.frequency_hz * t_s + c.phase_rad);
        break;
    }
  }
  return rate;
}

Eigen::VectorXd SampleRateProfile(const RateProfile& profile, Eigen::Index n,
                                  double sample_rate_hz) {
  Eigen::VectorXd out(n);
  for (Eigen::Index k = 0; k < n; ++k) out[k] = EvaluateRateProfile(profile, k / sample_rate_hz);
  return out;
}

bool ParseRateProfile(const std::string& text, RateProfile* profile, std::string* error) {
  profile->components.clear();
  if (text.empty()) return true;
  for (const std::string& item : Split(text, ',')) {
    const std::vector<std::string> fields = Split(item, ':');
    std::vector<double> v;
    bool numbers_ok = true;
    for (size_t i = 1; i < fields.size(); ++i) {
      double x = 0.0;
      numbers_ok = numbers_ok && ParseNumber(fields[i], &x);
      v.push_back(x);
    }
    auto fail = [&](const std::string& why) {
      if (error) *error = "rate profile component '" + item + "': " + why;
      profile->components.clear();
      return false;
    };
    if (fields.empty() || fields[0].empty()) return fail("empty component");
    if (!numbers_ok) return fail("every field after the kind must be a finite number");
    const std::string& kind = fields[0];
    const double to_si = units::DegPerHourToRadPerSecond(1.0);
    RateComponent c;
    if (kind == "constant" && v.size() == 1) {
      c.kind = RateComponent::Kind::kConstant;
      c.value_rad_s = v[0] * to_si;
    } else if (kind == "step" && v.size() == 2) {
      c.kind = RateComponent::Kind::kStep;
      c.start_s = v[0];
      c.value_rad_s = v[1] * to_si;
    } else if (kind == "ramp" && v.size() == 3) {
      c.kind = RateComponent::Kind::kRamp;
      c.start_s = v[0];
      c.end_s = v[1];
      c.slope_rad_s2 = v[2] * to_si;
    } else if (kind == "sine" && (v.size() == 2 || v.size() == 3)) {
      c.kind = RateComponent::Kind::kSine;
      c.frequency_hz = v[0];
      c.value_rad_s = v[1] * to_si;
      c.phase_rad = v.size() == 3 ? v[2] * units::kRadPerDeg : 0.0;
    } else {
      return fail(
          "expected constant:W, step:T:S, ramp:T0:T1:SLOPE or sine:F:A[:PHASE_DEG] (deg/h, s, Hz)");
    }
    profile->components.push_back(c);
  }
  std::string why;
  if (!profile->IsValid(&why)) {
    if (error) *error = why;
    profile->components.clear();
    return false;
  }
  return true;
}

std::string FormatRateProfile(const RateProfile& profile) {
  std::ostringstream out;
  out.precision(17);
  const double to_deg_h = units::RadPerSecondToDegPerHour(1.0);
  for (size_t i = 0; i < profile.components.size(); ++i) {
    const RateComponent& c = profile.components[i];
    if (i > 0) out << ',';
    out << ToString(c.kind) << ':';
    switch (c.kind) {
      case RateComponent::Kind::kConstant:
        out << c.value_rad_s * to_deg_h;
        break;
      case RateComponent::Kind::kStep:
        out << c.start_s << ':' << c.value_rad_s * to_deg_h;
        break;
      case RateComponent::Kind::kRamp:
        out << c.start_s << ':' << c.end_s << ':' << c.slope_rad_s2 * to_deg_h;
        break;
      case RateComponent::Kind::kSine:
        out << c.frequency_hz << ':' << c.value_rad_s * to_deg_h << ':'
            << c.phase_rad * units::kDegPerRad;
        break;
    }
  }
  return out.str();
}

}  // namespace fogpipe::simulation
