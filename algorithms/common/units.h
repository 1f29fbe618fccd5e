// Units. Everything inside fogpipe is SI: rate in rad/s, angle in rad, time in s.
// Conversions to the units a gyro engineer reads (IEEE Std 952-1997 Annex C, IEEE Std 647) live
// here and nowhere else.
#pragma once

#include <optional>
#include <string>

namespace fogpipe::units {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegPerRad = 180.0 / kPi;
inline constexpr double kRadPerDeg = kPi / 180.0;
inline constexpr double kSecondsPerHour = 3600.0;
inline constexpr double kArcsecPerRad = kDegPerRad * 3600.0;
/// Earth's sidereal rotation rate, rad/s (IERS Conventions 2010, WGS 84). Used by the simulator and
/// by `compare` (bias net of the Earth-rate projection).
inline constexpr double kEarthRotationRateRadS = 7.2921150e-5;

/// The rate units a recording may declare (input contract v1: "deg/h", "deg/s", "rad/s").
enum class RateUnit { kDegPerHour, kDegPerSecond, kRadPerSecond };

/// Parses a `units` attribute. Returns nullopt for anything not in the contract.
std::optional<RateUnit> ParseRateUnit(const std::string& text);
/// The attribute spelling, e.g. "deg/h".
const char* ToString(RateUnit unit);
/// Multiply a rate in `unit` by this to get rad/s.
double ToRadPerSecond(RateUnit unit);

// The five IEEE noise terms. SI on the left, engineer's units on the right.
/// Quantization Q: rad -> arcsec.
inline double QuantizationToArcsec(double q_rad) { return q_rad * kArcsecPerRad; }
/// Angle random walk N: rad/sqrt(s) -> deg/sqrt(h)  (sqrt(3600 s) = 60 sqrt(s)).
inline double ArwToDegPerSqrtHour(double n_rad_per_sqrt_s) {
  return n_rad_per_sqrt_s * kDegPerRad * 60.0;
}
/// Bias instability B: rad/s -> deg/h.
inline double BiasToDegPerHour(double b_rad_per_s) { return b_rad_per_s * kDegPerRad * 3600.0; }
/// Rate random walk K: rad/s/sqrt(s) -> deg/h/sqrt(h).
inline double RrwToDegPerHourSqrtHour(double k_rad_per_s_sqrt_s) {
  return k_rad_per_s_sqrt_s * kDegPerRad * 3600.0 * 60.0;
}
/// Rate ramp R: rad/s^2 -> deg/h^2.
inline double RampToDegPerHour2(double r_rad_per_s2) {
  return r_rad_per_s2 * kDegPerRad * 3600.0 * 3600.0;
}
// Inverses, for simulators and configuration files written in engineer's units.
inline double ArcsecToQuantization(double q_arcsec) { return q_arcsec / kArcsecPerRad; }
inline double DegPerSqrtHourToArw(double n) { return n / (kDegPerRad * 60.0); }
inline double DegPerHourToBias(double b) { return b / (kDegPerRad * 3600.0); }
inline double DegPerHourSqrtHourToRrw(double k) { return k / (kDegPerRad * 3600.0 * 60.0); }
inline double DegPerHour2ToRamp(double r) { return r / (kDegPerRad * 3600.0 * 3600.0); }
/// Rate: rad/s <-> deg/h.
inline double RadPerSecondToDegPerHour(double w) { return w * kDegPerRad * 3600.0; }
inline double DegPerHourToRadPerSecond(double w) { return w / (kDegPerRad * 3600.0); }

// Unit names as written in HDF5 `units` attributes, JSON and printed tables.
inline constexpr const char* kQuantizationUnit = "arcsec";
inline constexpr const char* kArwUnit = "deg/sqrt(h)";
inline constexpr const char* kBiasUnit = "deg/h";
inline constexpr const char* kRrwUnit = "deg/h/sqrt(h)";
inline constexpr const char* kRampUnit = "deg/h^2";

}  // namespace fogpipe::units
