#include "algorithms/simulation/temperature_profile.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/units.h"

namespace fogpipe::simulation {
namespace {

using units::kPi;

TemperatureProfile Chamber(double sharpness) {
  TemperatureProfile p;
  p.mean_degC = 23.0;
  p.peak_to_peak_degC = 10.0;
  p.period_s = 4000.0;
  p.sharpness = sharpness;
  p.phase_rad = 0.3;
  return p;
}

TEST(TemperatureProfile, SwingsExactlyByThePeakToPeakAroundTheMean) {
  for (double s : {0.0, 0.5, 2.0, 8.0}) {
    const TemperatureProfile p = Chamber(s);
    // theta = pi/2 and 3 pi/2 are the extremes of g for every sharpness.
    const double t_max = (kPi / 2.0 - p.phase_rad) / (2.0 * kPi) * p.period_s;
    const double t_min = t_max + 0.5 * p.period_s;
    EXPECT_NEAR(TrueTemperature(p, t_max), 28.0, 1e-12) << s;
    EXPECT_NEAR(TrueTemperature(p, t_min), 18.0, 1e-12) << s;
    // And no sample of a dense grid leaves [min, max].
    const Eigen::VectorXd x = SampleTrueTemperature(p, 40000, 10.0);
    EXPECT_LE(x.maxCoeff(), 28.0 + 1e-12);
    EXPECT_GE(x.minCoeff(), 18.0 - 1e-12);
    EXPECT_NEAR(x.maxCoeff() - x.minCoeff(), 10.0, 1e-5);  // grid step 0.1 s near flat extremes
  }
}

TEST(TemperatureProfile, RepeatsWithItsPeriodAndIsASineAtZeroSharpness) {
  const TemperatureProfile p = Chamber(2.0);
  for (double t : {0.0, 123.4, 2500.0}) {
    EXPECT_NEAR(TrueTemperature(p, t + p.period_s), TrueTemperature(p, t), 1e-12);
  }
  const TemperatureProfile sine = Chamber(0.0);
  for (double t : {0.0, 777.0, 3001.0}) {
    EXPECT_NEAR(TrueTemperature(sine, t), 23.0 + 5.0 * std::sin(2.0 * kPi * t / 4000.0 + 0.3),
                1e-12);
  }
}

TEST(TemperatureProfile, SharperCyclesSpendLongerNearThePlateaus) {
  // Fraction of time within 10 % of the swing from an extreme: arcsin-law 2 acos(0.8)/pi = 0.41
  // for the sine, larger for the smoothed trapezoid.
  auto near_plateau = [](double s) {
    const Eigen::VectorXd x = SampleTrueTemperature(Chamber(s), 40000, 10.0);
    return ((x.array() - 23.0).abs() > 4.0).cast<double>().mean();
  };
  EXPECT_NEAR(near_plateau(0.0), 2.0 * std::acos(0.8) / kPi, 1e-3);
  EXPECT_GT(near_plateau(2.0), 0.55);
}

TEST(TemperatureProfile, DerivativeMatchesACentralDifference) {
  for (double s : {0.0, 2.0, 5.0}) {
    const TemperatureProfile p = Chamber(s);
    const double h = 0.01;
    for (double t : {0.0, 100.0, 999.0, 2345.6, 3900.0}) {
      const double numeric = (TrueTemperature(p, t + h) - TrueTemperature(p, t - h)) / (2.0 * h);
      // Truncation h^2 T''' / 6 with |T'''| <= 5 (2 pi / 4000)^3 (1 + s)^3 ~ 1e-6 is < 1e-10;
      // rounding eps * 28 / h ~ 6e-13.
      EXPECT_NEAR(TrueTemperatureRate(p, t), numeric, 1e-9) << s << " " << t;
    }
  }
}

TEST(TemperatureProfile, MaxAbsRateIsReachedWhereTheCycleCrossesItsMean) {
  for (double s : {0.0, 2.0, 5.0}) {
    const TemperatureProfile p = Chamber(s);
    const Eigen::VectorXd rate = SampleTrueTemperatureRate(p, 40000, 10.0);
    EXPECT_NEAR(rate.cwiseAbs().maxCoeff() / MaxAbsTemperatureRate(p), 1.0, 1e-5) << s;
    EXPECT_LE(rate.cwiseAbs().maxCoeff(), MaxAbsTemperatureRate(p) * (1.0 + 1e-12));
  }
  EXPECT_NEAR(MaxAbsTemperatureRate(Chamber(0.0)), 5.0 * 2.0 * kPi / 4000.0, 1e-15);
}

TEST(TemperatureProfile, RejectsNonPhysicalSettings) {
  std::string error;
  TemperatureProfile p = Chamber(2.0);
  EXPECT_TRUE(p.IsValid(&error));
  p.period_s = 0.0;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("period"), std::string::npos);
  p = Chamber(2.0);
  p.noise_std_degC = -1.0;
  EXPECT_FALSE(p.IsValid(&error));
  p = Chamber(-1.0);
  EXPECT_FALSE(p.IsValid(&error));
}

}  // namespace
}  // namespace fogpipe::simulation
