#include "algorithms/model/compensate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace fogpipe::model {
namespace {

TEST(Compensate, SubtractsExactlyTheModelledEffects) {
  const double fs = 2.0;
  const long n = 4000;
  Eigen::VectorXd t(n), rate(n), temp(n);
  for (long i = 0; i < n; ++i) {
    const double s = i / fs;
    temp[i] = 20.0 + 3.0 * std::sin(2 * M_PI * s / 900.0);
    rate[i] =
        0.5 + 0.01 * (temp[i] - 20.0) + (s >= 1000.0 ? 0.2 : 0.0) + 0.3 * std::exp(-s / 100.0);
  }
  DeterministicModel m;
  m.bias_rad_s = 0.5;
  m.temperature_ref_degc = 20.0;
  m.components.push_back({Term::kTemperature, 0.0, 0.0, {0.01}, {0.0}, 0.0, "", {}, {}});
  m.components.push_back({Term::kBiasStep, 1000.0, 0.0, {0.2}, {0.0}, 0.0, "", {}, {}});
  m.components.push_back({Term::kWarmup, 100.0, 0.0, {0.3}, {0.0}, 0.0, "", {}, {}});
  CompensateOptions o;
  o.subtract_bias = true;
  const Compensation c = Compensate(rate, fs, &temp, m, o);
  ASSERT_EQ(c.summary.termination, Termination::kSuccess);
  EXPECT_EQ(c.summary.num_effects, 3);
  // Closed form in, closed form out: only rounding (the exp recurrence is re-anchored).
  EXPECT_LT(c.rate_rad_s.cwiseAbs().maxCoeff(), 1e-12);
  o.subtract_bias = false;
  EXPECT_NEAR(Compensate(rate, fs, &temp, m, o).rate_rad_s.mean(), 0.5, 1e-12);
}

TEST(Compensate, AThermalModelNeedsTheTemperature) {
  DeterministicModel m;
  m.components.push_back({Term::kTemperatureRate, 0.0, 0.0, {1.0}, {0.0}, 0.0, "", {}, {}});
  const Eigen::VectorXd rate = Eigen::VectorXd::Zero(100);
  EXPECT_EQ(Compensate(rate, 1.0, nullptr, m, {}).summary.termination,
            Termination::kInsufficientData);
}

TEST(Compensate, SubtractsAnAuxPolynomialEvaluatedOnItsOwnChannel) {
  // aux:supply_voltage of order 2 about the channel's fitted mean: c1 (v - v_ref) + c2 (v -
  // v_ref)^2, written out here in closed form.
  const double fs = 10.0, v_ref = 28.0, c1 = 2e-6, c2 = -5e-7;
  const long n = 3000;
  Eigen::VectorXd rate(n), volts(n), other(n);
  for (long i = 0; i < n; ++i) {
    volts[i] = v_ref + 0.4 * std::sin(2 * M_PI * i / 700.0) + 0.1 * std::cos(2 * M_PI * i / 37.0);
    other[i] = 1000.0 + i;
    const double d = volts[i] - v_ref;
    rate[i] = 1e-5 + c1 * d + c2 * d * d;
  }
  DeterministicModel m;
  m.bias_rad_s = 1e-5;
  m.components.push_back({ModelTerm::Aux(AuxForm::kValue, "supply_voltage"),
                          0.0,
                          0.0,
                          {c1, c2},
                          {0.0, 0.0},
                          v_ref,
                          "V"});
  // The channel is found by name among others.
  const std::vector<AuxSeries> aux = {{"pressure", "hPa", &other}, {"supply_voltage", "V", &volts}};
  const Compensation c = Compensate(rate, fs, aux, m, {});
  ASSERT_EQ(c.summary.termination, Termination::kSuccess) << c.summary.message;
  EXPECT_EQ(c.summary.num_effects, 1);
  EXPECT_LT((c.rate_rad_s.array() - 1e-5).abs().maxCoeff(), 1e-18);
}

TEST(Compensate, SubtractsAnAmLineWhoseAmplitudeFollowsItsChannel) {
  // aux_am:supply_voltage: (c0 + c1 (V - V_ref)) cos(2 pi f t) + (s0 + s1 (V - V_ref)) sin(2 pi f
  // t), written out with std::cos / std::sin. The evaluation's rotation recurrence (re-anchored
  // every 1024 samples) and both sides' rounding of the phase (2 pi f t <= 2.3e4 rad at 36000
  // samples: ~5e-12 rad) leave ~1e-17 on a 1.5e-6 rad/s envelope: bound 1e-15.
  const double fs = 10.0, f = 1.3, v_ref = 28.0, c0 = 1e-6, s0 = -5e-7, c1 = 2e-6, s1 = 1e-6;
  const long n = 36000;
  Eigen::VectorXd rate(n), volts(n);
  for (long i = 0; i < n; ++i) {
    volts[i] = v_ref + 0.2 * std::sin(2 * M_PI * i / (fs * 900.0));
    const double w = 2 * M_PI * f * i / fs, d = volts[i] - v_ref;
    rate[i] = 1e-5 + (c0 + c1 * d) * std::cos(w) + (s0 + s1 * d) * std::sin(w);
  }
  DeterministicModel m;
  m.components.push_back({ModelTerm::Aux(AuxForm::kAm, "supply_voltage"),
                          f,
                          0.0,
                          {c0, s0, c1, s1},
                          {0.0, 0.0, 0.0, 0.0},
                          v_ref,
                          "V"});
  const Compensation c = Compensate(rate, fs, {{"supply_voltage", "V", &volts}}, m, {});
  ASSERT_EQ(c.summary.termination, Termination::kSuccess) << c.summary.message;
  EXPECT_LT((c.rate_rad_s.array() - 1e-5).abs().maxCoeff(), 1e-15);
}

TEST(Compensate, SubtractsAHysteresisTermWithTheDeadBandItWasFittedWith) {
  // aux_hysteresis:supply_voltage on a triangle wave (period 600 s at 10 Hz, +-0.5 V): +c while
  // the voltage rises, -c while it falls, written out in closed form. Its slope, 1/300 V/s, is 33
  // times the stored dead band, and the 120 s window's slope is exact on a straight line: the
  // state can differ from the closed form only within the half-window (60 s) of a turn, where the
  // smoothed slope passes through zero at the turn itself and the band holds the state for the
  // ~2 s it takes to cross it.
  const double fs = 10.0, c = 3e-6, band = 1e-4;
  const long n = 36000;
  Eigen::VectorXd rate(n), volts(n);
  for (long i = 0; i < n; ++i) {
    const double phase = std::fmod(i / fs, 600.0) / 600.0;
    const bool rising = phase < 0.5;
    volts[i] = 28.0 + (rising ? -0.5 + 2 * phase : 1.5 - 2 * phase);
    rate[i] = 1e-5 + (rising ? c : -c);
  }
  DeterministicModel m;
  m.components.push_back(
      {ModelTerm::Aux(AuxForm::kHysteresis, "supply_voltage"), 0.0, 0.0, {c}, {0.0}, band, "V"});
  const Compensation k = Compensate(rate, fs, {{"supply_voltage", "V", &volts}}, m, {});
  ASSERT_EQ(k.summary.termination, Termination::kSuccess) << k.summary.message;
  const Eigen::ArrayXd left = k.rate_rad_s.array() - 1e-5;
  // Away from the turns (more than the 60 s half-window from each), exactly the bias is left.
  long off = 0;
  for (long i = 0; i < n; ++i) {
    const double into_half = std::fmod(i / fs, 300.0);
    if (into_half > 60.0 && into_half < 240.0) {
      EXPECT_LT(std::abs(left[i]), 1e-18) << i;
    }
    off += std::abs(left[i]) > 1e-18;
  }
  // Near the turns the switch falls where the smoothed slope crosses zero, the turn itself.
  EXPECT_LT(off, n / 100);
}

TEST(Compensate, RefusesAnAuxTermWhoseChannelIsMissingShortOrInOtherUnits) {
  DeterministicModel m;
  m.components.push_back(
      {ModelTerm::Aux(AuxForm::kRate, "supply_voltage"), 0.0, 0.0, {1.0}, {0.0}, 28.0, "V"});
  const Eigen::VectorXd rate = Eigen::VectorXd::Zero(100), volts = Eigen::VectorXd::Ones(100),
                        short_volts = Eigen::VectorXd::Ones(99);
  struct Case {
    std::vector<AuxSeries> aux;
    const char* expected;
  } cases[] = {
      {{}, "which is not there"},
      {{{"temperature", "degC", &volts}}, "which is not there"},
      {{{"supply_voltage", "V", &short_volts}}, "it has 99"},
      {{{"supply_voltage", "mV", &volts}},
       "fitted on /aux/supply_voltage in V, but the channel here is in mV"},
  };
  for (const Case& k : cases) {
    const Compensation c = Compensate(rate, 1.0, k.aux, m, {});
    EXPECT_EQ(c.summary.termination, Termination::kInsufficientData);
    EXPECT_EQ(c.rate_rad_s.size(), 0);
    EXPECT_NE(c.summary.message.find("aux_rate:supply_voltage"), std::string::npos)
        << c.summary.message;
    EXPECT_NE(c.summary.message.find(k.expected), std::string::npos) << c.summary.message;
  }
  EXPECT_EQ(Compensate(rate, 1.0, {{"supply_voltage", "V", &volts}}, m, {}).summary.termination,
            Termination::kSuccess);
}

}  // namespace
}  // namespace fogpipe::model
