// The hidden-effect proof of issue 4 on simulated navigation-grade recordings (6 h at 10 Hz,
// aux temperature cycling 6-12 degC with a 1-2 h period in every file). Effect sizes:
// hidden_effects.h. Seeds: 101-103 for each effect, 201-220 for the control, 301-302 for two
// effects, 401-418 for thermal innocence. The development runs that chose the design used seeds
// 1-20 (each effect) and 500-539 (effect-free: 2 of 40 inconsistent, none with a suggestion).
// The truth is read only to score.
#include "algorithms/model/compare.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/units.h"
#include "hidden_effects.h"

namespace fogpipe::model {
namespace {

namespace sim = fogpipe::simulation;
using testing::MakeHiddenCase;

const Parameter* Param(const std::vector<Parameter>& ps, const std::string& name) {
  for (const auto& p : ps)
    if (p.name == name) return &p;
  return nullptr;
}

double RelErr(double est, double truth) { return std::abs(est - truth) / std::abs(truth); }
double DegH(double rad_s) { return units::RadPerSecondToDegPerHour(rad_s); }

bool Blames(const CompareResult& r, Term t) {
  for (const auto& s : r.suggestions)
    if (s.term == t) return true;
  return false;
}

// Parameters of the first suggestion against the truth: coefficients and amplitudes 10 %,
// frequency 2 %, step time 1 % of the record, correlation time and warm-up constant 25 %.
void ExpectParametersNearTruth(sim::Term effect, const sim::SimulatedRecording& rec,
                               const std::vector<Parameter>& p) {
  const auto& e = rec.truth.options.errors;
  const double record = rec.truth.options.duration_s;
  switch (effect) {
    case sim::Term::kTemperature:
      EXPECT_LT(
          RelErr(Param(p, "coefficient")->value, DegH(e.temperature->coefficient_rad_s_per_degC)),
          0.10);
      break;
    case sim::Term::kTemperatureRate:
      EXPECT_LT(RelErr(Param(p, "coefficient")->value,
                       DegH(e.temperature_rate->coefficient_rad_s_per_degC_per_s)),
                0.10);
      break;
    case sim::Term::kSinusoid:
      EXPECT_LT(RelErr(Param(p, "frequency")->value, e.sinusoids[0].frequency_hz), 0.02);
      EXPECT_LT(
          RelErr(Param(p, "amplitude")->value, DegH(std::abs(e.sinusoids[0].amplitude_rad_s))),
          0.10);
      break;
    case sim::Term::kGaussMarkov:
      EXPECT_LT(RelErr(Param(p, "correlation_time")->value, e.gauss_markov[0].correlation_time_s),
                0.25);
      EXPECT_LT(RelErr(Param(p, "sigma")->value, DegH(e.gauss_markov[0].sigma_rad_s)), 0.10);
      break;
    case sim::Term::kBiasStep:
      EXPECT_LT(std::abs(Param(p, "time")->value - e.bias_steps[0].time_s), 0.01 * record);
      EXPECT_LT(RelErr(Param(p, "size")->value, DegH(e.bias_steps[0].size_rad_s)), 0.10);
      break;
    case sim::Term::kWarmup:
      EXPECT_LT(RelErr(Param(p, "amplitude")->value, DegH(e.warmup->amplitude_rad_s)), 0.10);
      EXPECT_LT(RelErr(Param(p, "time_constant")->value, e.warmup->time_constant_s), 0.25);
      break;
    default:
      FAIL();
  }
}

// The failures point to the right place.
void ExpectFailuresPointAt(sim::Term effect, const sim::SimulatedRecording& rec,
                           const std::vector<Failure>& failures) {
  const auto& e = rec.truth.options.errors;
  bool found = false;
  for (const auto& f : failures) {
    switch (effect) {
      case sim::Term::kSinusoid: {
        // A tau range containing 0.371/f0, or the line's band, which maps onto that tau (at
        // navigation-grade ARW a line at 1/300..1/20 Hz is a few % of the Allan variance at
        // 0.371/f0: the frequency view is where it is significant).
        const double f0 = e.sinusoids[0].frequency_hz, tau0 = 0.371 / f0;
        found |= (f.domain == "tau" && f.from <= tau0 && tau0 <= f.to) ||
                 (f.domain == "frequency" && f.from <= f0 && f0 <= f.to);
        break;
      }
      case sim::Term::kBiasStep:
        found |= f.domain == "time" && f.from <= e.bias_steps[0].time_s &&
                 e.bias_steps[0].time_s <= f.to;
        break;
      case sim::Term::kWarmup:
        found |= f.domain == "time" && f.from <= 0.0;
        break;
      case sim::Term::kTemperature:
        found |= f.domain == "aux" && f.channel == "temperature";
        break;
      case sim::Term::kTemperatureRate:
        found |= f.domain == "aux" && f.channel == "d(temperature)/dt";
        break;
      case sim::Term::kGaussMarkov: {
        const double tau0 = 1.89 * e.gauss_markov[0].correlation_time_s;
        found |= f.domain == "tau" && f.from <= tau0 && tau0 <= f.to;
        break;
      }
      default:
        break;
    }
  }
  EXPECT_TRUE(found) << "no failure at the hidden " << sim::ToString(effect);
}

class HiddenEffect : public ::testing::TestWithParam<std::tuple<sim::Term, int>> {};

TEST_P(HiddenEffect, IsFoundNamedEstimatedAndFixed) {
  const auto [effect, seed] = GetParam();
  const auto c = MakeHiddenCase(seed, {effect});
  const CompareOptions options;
  const CompareResult before = Compare(c.input, DefaultTerms(), options);
  ASSERT_TRUE(HasResult(before.summary.termination)) << before.summary.message;
  EXPECT_FALSE(before.base.views.consistent) << "error " << before.base.views.error;
  ASSERT_FALSE(before.suggestions.empty());
  const Term hidden = testing::AnalysisTerm(effect);
  EXPECT_EQ(before.suggestions[0].term, hidden)
      << "first: " << ToString(before.suggestions[0].term);
  if (before.suggestions[0].term != hidden) return;
  ExpectParametersNearTruth(effect, c.recording, before.suggestions[0].parameters);
  ExpectFailuresPointAt(effect, c.recording, before.base.views.failures);
  std::vector<Term> terms = DefaultTerms();
  terms.push_back(hidden);
  const Evaluation after = EvaluateModel(c.input, terms, options);
  EXPECT_LE(3.0 * after.views.error, before.base.views.error)
      << before.base.views.error << " -> " << after.views.error;
  EXPECT_TRUE(after.views.consistent) << "error after " << after.views.error;
}

std::string Name(const ::testing::TestParamInfo<std::tuple<sim::Term, int>>& info) {
  return std::string(sim::ToString(std::get<0>(info.param))) + "_seed" +
         std::to_string(std::get<1>(info.param));
}

INSTANTIATE_TEST_SUITE_P(
    Compare, HiddenEffect,
    ::testing::Combine(::testing::Values(sim::Term::kTemperature, sim::Term::kTemperatureRate,
                                         sim::Term::kSinusoid, sim::Term::kGaussMarkov,
                                         sim::Term::kBiasStep, sim::Term::kWarmup),
                       ::testing::Values(101, 102, 103)),
    Name);

TEST(Compare, TheDefaultModelIsConsistentWithoutHiddenEffects) {
  // Control over 20 seeds: something is suggested in at most 10 % of them (2), temperature in at
  // most 5 % (1). Suggestions only exist when the model is inconsistent.
  int suggested = 0, temperature = 0;
  for (int seed = 201; seed <= 220; ++seed) {
    const auto c = MakeHiddenCase(seed, {});
    const CompareResult r = Compare(c.input, DefaultTerms(), {});
    suggested += r.suggestions.empty() ? 0 : 1;
    temperature += Blames(r, Term::kTemperature) || Blames(r, Term::kTemperatureRate);
  }
  EXPECT_LE(suggested, 2);
  EXPECT_LE(temperature, 1);
}

TEST(Compare, TemperatureIsNotBlamedWhereItIsInnocent) {
  // Non-thermal effects (4 effects x 3 seeds, seeds 401-403) plus 8 effect-free seeds
  // (411-418): at most 5 % of these 20 recordings (1) may blame a thermal term.
  int blamed = 0, total = 0;
  for (sim::Term effect :
       {sim::Term::kSinusoid, sim::Term::kGaussMarkov, sim::Term::kBiasStep, sim::Term::kWarmup}) {
    for (int seed = 401; seed <= 403; ++seed) {
      const auto c = MakeHiddenCase(seed, {effect});
      const CompareResult r = Compare(c.input, DefaultTerms(), {});
      blamed += Blames(r, Term::kTemperature) || Blames(r, Term::kTemperatureRate);
      ++total;
    }
  }
  for (int seed = 411; seed <= 418; ++seed) {
    const auto c = MakeHiddenCase(seed, {});
    const CompareResult r = Compare(c.input, DefaultTerms(), {});
    blamed += Blames(r, Term::kTemperature) || Blames(r, Term::kTemperatureRate);
    ++total;
  }
  EXPECT_EQ(total, 20);
  EXPECT_LE(blamed, 1);
}

TEST(Compare, TwoHiddenEffectsAreFoundOneAfterTheOther) {
  for (int seed : {301, 302}) {
    const auto c = MakeHiddenCase(seed, {sim::Term::kTemperature, sim::Term::kSinusoid});
    const CompareOptions o;
    std::vector<Term> terms = DefaultTerms();
    const CompareResult first = Compare(c.input, terms, o);
    ASSERT_FALSE(first.suggestions.empty()) << "seed " << seed;
    const Term a = first.suggestions[0].term;
    EXPECT_TRUE(a == Term::kTemperature || a == Term::kSinusoid) << ToString(a);
    terms.push_back(a);
    const CompareResult second = Compare(c.input, terms, o);
    EXPECT_LT(second.base.views.error, first.base.views.error);
    ASSERT_FALSE(second.suggestions.empty()) << "seed " << seed;
    const Term b = second.suggestions[0].term;
    EXPECT_EQ(b, a == Term::kTemperature ? Term::kSinusoid : Term::kTemperature) << ToString(b);
    terms.push_back(b);
    const Evaluation last = EvaluateModel(c.input, terms, o);
    EXPECT_TRUE(last.views.consistent) << "error " << last.views.error;
  }
}

}  // namespace
}  // namespace fogpipe::model
