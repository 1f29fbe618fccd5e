#include "algorithms/simulation/rate_profile.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/units.h"

namespace fogpipe::simulation {
namespace {

double DegH(double deg_h) { return units::DegPerHourToRadPerSecond(deg_h); }

TEST(RateProfile, AnEmptyProfileIsAStaticTest) {
  EXPECT_EQ(EvaluateRateProfile(RateProfile{}, 123.0), 0.0);
}

TEST(RateProfile, ParsesTheDocumentedExampleAndSumsItsComponents) {
  RateProfile p;
  std::string error;
  ASSERT_TRUE(ParseRateProfile("step:600:10,ramp:1200:1800:0.01,sine:0.01:5", &p, &error)) << error;
  ASSERT_EQ(p.components.size(), 3u);
  auto sine = [](double t) { return 5.0 * std::sin(2.0 * units::kPi * 0.01 * t); };
  // Hand-evaluated in deg/h: before the step, after it, mid-ramp, after the ramp (held at +6).
  EXPECT_NEAR(EvaluateRateProfile(p, 599.9), DegH(sine(599.9)), 1e-18);
  EXPECT_NEAR(EvaluateRateProfile(p, 600.0), DegH(10.0 + sine(600.0)), 1e-18);
  EXPECT_NEAR(EvaluateRateProfile(p, 1500.0), DegH(10.0 + 3.0 + sine(1500.0)), 1e-18);
  EXPECT_NEAR(EvaluateRateProfile(p, 5000.0), DegH(10.0 + 6.0 + sine(5000.0)), 1e-18);
}

TEST(RateProfile, ConstantAndPhasedSineParseInDegPerHourAndDegrees) {
  RateProfile p;
  std::string error;
  ASSERT_TRUE(ParseRateProfile("constant:-3,sine:0.5:2:90", &p, &error)) << error;
  EXPECT_NEAR(EvaluateRateProfile(p, 0.0), DegH(-3.0 + 2.0), 1e-18);  // sin(90 deg) = 1
  EXPECT_NEAR(EvaluateRateProfile(p, 1.0), DegH(-3.0 - 2.0), 1e-18);  // half a period later
}

TEST(RateProfile, SamplingEvaluatesAtTheSampleTimes) {
  RateProfile p;
  std::string error;
  ASSERT_TRUE(ParseRateProfile("ramp:1:2:3600", &p, &error));  // 3600 deg/h per s = 1 deg/s^2
  const Eigen::VectorXd x = SampleRateProfile(p, 40, 10.0);
  EXPECT_EQ(x[10], 0.0);
  EXPECT_NEAR(x[15], DegH(1800.0), 1e-15);
  EXPECT_NEAR(x[30], DegH(3600.0), 1e-15);
}

TEST(RateProfile, RejectsMalformedComponentsAndNamesThem) {
  RateProfile p;
  std::string error;
  for (const char* bad : {"step:600", "ramp:10:5:1", "sine:0:3", "wobble:1", "step:abc:1",
                          "step:1:2,", "constant:1:2", "sine:0.1:nan"}) {
    error.clear();
    EXPECT_FALSE(ParseRateProfile(bad, &p, &error)) << bad;
    EXPECT_FALSE(error.empty()) << bad;
    EXPECT_TRUE(p.components.empty()) << bad;
  }
  ParseRateProfile("wobble:1", &p, &error);
  EXPECT_NE(error.find("wobble"), std::string::npos);
}

TEST(RateProfile, FormattingThenParsingGivesTheSameProfile) {
  RateProfile p;
  std::string error;
  ASSERT_TRUE(
      ParseRateProfile("constant:0.1,step:600:10,ramp:1200:1800:0.01,sine:0.013:5:33", &p, &error));
  RateProfile again;
  ASSERT_TRUE(ParseRateProfile(FormatRateProfile(p), &again, &error)) << error;
  ASSERT_EQ(again.components.size(), p.components.size());
  for (double t : {0.0, 599.0, 600.0, 1333.3, 1800.0, 4000.0}) {
    // Two roundings of the unit factor per value: a few ulp of ~1e-4 rad/s (ulp 1.4e-20).
    EXPECT_NEAR(EvaluateRateProfile(again, t), EvaluateRateProfile(p, t), 1e-18) << t;
  }
  EXPECT_EQ(FormatRateProfile(RateProfile{}), "");
}

}  // namespace
}  // namespace fogpipe::simulation
