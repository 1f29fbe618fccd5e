#include "algorithms/common/units.h"

namespace fogpipe::units {

std::optional<RateUnit> ParseRateUnit(const std::string& text) {
  if (text == "deg/h") return RateUnit::kDegPerHour;
  if (text == "deg/s") return RateUnit::kDegPerSecond;
  if (text == "rad/s") return RateUnit::kRadPerSecond;
  return std::nullopt;
}

const char* ToString(RateUnit unit) {
  switch (unit) {
    case RateUnit::kDegPerHour:
      return "deg/h";
    case RateUnit::kDegPerSecond:
      return "deg/s";
    case RateUnit::kRadPerSecond:
      return "rad/s";
  }
  return "?";
}

double ToRadPerSecond(RateUnit unit) {
  switch (unit) {
    case RateUnit::kDegPerHour:
      return kRadPerDeg / kSecondsPerHour;
    case RateUnit::kDegPerSecond:
      return kRadPerDeg;
    case RateUnit::kRadPerSecond:
      return 1.0;
  }
  return 1.0;
}

}  // namespace fogpipe::units
