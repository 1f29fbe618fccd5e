#include "algorithms/common/units.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fogpipe::units {
namespace {

// IEEE Std 952-1997 Annex C: 1 deg/sqrt(h) = (pi/180)/60 rad/sqrt(s).
TEST(Units, AngleRandomWalkOfOneDegPerSqrtHourIsPiOver10800RadPerSqrtS) {
  EXPECT_NEAR(DegPerSqrtHourToArw(1.0), kPi / 180.0 / 60.0, 1e-18);
  EXPECT_NEAR(ArwToDegPerSqrtHour(DegPerSqrtHourToArw(0.005)), 0.005, 1e-15);
}

TEST(Units, EarthRateIsAbout15DegPerHour) {
  const double earth_rad_s = 7.2921150e-5;
  EXPECT_NEAR(RadPerSecondToDegPerHour(earth_rad_s), 15.041, 1e-3);
}

TEST(Units, EveryTermRoundTripsThroughEngineerUnits) {
  EXPECT_NEAR(QuantizationToArcsec(ArcsecToQuantization(0.1)), 0.1, 1e-15);
  EXPECT_NEAR(BiasToDegPerHour(DegPerHourToBias(0.003)), 0.003, 1e-15);
  EXPECT_NEAR(RrwToDegPerHourSqrtHour(DegPerHourSqrtHourToRrw(0.004)), 0.004, 1e-15);
  EXPECT_NEAR(RampToDegPerHour2(DegPerHour2ToRamp(0.02)), 0.02, 1e-15);
}

TEST(Units, ParsesOnlyTheContractRateUnits) {
  EXPECT_EQ(ParseRateUnit("deg/h"), RateUnit::kDegPerHour);
  EXPECT_EQ(ParseRateUnit("deg/s"), RateUnit::kDegPerSecond);
  EXPECT_EQ(ParseRateUnit("rad/s"), RateUnit::kRadPerSecond);
  EXPECT_FALSE(ParseRateUnit("dps").has_value());
  EXPECT_DOUBLE_EQ(ToRadPerSecond(RateUnit::kDegPerSecond), kPi / 180.0);
}

}  // namespace
}  // namespace fogpipe::units
