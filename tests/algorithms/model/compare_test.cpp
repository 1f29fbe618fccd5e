// The hidden-effect proof of `fogpipe compare` on simulated navigation-grade recordings (6 h at
// 10 Hz, aux temperature cycling 6-12 degC with a 1-2 h period in every file). Effect sizes:
// hidden_effects.h. Seeds: 101-110 for each effect (101-103 for its size), 201-220 for the control,
// 301-302 for two effects, 401-418 for thermal innocence, 711-714 and 721-723 for the aux terms,
// 801-830 for the aux controls, 101-110 for the thermal hysteresis (4x and 8x) and its K-30x
// control. The development runs that chose the design used seeds 1-20 (each effect, each aux
// effect, the hysteresis), 500-539 (effect-free: 2 of 40 inconsistent, none with a suggestion),
// 850-889 (aux controls) and 1-40 (K-30x control). The truth is read only to score.
#include "algorithms/model/compare.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <optional>
#include <random>
#include <sstream>

#include "algorithms/common/units.h"
#include "algorithms/simulation/navigation_grade.h"
#include "hidden_effects.h"
#include "independent_records.h"

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

// A thermal term among the suggestions: temperature, temperature_rate or an aux term of the
// temperature channel (aux:temperature, the polynomial that contains the temperature term).
bool BlamesTemperature(const CompareResult& r) {
  for (const auto& s : r.suggestions)
    if (AuxChannelOf(s.term) == "temperature") return true;
  return false;
}

// Parameters of the first suggestion against the truth: coefficients and amplitudes 10 %,
// frequency 2 %, step time 1 % of the record, correlation time and warm-up constant 25 %. Each
// entry: name, |estimate - truth| / tolerance (the criterion holds when < 1).
std::vector<std::pair<std::string, double>> ParameterErrors(sim::Term effect,
                                                            const sim::SimulatedRecording& rec,
                                                            const std::vector<Parameter>& p) {
  const auto& e = rec.truth.options.errors;
  const double record = rec.truth.options.duration_s;
  auto rel = [&](const char* name, double truth, double tol) {
    const Parameter* q = Param(p, name);
    return std::make_pair(std::string(name),
                          q ? RelErr(q->value, truth) / tol : std::numeric_limits<double>::max());
  };
  switch (effect) {
    case sim::Term::kTemperature:
      return {rel("coefficient", DegH(e.temperature->coefficient_rad_s_per_degC), 0.10)};
    case sim::Term::kTemperatureRate:
      return {rel("coefficient", DegH(e.temperature_rate->coefficient_rad_s_per_degC_per_s), 0.10)};
    case sim::Term::kSinusoid:
      return {rel("frequency", e.sinusoids[0].frequency_hz, 0.02),
              rel("amplitude", DegH(std::abs(e.sinusoids[0].amplitude_rad_s)), 0.10)};
    case sim::Term::kGaussMarkov:
      return {rel("correlation_time", e.gauss_markov[0].correlation_time_s, 0.25),
              rel("sigma", DegH(e.gauss_markov[0].sigma_rad_s), 0.10)};
    case sim::Term::kBiasStep: {
      const Parameter* t = Param(p, "time");
      return {{"time", t ? std::abs(t->value - e.bias_steps[0].time_s) / (0.01 * record)
                         : std::numeric_limits<double>::max()},
              rel("size", DegH(e.bias_steps[0].size_rad_s), 0.10)};
    }
    case sim::Term::kWarmup:
      return {rel("amplitude", DegH(e.warmup->amplitude_rad_s), 0.10),
              rel("time_constant", e.warmup->time_constant_s, 0.25)};
    default:
      return {};
  }
}

// The failures point to the right place.
bool FailuresPointAt(sim::Term effect, const sim::SimulatedRecording& rec,
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
        found |= (f.domain == ViewDomain::kTau && f.from <= tau0 && tau0 <= f.to) ||
                 (f.domain == ViewDomain::kFrequency && f.from <= f0 && f0 <= f.to);
        break;
      }
      case sim::Term::kBiasStep:
        found |= f.domain == ViewDomain::kTime && f.from <= e.bias_steps[0].time_s &&
                 e.bias_steps[0].time_s <= f.to;
        break;
      case sim::Term::kWarmup:
        found |= f.domain == ViewDomain::kTime && f.from <= 0.0;
        break;
      case sim::Term::kTemperature:
        found |= f.domain == ViewDomain::kAux && f.channel == "temperature";
        break;
      case sim::Term::kTemperatureRate:
        found |= f.domain == ViewDomain::kAux && f.channel == "d(temperature)/dt";
        break;
      case sim::Term::kGaussMarkov: {
        const double tau0 = 1.89 * e.gauss_markov[0].correlation_time_s;
        found |= f.domain == ViewDomain::kTau && f.from <= tau0 && tau0 <= f.to;
        break;
      }
      default:
        break;
    }
  }
  return found;
}

// Every criterion of the hidden-effect proof on one recording.
struct ProofScore {
  bool default_inconsistent = false;
  bool first_is_hidden = false;
  std::string first;  // the first suggestion's term, "none" without one
  std::vector<std::pair<std::string, double>> parameter_errors;  // error / tolerance
  bool failures_point_at_it = false;
  double error_before = 0, error_after = 0;
  bool error_falls_3x = false;
  bool consistent_after = false;
  bool ParametersNearTruth() const {
    if (parameter_errors.empty()) return false;
    for (const auto& [name, x] : parameter_errors)
      if (!(x < 1.0)) return false;
    return true;
  }
};

ProofScore ScoreProof(sim::Term effect, const testing::HiddenCase& c) {
  ProofScore s;
  const CompareOptions options;
  const CompareResult before = Compare(c.input, DefaultTerms(), options);
  if (!HasResult(before.summary.termination)) return s;
  s.error_before = before.base.views.error;
  s.default_inconsistent = !before.base.views.consistent;
  s.failures_point_at_it = FailuresPointAt(effect, c.recording, before.base.views.failures);
  const Term hidden = testing::AnalysisTerm(effect);
  s.first = before.suggestions.empty() ? "none" : ToString(before.suggestions[0].term);
  s.first_is_hidden = !before.suggestions.empty() && before.suggestions[0].term == hidden;
  // The parameters and the error after adding the effect are scored whatever was suggested: the
  // trial of the hidden term is the model the engineer would fit once told what to add.
  std::vector<ModelTerm> terms = DefaultTerms();
  terms.push_back(hidden);
  const Evaluation after = EvaluateModel(c.input, terms, options);
  s.parameter_errors = ParameterErrors(effect, c.recording, ParametersOf(after, hidden));
  s.error_after = after.views.error;
  s.error_falls_3x = 3.0 * after.views.error <= before.base.views.error;
  s.consistent_after = after.views.consistent;
  return s;
}

// The proof on CI seeds 101-110, as rates (statistics over seeds, not single cases), each
// criterion bounded from its own design rate (hidden_effects.h, docs/compare.md): most passed on
// 19-20 of 20 design seeds (0.95: at least 8 of 10, P(X <= 7) = 1.2 % for Binomial(10, 0.95));
// temperature's parameters on 53 of 60 (0.88: at least 7, P(X <= 6) = 2.4 %); Gauss-Markov's
// parameters and consistency after on 17 and 16 of 20 (0.8: at least 6, P(X <= 5) = 3.3 %).
class HiddenEffect : public ::testing::TestWithParam<sim::Term> {};

TEST_P(HiddenEffect, IsFoundNamedEstimatedAndFixedOnMostSeeds) {
  const sim::Term effect = GetParam();
  int inconsistent = 0, first = 0, parameters = 0, pointed = 0, falls = 0, consistent = 0;
  for (int seed = 101; seed <= 110; ++seed) {
    const ProofScore s = ScoreProof(effect, MakeHiddenCase(seed, {effect}));
    inconsistent += s.default_inconsistent;
    first += s.first_is_hidden;
    parameters += s.ParametersNearTruth();
    pointed += s.failures_point_at_it;
    falls += s.error_falls_3x;
    consistent += s.consistent_after;
    std::printf(
        "%s seed %d: inconsistent %d first %d (%s) parameters %d pointed %d error %.3g -> "
        "%.3g consistent %d\n",
        sim::ToString(effect), seed, s.default_inconsistent, s.first_is_hidden, s.first.c_str(),
        s.ParametersNearTruth(), s.failures_point_at_it, s.error_before, s.error_after,
        s.consistent_after);
  }
  const bool gauss_markov = effect == sim::Term::kGaussMarkov;
  EXPECT_GE(inconsistent, 8);
  EXPECT_GE(first, 8);
  EXPECT_GE(parameters, gauss_markov ? 6 : effect == sim::Term::kTemperature ? 7 : 8);
  EXPECT_GE(pointed, 8);
  EXPECT_GE(falls, 8);
  EXPECT_GE(consistent, gauss_markov ? 6 : 8);
}

std::string Name(const ::testing::TestParamInfo<sim::Term>& info) {
  return sim::ToString(info.param);
}

INSTANTIATE_TEST_SUITE_P(Compare, HiddenEffect,
                         ::testing::Values(sim::Term::kTemperature, sim::Term::kTemperatureRate,
                                           sim::Term::kSinusoid, sim::Term::kGaussMarkov,
                                           sim::Term::kBiasStep, sim::Term::kWarmup),
                         Name);

// The size claim of hidden_effects.h, measured: each hidden effect's peak Allan signature over
// the noise model's Allan deviation (PeakAllanSignature), for the CI seeds. The ranges are the
// design's (measured over design seeds 1-20, hidden_effects.h); a resizing that leaves them fails
// here. The signature of a simulated step is also checked against its closed form.
TEST(HiddenEffectSize, IsAFewTimesTheNoiseFloorAtTheTauWhereItShows) {
  struct Range {
    sim::Term effect;
    double lo, hi;
  };
  int closed_form_checks = 0;
  for (const Range& r :
       {Range{sim::Term::kSinusoid, 1.4, 2.5}, Range{sim::Term::kWarmup, 1.5, 4.0},
        Range{sim::Term::kTemperature, 3.0, 6.5}, Range{sim::Term::kTemperatureRate, 4.5, 7.5},
        Range{sim::Term::kBiasStep, 5.5, 8.5}, Range{sim::Term::kGaussMarkov, 7.5, 16.0}}) {
    for (int seed = 101; seed <= 103; ++seed) {
      const sim::GyroSimulatorOptions o = testing::HiddenEffectOptions(seed, {r.effect});
      const testing::AllanSignature s = testing::PeakAllanSignature(o, r.effect);
      EXPECT_GE(s.ratio, r.lo) << sim::ToString(r.effect) << " seed " << seed;
      EXPECT_LE(s.ratio, r.hi) << sim::ToString(r.effect) << " seed " << seed;
      const double step_s = r.effect == sim::Term::kBiasStep ? o.errors.bias_steps[0].time_s : 0;
      if (r.effect == sim::Term::kBiasStep && step_s >= 2 * s.tau_s &&
          o.duration_s - step_s >= 2 * s.tau_s) {
        // Overlapping Allan variance of a step D at least 2m samples from either end, n rate
        // samples, averaging factor m: only the 2m - 1 differences that straddle it are non-zero,
        // a triangle of peak D, so sigma^2 = D^2 (2 m^2 + 1) / (6 m (n - 2 m + 1)).
        const double n = static_cast<double>(o.NumSamples());
        const double m = std::round(s.tau_s * o.sample_rate_hz);
        const double d = o.errors.bias_steps[0].size_rad_s;
        const double closed = std::abs(d) * std::sqrt((2 * m * m + 1) / (6 * m * (n - 2 * m + 1)));
        EXPECT_NEAR(s.effect_adev_rad_s / closed, 1.0, 1e-6) << "seed " << seed;
        ++closed_form_checks;
      }
    }
  }
  EXPECT_GE(closed_form_checks, 1);
}

TEST(Compare, TheDefaultModelIsConsistentWithoutHiddenEffects) {
  // Control over 20 seeds: something is suggested in at most 10 % of them (2), temperature in at
  // most 5 % (1). Suggestions only exist when the model is inconsistent.
  // The verdict is "consistent" on at least 18 of them (alpha = 5 %: 1 expected). narrow_band,
  // tried whenever the frequency view fails, is suggested in at most 10 % (2).
  int suggested = 0, temperature = 0, consistent = 0, band = 0;
  for (int seed = 201; seed <= 220; ++seed) {
    const auto c = MakeHiddenCase(seed, {});
    const CompareResult r = Compare(c.input, DefaultTerms(), {});
    suggested += r.suggestions.empty() ? 0 : 1;
    temperature += BlamesTemperature(r);
    band += Blames(r, Term::kNarrowBand);
    consistent += r.verdict.status == "consistent";
  }
  EXPECT_LE(suggested, 2);
  EXPECT_LE(band, 2);
  EXPECT_LE(temperature, 1);
  EXPECT_GE(consistent, 18);
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
      blamed += BlamesTemperature(r);
      ++total;
    }
  }
  for (int seed = 411; seed <= 418; ++seed) {
    const auto c = MakeHiddenCase(seed, {});
    const CompareResult r = Compare(c.input, DefaultTerms(), {});
    blamed += BlamesTemperature(r);
    ++total;
  }
  EXPECT_EQ(total, 20);
  EXPECT_LE(blamed, 1);
}

TEST(Compare, TwoHiddenEffectsAreFoundOneAfterTheOther) {
  for (int seed : {301, 302}) {
    const auto c = MakeHiddenCase(seed, {sim::Term::kTemperature, sim::Term::kSinusoid});
    const CompareOptions o;
    std::vector<ModelTerm> terms = DefaultTerms();
    const CompareResult first = Compare(c.input, terms, o);
    ASSERT_FALSE(first.suggestions.empty()) << "seed " << seed;
    const ModelTerm a = first.suggestions[0].term;
    EXPECT_TRUE(a == Term::kTemperature || a == Term::kSinusoid) << ToString(a);
    terms.push_back(a);
    const CompareResult second = Compare(c.input, terms, o);
    EXPECT_LT(second.base.views.error, first.base.views.error);
    ASSERT_FALSE(second.suggestions.empty()) << "seed " << seed;
    const ModelTerm b = second.suggestions[0].term;
    EXPECT_EQ(b, a == Term::kTemperature ? Term::kSinusoid : Term::kTemperature) << ToString(b);
    terms.push_back(b);
    const Evaluation last = EvaluateModel(c.input, terms, o);
    EXPECT_TRUE(last.views.consistent) << "error " << last.views.error;
  }
}

// Synthetic evaluations for the ranking and the verdict: per-view errors set by hand, the rest
// of each evaluation just enough for delta_bic.
Evaluation Synthetic(std::vector<ViewError> errors, double rss, int parameters) {
  Evaluation e;
  e.views.view_errors = std::move(errors);
  for (const auto& v : e.views.view_errors) {
    e.views.error = std::max(e.views.error, v.error);
    if (v.error > 1)
      e.views.failures.push_back({v.domain, v.domain == ViewDomain::kFrequency ? 2.0 : 10.0,
                                  v.domain == ViewDomain::kFrequency ? 3.0 : 20.0, "", v.error});
  }
  e.views.consistent = e.views.error <= 1;
  e.deterministic.residual = Eigen::VectorXd::Zero(10000);
  e.deterministic.rss = rss;
  e.deterministic.summary.num_parameters = parameters;
  e.allan.tau_s.assign(12, 1.0);
  return e;
}

TEST(RankSuggestions, ATermThatBicRejectsIsNeverFirstAndIsMarked) {
  // The time view fails (error 9). bias_step would fix it best (error 0.5) but its scan statistic
  // is below its look-elsewhere critical value (delta_bic = 3^2 - 2^2 = +5); warmup fixes it too
  // with delta_bic = 3^2 - 5^2 = -16.
  Evaluation base = Synthetic(
      {{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 0.5}, {ViewDomain::kTime, 9}}, 1.0, 1);
  base.views.time.step_critical = 3;
  base.views.time.step_z = 2;
  base.views.time.warmup_critical = 3;
  base.views.time.warmup_z = 5;
  const std::vector<ModelTerm> tt = {Term::kBiasStep, Term::kWarmup};
  const std::vector<Evaluation> trials = {
      Synthetic({{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 0.5}, {ViewDomain::kTime, 0.5}},
                0.9, 3),
      Synthetic({{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 0.5}, {ViewDomain::kTime, 0.8}},
                0.9, 3)};
  const auto s = RankSuggestions(base, tt, trials, {});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].term, Term::kWarmup);
  EXPECT_FALSE(s[0].bic_rejects);
  EXPECT_EQ(s[1].term, Term::kBiasStep);
  EXPECT_TRUE(s[1].bic_rejects);
  EXPECT_NEAR(s[1].delta_bic, 5.0, 1e-12);
  const Verdict v = MakeVerdict(base, tt, trials, s);
  EXPECT_EQ(v.status, "inconsistent");
  ASSERT_TRUE(v.suggestion.has_value());
  EXPECT_EQ(*v.suggestion, Term::kWarmup);
  EXPECT_TRUE(v.consistent_with_suggestion);
  EXPECT_EQ(v.text, "inconsistent: suggestion warmup (makes the model consistent)");
}

// A line (the frequency view fails) that both sinusoid and aux_am:v fix. aux_am's delta_bic is the
// Wald form, -W + 5 ln(n) = -(10^2 + m^2) + 46.1 with the carrier at 10 SE and the modulation at
// m SE; the sinusoid's the RSS form, 10000 ln(0.9) + 3 ln(10000) = -1026. The modulation test's
// critical value at the aux view's critical 3.0 is -2 ln(erfc(3 / sqrt 2)) = 11.8.
TEST(RankSuggestions, ASupportedAmLineGoesAheadOfTheSinusoidAtItsFrequencyOnly) {
  const Evaluation base = Synthetic(
      {{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 5}, {ViewDomain::kTime, 0.5}}, 1.0, 1);
  const ModelTerm am = ModelTerm::Aux(AuxForm::kAm, "v");
  const std::vector<ModelTerm> tt = {Term::kSinusoid, am};
  const auto trials = [&](double modulation_z, double am_frequency_hz) {
    std::vector<Evaluation> t = {
        Synthetic(
            {{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 0.8}, {ViewDomain::kTime, 0.5}}, 0.9,
            4),
        Synthetic(
            {{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 0.7}, {ViewDomain::kTime, 0.5}},
            0.899, 6)};
    DeterministicComponent sinusoid;
    sinusoid.term = Term::kSinusoid;
    sinusoid.nonlinear = 1.0;
    sinusoid.nonlinear_se = 1e-3;
    sinusoid.coefficients = {1e-5, 0.0};
    sinusoid.coefficients_se = {1e-6, 1e-6};
    t[0].deterministic.model.components.push_back(sinusoid);
    DeterministicComponent line;
    line.term = am;
    line.nonlinear = am_frequency_hz;
    line.nonlinear_se = 1e-3;
    line.coefficients = {1e-5, 0.0, modulation_z * 1e-6, 0.0};
    line.coefficients_se = {1e-6, 1e-6, 1e-6, 1e-6};
    line.reference = 20.0;
    line.units = "V";
    line.coefficients_covariance.assign(16, 0.0);
    for (int i = 0; i < 4; ++i) line.coefficients_covariance[5 * i] = 1e-12;
    t[1].deterministic.model.components.push_back(line);
    t[1].views.aux.critical = 3.0;
    return t;
  };
  // Supported (modulation at 5 SE: chi-square 25 > 11.8): ahead of the sinusoid, whose lower
  // delta_bic it takes.
  const auto supported = RankSuggestions(base, tt, trials(5.0, 1.0), {});
  ASSERT_EQ(supported.size(), 2u);
  EXPECT_EQ(supported[0].term, am);
  EXPECT_NEAR(supported[0].delta_bic, -125.0 + 5.0 * std::log(10000.0), 1e-9);
  EXPECT_EQ(supported[1].term, Term::kSinusoid);
  // Not supported (modulation at 3 SE: 9 < 11.8): not a candidate at all.
  const auto weak = RankSuggestions(base, tt, trials(3.0, 1.0), {});
  ASSERT_EQ(weak.size(), 1u);
  EXPECT_EQ(weak[0].term, Term::kSinusoid);
  // A sinusoid elsewhere (1.1 Hz, 70 SE away) is not its nested model: the delta_bic decide.
  const auto elsewhere = RankSuggestions(base, tt, trials(5.0, 1.1), {});
  ASSERT_EQ(elsewhere.size(), 2u);
  EXPECT_EQ(elsewhere[0].term, Term::kSinusoid);
}

TEST(RankSuggestions, WhenTheLongTauCheckFlagsATermThatClearsItAndThatBicAcceptsIsSuggested) {
  // Every view passes, but the base model's long-tau check flags. aux_hysteresis:temperature
  // clears the flag with RSS 1 -> 0.9 (delta_bic = 10^4 ln 0.9 + ln 10^4 < 0); aux:supply_voltage
  // clears it too but BIC rejects it (RSS 1 -> 0.99999: 10^4 ln 0.99999 + ln 10^4 = +9.1);
  // temperature's trial is still flagged, and warmup's check ran but could not be evaluated (a
  // singular covariance, say), which says nothing. No aux view supports any
  // of them (the synthetic base has no aux channel): clearing the flag is their evidence.
  Evaluation base = Synthetic(
      {{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 0.5}, {ViewDomain::kTime, 0.5}}, 1.0, 1);
  base.long_tau.run = base.long_tau.evaluated = base.long_tau.flagged = true;
  const ModelTerm hysteresis = ModelTerm::Aux(AuxForm::kHysteresis, "temperature");
  const std::vector<ModelTerm> tt = {Term::kTemperature, Term::kWarmup, hysteresis,
                                     ModelTerm::Aux(AuxForm::kValue, "supply_voltage")};
  std::vector<Evaluation> trials;
  for (double rss : {0.9, 0.9, 0.9, 0.99999}) {
    trials.push_back(Synthetic(
        {{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 0.5}, {ViewDomain::kTime, 0.5}}, rss,
        2));
    trials.back().long_tau.run = trials.back().long_tau.evaluated = true;
  }
  trials[0].long_tau.flagged = true;
  trials[1].long_tau.evaluated = false;  // and not nothing_to_absorb
  const auto s = RankSuggestions(base, tt, trials, {});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].term, hysteresis);
  EXPECT_TRUE(s[0].clears_long_tau);
  EXPECT_FALSE(s[0].bic_rejects);
  EXPECT_LT(s[0].delta_bic, 0.0);
  EXPECT_EQ(MakeVerdict(base, tt, trials, s).status, "consistent");
  // Without the flag a consistent model gets no suggestion.
  base.long_tau.flagged = false;
  EXPECT_TRUE(RankSuggestions(base, tt, trials, {}).empty());
}

// The groups when the base model is inconsistent and its long-tau check flags: a term that makes
// a failing view pass first, then one that only clears the flag, then one that only lowers the
// error; the unexplained verdict quotes the one that lowers the error, not the flag's.
TEST(RankSuggestions, AFlaggedInconsistentModelRanksFixesThenFlagClearingThenErrorLowering) {
  Evaluation base = Synthetic(
      {{ViewDomain::kTau, 4}, {ViewDomain::kFrequency, 2}, {ViewDomain::kTime, 0.5}}, 1.0, 1);
  base.long_tau.run = base.long_tau.evaluated = base.long_tau.flagged = true;
  const std::vector<ModelTerm> tt = {Term::kWarmup, Term::kBiasStep, Term::kSinusoid};
  // delta_bic = 10^4 ln(rss) + (parameters - 1) ln 10^4 < 0 for each.
  std::vector<Evaluation> trials = {
      Synthetic({{ViewDomain::kTau, 3}, {ViewDomain::kFrequency, 2}, {ViewDomain::kTime, 0.5}},
                0.95, 3),
      Synthetic({{ViewDomain::kTau, 4}, {ViewDomain::kFrequency, 2}, {ViewDomain::kTime, 0.5}}, 0.9,
                3),
      Synthetic({{ViewDomain::kTau, 4}, {ViewDomain::kFrequency, 0.5}, {ViewDomain::kTime, 0.5}},
                0.9, 4)};
  for (Evaluation& trial : trials) trial.long_tau.run = trial.long_tau.evaluated = true;
  trials[0].long_tau.flagged = trials[2].long_tau.flagged = true;
  const auto s = RankSuggestions(base, tt, trials, {});
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].term, Term::kSinusoid);
  EXPECT_FALSE(s[0].clears_long_tau);
  EXPECT_EQ(s[1].term, Term::kBiasStep);
  EXPECT_TRUE(s[1].clears_long_tau);
  EXPECT_TRUE(s[1].fixes.empty());
  EXPECT_EQ(s[2].term, Term::kWarmup);
  EXPECT_FALSE(s[2].clears_long_tau);
  // Without the frequency fix the verdict is unexplained, and its text names warmup (3 < 4), not
  // bias_step, which ranks first but leaves the error at 4.
  const std::vector<Suggestion> without_fix(s.begin() + 1, s.end());
  const Verdict v = MakeVerdict(base, tt, trials, without_fix);
  EXPECT_EQ(v.status, "unexplained");
  EXPECT_NE(v.text.find("the first candidate, warmup"), std::string::npos) << v.text;
  EXPECT_EQ(v.text.find("the first candidate, bias_step"), std::string::npos) << v.text;
}

// Within a group, terms tied on the error (within 15 % + 0.05 of the best) that clear the
// long-tau flag come before those that do not, even against a better delta_bic.
TEST(RankSuggestions, AmongTermsTiedOnTheErrorTheOneThatClearsTheFlagComesFirst) {
  Evaluation base = Synthetic(
      {{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 2}, {ViewDomain::kTime, 0.5}}, 1.0, 1);
  base.long_tau.run = base.long_tau.evaluated = base.long_tau.flagged = true;
  const std::vector<ModelTerm> tt = {Term::kSinusoid, Term::kBiasStep};
  std::vector<Evaluation> trials = {
      Synthetic({{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 0.5}, {ViewDomain::kTime, 0.5}},
                0.8, 4),
      Synthetic(
          {{ViewDomain::kTau, 0.55}, {ViewDomain::kFrequency, 0.55}, {ViewDomain::kTime, 0.5}}, 0.9,
          3)};
  for (Evaluation& trial : trials) trial.long_tau.run = trial.long_tau.evaluated = true;
  trials[0].long_tau.flagged = true;
  const auto s = RankSuggestions(base, tt, trials, {});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_LT(s[1].delta_bic, s[0].delta_bic);  // the sinusoid is the better fit by BIC
  EXPECT_EQ(s[0].term, Term::kBiasStep);
  EXPECT_TRUE(s[0].clears_long_tau);
  EXPECT_EQ(s[1].term, Term::kSinusoid);
}

TEST(RankSuggestions, ATermIsCreditedForTheViewItFixesWhileAnotherDominates) {
  // The tau view dominates (error 4) and nothing fixes it; the sinusoid makes the failing
  // frequency view pass (2 -> 0.5) without changing the overall error: it is suggested, credited
  // with "frequency", and the verdict does not call the model consistent with it.
  const Evaluation base = Synthetic(
      {{ViewDomain::kTau, 4}, {ViewDomain::kFrequency, 2}, {ViewDomain::kTime, 0.5}}, 1.0, 1);
  const std::vector<ModelTerm> tt = {Term::kSinusoid, Term::kRateRandomWalk};
  const std::vector<Evaluation> trials = {
      Synthetic({{ViewDomain::kTau, 4}, {ViewDomain::kFrequency, 0.5}, {ViewDomain::kTime, 0.5}},
                0.9, 4),
      Synthetic({{ViewDomain::kTau, 3.9}, {ViewDomain::kFrequency, 2}, {ViewDomain::kTime, 0.5}},
                1.0, 1)};
  const auto s = RankSuggestions(base, tt, trials, {});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].term, Term::kSinusoid);
  EXPECT_EQ(s[0].fixes, std::vector<ViewDomain>{ViewDomain::kFrequency});
  EXPECT_NEAR(s[0].error_after, 4.0, 1e-12);
  const Verdict v = MakeVerdict(base, tt, trials, s);
  EXPECT_EQ(v.status, "inconsistent");
  EXPECT_FALSE(v.consistent_with_suggestion);
  ASSERT_EQ(v.still_failing.size(), 1u);
  EXPECT_EQ(v.still_failing[0].domain, ViewDomain::kTau);
  EXPECT_NE(v.text.find("still failing with it: tau"), std::string::npos) << v.text;
  // Nothing makes the tau view pass: it is listed as unexplained.
  ASSERT_EQ(v.unexplained.size(), 1u);
  EXPECT_EQ(v.unexplained[0].domain, ViewDomain::kTau);
}

TEST(RankSuggestions, NoTermThatFixesAFailingViewGivesUnexplained) {
  // The frequency view fails (error 6); the best trial lowers it to 2, which still fails.
  const Evaluation base = Synthetic(
      {{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 6}, {ViewDomain::kTime, 0.5}}, 1.0, 1);
  const std::vector<ModelTerm> tt = {Term::kSinusoid};
  const std::vector<Evaluation> trials = {Synthetic(
      {{ViewDomain::kTau, 0.5}, {ViewDomain::kFrequency, 2}, {ViewDomain::kTime, 0.5}}, 0.9, 4)};
  const auto s = RankSuggestions(base, tt, trials, {});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_TRUE(s[0].fixes.empty());
  const Verdict v = MakeVerdict(base, tt, trials, s);
  EXPECT_EQ(v.status, "unexplained");
  EXPECT_FALSE(v.suggestion.has_value());
  ASSERT_EQ(v.still_failing.size(), 1u);
  EXPECT_EQ(FormatFailure(v.still_failing[0]), "frequency 2-3 Hz");
  EXPECT_EQ(v.unexplained.size(), 1u);
  EXPECT_EQ(v.text.rfind("unexplained: no catalog term makes any failing view (frequency) pass", 0),
            0u)
      << v.text;
}

// Frequency failures are bands: a narrow vibration band (AddNarrowBand: damping ratio 2 %, half-
// power bandwidth ~100 Welch bins at 6 h, 10 Hz; peak 10x the white floor) fails on many bins,
// which chi-square scatter splits into runs; it must come back as one failure around its centre
// (ViewOptions::band_gap_bins, band_gap_fraction), with its peak and a positive excess power.
TEST(Compare, AVibrationBandIsOneFrequencyFailure) {
  int one_band = 0, total = 0;
  std::string report;
  for (int seed = 501; seed <= 510; ++seed) {
    auto c = MakeHiddenCase(seed, {});
    const double f0 = 0.5 + 0.25 * (seed - 501), zeta = 0.02;
    testing::AddNarrowBand(f0, zeta, 10.0, seed, &c);
    const Evaluation e = EvaluateModel(c.input, DefaultTerms(), {});
    ASSERT_TRUE(HasResult(e.termination)) << e.message;
    int near = 0;
    bool right = false;
    for (const auto& f : e.views.failures) {
      if (f.domain != ViewDomain::kFrequency || f.to < f0 * (1 - 4 * zeta) ||
          f.from > f0 * (1 + 4 * zeta))
        continue;
      ++near;
      right = f.from <= f0 && f0 <= f.to && std::abs(f.center_hz - f0) < 2 * zeta * f0 &&
              f.peak_ratio > 3 && f.excess_power > 0 && f.failing_bins > 1;
    }
    ++total;
    one_band += near == 1 && right;
    report += "seed " + std::to_string(seed) + ": " + std::to_string(near) + " band(s) near " +
              std::to_string(f0) + " Hz" + (right ? "" : " (not around the centre)") + "\n";
  }
  EXPECT_GE(one_band, total - 1) << report;
}

// The verdict's checks on the seeds of VerdictStudy (design 600-619, test 620-629; docs/compare.md
// has the rates). The two effects the out-of-catalog test first held are now catalog terms and must
// be explained: a narrow vibration band (AddNarrowBand, damping 2 %, peak 10x the white floor,
// 0.5-2.75 Hz) is narrow_band (its proof is Compare.AVibrationBandIsFoundNamedEstimatedAndFixed),
// and a bias that follows an aux channel (AddPressureBias, 8x the noise Allan deviation at 1000 s)
// is aux:pressure (a bias that follows a recorded channel cannot leave the aux view failing once
// aux:<channel> is trialled: the view scores the residual's linear dependence on the channel,
// which the term's least squares removes). The out-of-catalog case is now a vibration line that
// sweeps in frequency (AddChirp).
bool Unexplained(const Verdict& v, ViewDomain domain, const std::string& channel, double at) {
  for (const auto& f : v.unexplained) {
    if (f.domain != domain) continue;
    if (domain == ViewDomain::kAux ? f.channel == channel : (f.from <= at && at <= f.to))
      return true;
  }
  return false;
}

// The verdict adds aux:pressure and says it makes the model consistent.
bool AddsAuxPressure(const Verdict& v) {
  return v.status == "inconsistent" && v.suggestion &&
         *v.suggestion == ModelTerm::Aux(AuxForm::kValue, "pressure") &&
         v.consistent_with_suggestion;
}

double BandCentre(int seed) { return 0.5 + 0.25 * (seed % 10); }

// The chirp's peak Allan signature (AddChirp) in the out-of-catalog test and its study.
constexpr double kChirpSignature = 3.0;

// One frequency failure listed unexplained spans the middle 80 % of the chirp's sweep.
bool ChirpUnexplained(const Verdict& v, const testing::Chirp& ch) {
  const double margin = 0.1 * (ch.f2_hz - ch.f1_hz);
  for (const auto& f : v.unexplained)
    if (f.domain == ViewDomain::kFrequency && f.from <= ch.f1_hz + margin &&
        f.to >= ch.f2_hz - margin)
      return true;
  return false;
}

TEST(Compare, AVibrationBandOnTheVerdictSeedsIsExplainedByNarrowBand) {
  int band = 0;
  std::string report;
  for (int seed = 620; seed <= 629; ++seed) {
    auto b = MakeHiddenCase(seed, {});
    testing::AddNarrowBand(BandCentre(seed), 0.02, 10.0, seed, &b);
    const CompareResult rb = Compare(b.input, DefaultTerms(), {});
    band += rb.verdict.status == "inconsistent" && rb.verdict.suggestion &&
            *rb.verdict.suggestion == Term::kNarrowBand &&
            !Unexplained(rb.verdict, ViewDomain::kFrequency, "", BandCentre(seed));
    report += "seed " + std::to_string(seed) + " band: " + rb.verdict.text + "\n";
  }
  EXPECT_GE(band, 9) << report;
}

TEST(Compare, ABiasFollowingAnAuxPressureGetsItsAuxTerm) {
  int pressure = 0;
  std::string report;
  for (int seed = 620; seed <= 629; ++seed) {
    auto a = MakeHiddenCase(seed, {});
    testing::AddPressureBias(8.0, seed, &a);
    const CompareResult ra = Compare(a.input, DefaultTerms(), {});
    pressure += AddsAuxPressure(ra.verdict);
    EXPECT_FALSE(Unexplained(ra.verdict, ViewDomain::kAux, "pressure", 0)) << ra.verdict.text;
    report += "seed " + std::to_string(seed) + " pressure: " + ra.verdict.text + "\n";
  }
  EXPECT_GE(pressure, 9) << report;
}

// An out-of-catalog effect gets the verdict "unexplained" with the range that fails: a vibration
// line sweeping 1 Hz in frequency over the record (AddChirp, f1 in [0.8, 1.6] Hz, peak Allan
// signature 3x the noise floor, near tau 0.1-0.4 s). Its spectrum is a plateau over the sweep;
// narrow_band's resonance fits the plateau's middle and a sinusoid one line, so neither makes the
// frequency view pass. Design seeds 600-619 (VerdictStudy, kind chirp): status unexplained on 19
// of 20 (the other: "inconsistent: suggestion narrow_band", fixing tau only and listing the sweep
// as still failing and unexplained), one unexplained frequency failure spanning the middle 80 %
// of the sweep on 20 of 20, no suggestion claiming consistency or the frequency view on any. Test
// seeds 620-629: at least 9 of 10 unexplained and the sweep unexplained, no claim on any.
TEST(Compare, AnOutOfCatalogEffectIsUnexplainedWithItsRange) {
  int unexplained = 0, sweep = 0;
  std::string report;
  for (int seed = 620; seed <= 629; ++seed) {
    auto c = MakeHiddenCase(seed, {});
    const testing::Chirp ch = testing::AddChirp(kChirpSignature, seed, &c);
    const CompareResult r = Compare(c.input, DefaultTerms(), {});
    const Verdict& v = r.verdict;
    unexplained += v.status == "unexplained";
    sweep += ChirpUnexplained(v, ch);
    EXPECT_NE(v.status, "consistent") << v.text;
    EXPECT_FALSE(v.consistent_with_suggestion) << v.text;
    EXPECT_EQ(std::count(v.fixes.begin(), v.fixes.end(), ViewDomain::kFrequency), 0) << v.text;
    report += "seed " + std::to_string(seed) + " sweep " + std::to_string(ch.f1_hz) + "-" +
              std::to_string(ch.f2_hz) + " Hz: " + v.text + "\n";
  }
  EXPECT_GE(unexplained, 9) << report;
  EXPECT_GE(sweep, 9) << report;
}

// narrow_band's hidden-effect proof: a vibration band (AddNarrowBand: damping ratio 2 %, peak 10x
// the white floor 2 N^2, centre 0.5-2.75 Hz by seed) in a navigation-grade record. Criteria: the
// default model is inconsistent; narrow_band is the first suggestion; with narrow_band added, its
// centre is within 1 % (a quarter of the half-power width), its damping ratio within 25 % and its
// rms within 10 % of the truth, each or within 3 of its standard errors; the model with it is
// consistent. Design seeds 700-719 (NarrowBandStudy below), test seeds 720-724.
struct BandProof {
  bool inconsistent_before = false, first_is_band = false, consistent_after = false;
  bool f0_ok = false, zeta_ok = false, rms_ok = false;
  double z_f0 = 0, z_zeta = 0, z_rms = 0;  // (estimate - truth) / SE
  std::string first = "none", text;
};

BandProof ScoreBandProof(int seed) {
  BandProof p;
  auto c = MakeHiddenCase(seed, {});
  const double f0 = BandCentre(seed), zeta = 0.02, peak_ratio = 10.0;
  testing::AddNarrowBand(f0, zeta, peak_ratio, seed, &c);
  const double n = c.recording.truth.options.errors.n_rad_sqrt_s;
  const double rms = std::sqrt(peak_ratio * 2.0 * n * n * units::kPi * zeta * f0);  // its power
  const CompareResult before = Compare(c.input, DefaultTerms(), {});
  p.inconsistent_before = !before.base.views.consistent;
  if (!before.suggestions.empty()) p.first = ToString(before.suggestions[0].term);
  p.first_is_band = p.first == "narrow_band";
  std::vector<ModelTerm> terms = DefaultTerms();
  terms.push_back(Term::kNarrowBand);
  const Evaluation after = EvaluateModel(c.input, terms, {});
  p.consistent_after = after.views.consistent;
  p.text = before.verdict.text + " | after: error " + std::to_string(after.views.error);
  if (after.stochastic.model.bands.empty()) return p;
  const NarrowBand& b = after.stochastic.model.bands.back();
  auto judge = [](double estimate, double se, double truth, double tolerance, double* z) {
    *z = se > 0 ? (estimate - truth) / se : std::numeric_limits<double>::infinity();
    return std::abs(estimate - truth) <= tolerance * truth || std::abs(*z) <= 3.0;
  };
  p.f0_ok = judge(b.f0_hz, b.f0_se_hz, f0, 0.01, &p.z_f0);
  p.zeta_ok = judge(b.zeta, b.zeta_se, zeta, 0.25, &p.z_zeta);
  p.rms_ok = judge(b.sigma_rad_s, b.sigma_se_rad_s, rms, 0.10, &p.z_rms);
  return p;
}

TEST(Compare, AVibrationBandIsFoundNamedEstimatedAndFixed) {
  int inconsistent = 0, first = 0, f0 = 0, zeta = 0, rms = 0, consistent = 0;
  std::string report;
  for (int seed = 720; seed <= 724; ++seed) {
    const BandProof p = ScoreBandProof(seed);
    inconsistent += p.inconsistent_before;
    first += p.first_is_band;
    f0 += p.f0_ok;
    zeta += p.zeta_ok;
    rms += p.rms_ok;
    consistent += p.consistent_after;
    report += "seed " + std::to_string(seed) + ": " + p.text + "\n";
  }
  // Every criterion on every test seed but "consistent after", which the effect-free model
  // itself misses with probability alpha = 5 % per record: at most one of the five may fail it.
  EXPECT_EQ(inconsistent, 5) << report;
  EXPECT_EQ(first, 5) << report;
  EXPECT_EQ(f0, 5) << report;
  EXPECT_EQ(zeta, 5) << report;
  EXPECT_EQ(rms, 5) << report;
  EXPECT_GE(consistent, 4) << report;
}

// The design study of the test above (not run by ctest):
//   FOGPIPE_BAND_SEEDS=700-719 model_compare_test --gtest_also_run_disabled_tests
//   --gtest_filter='*NarrowBandStudy*'
// One line per recording: each criterion and (estimate - truth) / SE of f0, zeta and rms.
TEST(NarrowBandStudy, DISABLED_PassCountsOverSeeds) {
  const char* seeds = std::getenv("FOGPIPE_BAND_SEEDS");
  ASSERT_TRUE(seeds);
  int seed0 = 0, seed1 = 0;
  ASSERT_EQ(std::sscanf(seeds, "%d-%d", &seed0, &seed1), 2);
  for (int seed = seed0; seed <= seed1; ++seed) {
    const BandProof p = ScoreBandProof(seed);
    std::printf(
        "BAND seed %d f0 %.2f | incons %d first %d (%s) f0 %d zeta %d rms %d consistent %d | "
        "z_f0 %.2f z_zeta %.2f z_rms %.2f | %s\n",
        seed, BandCentre(seed), p.inconsistent_before, p.first_is_band, p.first.c_str(), p.f0_ok,
        p.zeta_ok, p.rms_ok, p.consistent_after, p.z_f0, p.z_zeta, p.z_rms, p.text.c_str());
    std::fflush(stdout);
  }
}

// The rates behind the out-of-catalog and aux pressure tests above (not run by ctest):
//   FOGPIPE_VERDICT_SEEDS=600-619 model_compare_test --gtest_also_run_disabled_tests
//   --gtest_filter='*VerdictStudy*'
// One line per recording and case (control, pressure, band, chirp; FOGPIPE_VERDICT_KIND picks
// one, FOGPIPE_CHIRP_K sets the chirp's signature): the verdict.
TEST(VerdictStudy, DISABLED_VerdictsOverSeeds) {
  const char* seeds = std::getenv("FOGPIPE_VERDICT_SEEDS");
  ASSERT_TRUE(seeds);
  std::vector<const char*> kinds = {"control", "pressure", "band", "chirp"};
  if (const char* only = std::getenv("FOGPIPE_VERDICT_KIND")) kinds = {only};
  const char* k_env = std::getenv("FOGPIPE_CHIRP_K");
  const double chirp_k = k_env ? std::atof(k_env) : kChirpSignature;
  int seed0 = 0, seed1 = 0;
  ASSERT_EQ(std::sscanf(seeds, "%d-%d", &seed0, &seed1), 2);
  for (int seed = seed0; seed <= seed1; ++seed) {
    for (const char* kind : kinds) {
      auto c = MakeHiddenCase(seed, {});
      const double f0 = BandCentre(seed);
      if (std::string(kind) == "pressure") testing::AddPressureBias(8.0, seed, &c);
      if (std::string(kind) == "band") testing::AddNarrowBand(f0, 0.02, 10.0, seed, &c);
      if (std::string(kind) == "chirp") {
        const testing::Chirp ch = testing::AddChirp(chirp_k, seed, &c);
        const CompareResult r = Compare(c.input, DefaultTerms(), {});
        const double n = c.recording.truth.options.errors.n_rad_sqrt_s;
        const double plateau =
            ch.amplitude_rad_s * ch.amplitude_rad_s / (2.0 * (ch.f2_hz - ch.f1_hz)) / (2.0 * n * n);
        const bool fixes_frequency =
            std::count(r.verdict.fixes.begin(), r.verdict.fixes.end(), ViewDomain::kFrequency) > 0;
        std::printf(
            "VERDICT chirp k %.2f seed %d f %.2f-%.2f plateau %.2fx error %.3g status %s "
            "sweep_unexplained %d claims %d fixes_frequency %d | %s\n",
            chirp_k, seed, ch.f1_hz, ch.f2_hz, plateau, r.base.views.error,
            r.verdict.status.c_str(), ChirpUnexplained(r.verdict, ch),
            r.verdict.consistent_with_suggestion, fixes_frequency, r.verdict.text.c_str());
        std::fflush(stdout);
        continue;
      }
      const CompareResult r = Compare(c.input, DefaultTerms(), {});
      // pressure: aux:pressure makes the model consistent; band: narrow_band explains it.
      const bool expected = std::string(kind) == "pressure" ? AddsAuxPressure(r.verdict)
                            : std::string(kind) == "band"
                                ? r.verdict.suggestion &&
                                      *r.verdict.suggestion == Term::kNarrowBand &&
                                      !Unexplained(r.verdict, ViewDomain::kFrequency, "", f0)
                                : true;
      std::printf("VERDICT %s seed %d error %.3g status %s expected %d narrow_band %d | %s\n", kind,
                  seed, r.base.views.error, r.verdict.status.c_str(), expected,
                  Blames(r, Term::kNarrowBand), r.verdict.text.c_str());
      std::fflush(stdout);
    }
  }
}

// The seed study behind the sizes of hidden_effects.h (not run by ctest; one process, ~1.3 s of
// CPU per recording):
//   FOGPIPE_STUDY_EFFECT=bias_step FOGPIPE_STUDY_RATIOS=2,3,5 FOGPIPE_STUDY_SEEDS=1-20
//   model_compare_test --gtest_also_run_disabled_tests --gtest_filter='*Study*'
// Ratio 0 keeps the CI sizing; any other value rescales the effect so that its peak Allan
// signature (PeakAllanSignature) is that many times the noise model's Allan deviation.
// FOGPIPE_STUDY_SIGNATURE_ONLY=1 prints the signatures without running compare.
// One line per recording: effect, seed, ratio, tau of the peak, pass/fail of each criterion.
TEST(HiddenEffectStudy, DISABLED_PassRatesAgainstTheSignatureRatio) {
  const char* name = std::getenv("FOGPIPE_STUDY_EFFECT");
  const char* ratios = std::getenv("FOGPIPE_STUDY_RATIOS");
  const char* seeds = std::getenv("FOGPIPE_STUDY_SEEDS");
  ASSERT_TRUE(name && ratios && seeds);
  sim::Term effect = sim::Term::kWhite;
  for (sim::Term t : {sim::Term::kTemperature, sim::Term::kTemperatureRate, sim::Term::kSinusoid,
                      sim::Term::kGaussMarkov, sim::Term::kBiasStep, sim::Term::kWarmup})
    if (std::string(sim::ToString(t)) == name) effect = t;
  ASSERT_NE(effect, sim::Term::kWhite) << name;
  int seed0 = 0, seed1 = 0;
  ASSERT_EQ(std::sscanf(seeds, "%d-%d", &seed0, &seed1), 2);
  std::vector<double> rho;
  std::stringstream ss(ratios);
  for (std::string tok; std::getline(ss, tok, ',');) rho.push_back(std::stod(tok));
  for (double r : rho) {
    for (int seed = seed0; seed <= seed1; ++seed) {
      sim::GyroSimulatorOptions o = testing::HiddenEffectOptions(seed, {effect});
      testing::AllanSignature sig = testing::PeakAllanSignature(o, effect);
      if (r > 0) {
        testing::ScaleEffect(effect, r / sig.ratio, &o);
        sig = testing::PeakAllanSignature(o, effect);
      }
      if (std::getenv("FOGPIPE_STUDY_SIGNATURE_ONLY")) {
        std::printf("SIGNATURE %s seed %d ratio %.3f tau %.1f effect/0.664B %.3f\n", name, seed,
                    sig.ratio, sig.tau_s,
                    sig.effect_adev_rad_s / sim::BiasInstabilityFloor(o.errors.b_rad_s));
        continue;
      }
      const auto c = testing::MakeHiddenCase(o);
      const ProofScore s = ScoreProof(effect, c);
      std::printf(
          "STUDY %s seed %d target %.1f ratio %.3f tau %.1f floorB %.3f | incons %d first %d "
          "(%s) params %d [",
          name, seed, r, sig.ratio, sig.tau_s,
          sig.effect_adev_rad_s / sim::BiasInstabilityFloor(o.errors.b_rad_s),
          s.default_inconsistent, s.first_is_hidden, s.first.c_str(), s.ParametersNearTruth());
      for (const auto& [pn, x] : s.parameter_errors) std::printf(" %s=%.2f", pn.c_str(), x);
      std::printf(" ] fail %d falls3x %d (%.2f->%.2f) consistent %d\n", s.failures_point_at_it,
                  s.error_falls_3x, s.error_before, s.error_after, s.consistent_after);
      std::fflush(stdout);
    }
  }
}

// Aux terms (catalog.h): a bias that follows an aux channel. Two hidden effects, each sized by its
// peak Allan signature k (hidden_effects.h; k drawn in [3, 5] per seed from its own stream, the
// temperature effect's range): a bias linear in a supply voltage that wanders slowly and carries a
// ripple (AddSupplyVoltageBias; an innocent magnetic_field is recorded too), and a quadratic
// temperature dependence c1 x + c2 x^2 (AddQuadraticTemperatureBias). The proof: the default model
// is inconsistent, the verdict's suggestion is the aux term (for the quadratic: aux:temperature
// with order 2 chosen by BIC), its coefficients are within 10 % of the truth or 3 of their
// standard errors, and the model with it is consistent. CI seeds 711-713 and 721-723; the design
// seeds were 1-20 (CompareAuxStudy below; docs/compare.md has the pass counts).
enum class AuxEffect { kSupplyVoltage, kQuadraticTemperature, kControl, kControlQuantizer };

const char* AuxEffectName(AuxEffect effect) {
  switch (effect) {
    case AuxEffect::kSupplyVoltage:
      return "supply_voltage";
    case AuxEffect::kQuadraticTemperature:
      return "quadratic_temperature";
    case AuxEffect::kControl:
      return "control";
    case AuxEffect::kControlQuantizer:
      return "control_quantizer";
  }
  return "";
}

double AuxSignatureK(int seed) {
  std::mt19937_64 g(static_cast<std::uint64_t>(seed) * 0x9E3779B97F4A7C15ULL + 0xA0C5ULL);
  return 3.0 + 2.0 * static_cast<double>(g() >> 11) * 0x1.0p-53;
}

struct AuxScore {
  bool inconsistent = false;
  // The verdict names a term to add; angle_quantizer on a record made with the undithered
  // quantizer is that record's own explanation (angle_quantizer_test.cpp), not counted here.
  bool suggested = false;
  bool first_right = false;  // ... and it is the hidden aux term
  std::string first = "none";
  std::string failures;  // the default model's failures, e.g. "time 0-338 s, aux magnetic_field"
  bool order_right = false;
  std::vector<std::pair<std::string, double>> parameter_errors;  // error / max(10 %, 3 SE)
  bool consistent_after = false;
  double error_before = 0, error_after = 0;
  bool ParametersNearTruth() const {
    if (parameter_errors.empty()) return false;
    for (const auto& [name, x] : parameter_errors)
      if (!(x <= 1.0)) return false;
    return true;
  }
};

// |estimate - truth| over the larger of 10 % of the truth and 3 standard errors.
std::pair<std::string, double> CoefficientError(const std::vector<Parameter>& ps,
                                                const std::string& name, double truth_deg_h) {
  const Parameter* q = Param(ps, name);
  if (q == nullptr) return {name, std::numeric_limits<double>::max()};
  return {name, std::abs(q->value - truth_deg_h) /
                    std::max(0.1 * std::abs(truth_deg_h), 3.0 * q->standard_error)};
}

// The base model's error, whether it is inconsistent, and its failures as text.
void ReadBase(const CompareResult& r, double* error, bool* inconsistent, std::string* failures) {
  *error = r.base.views.error;
  *inconsistent = !r.base.views.consistent;
  for (const Failure& f : r.base.views.failures)
    *failures += (failures->empty() ? "" : ", ") + FormatFailure(f);
}

// `k` > 0 rescales the effect to that signature; 0 keeps the CI sizing (AuxSignatureK).
AuxScore ScoreAux(AuxEffect effect, int seed, double k) {
  AuxScore s;
  sim::GyroSimulatorOptions o = testing::HiddenEffectOptions(seed, {});
  if (effect == AuxEffect::kControlQuantizer)
    o.errors.quantization_model = sim::QuantizationModel::kAngleQuantizer;
  auto c = testing::MakeHiddenCase(o);
  if (k <= 0) k = AuxSignatureK(seed);
  ModelTerm hidden;
  std::vector<std::pair<std::string, double>> truth;  // coefficient name, deg/h per unit^k
  int order = 1;
  switch (effect) {
    case AuxEffect::kSupplyVoltage:
      hidden = ModelTerm::Aux(AuxForm::kValue, "supply_voltage");
      truth = {{"coefficient", DegH(testing::AddSupplyVoltageBias(k, seed, &c))}};
      break;
    case AuxEffect::kQuadraticTemperature: {
      hidden = ModelTerm::Aux(AuxForm::kValue, "temperature");
      const auto [c1, c2] = testing::AddQuadraticTemperatureBias(k, seed, &c);
      truth = {{"coefficient", DegH(c1)}, {"coefficient_2", DegH(c2)}};
      order = 2;
      break;
    }
    default:
      testing::AddInnocentAux(seed, &c);
      break;
  }
  const CompareOptions options;
  const CompareResult before = Compare(c.input, DefaultTerms(), options);
  if (!HasResult(before.summary.termination)) return s;
  ReadBase(before, &s.error_before, &s.inconsistent, &s.failures);
  s.suggested =
      before.verdict.suggestion.has_value() && *before.verdict.suggestion != Term::kAngleQuantizer;
  if (s.suggested) s.first = ToString(*before.verdict.suggestion);
  if (truth.empty()) return s;
  s.first_right = s.suggested && *before.verdict.suggestion == hidden;
  std::vector<ModelTerm> terms = DefaultTerms();
  terms.push_back(hidden);
  const Evaluation after = EvaluateModel(c.input, terms, options);
  const std::vector<Parameter> ps = ParametersOf(after, hidden);
  const Parameter* fitted_order = Param(ps, "order");
  s.order_right = fitted_order && fitted_order->value == order;
  for (const auto& [name, value] : truth)
    s.parameter_errors.push_back(CoefficientError(ps, name, value));
  s.error_after = after.views.error;
  s.consistent_after = after.views.consistent;
  return s;
}

// Every criterion of the aux proof on seeds seed0..seed1.
void ExpectAuxProof(AuxEffect effect, int seed0, int seed1) {
  for (int seed = seed0; seed <= seed1; ++seed) {
    SCOPED_TRACE(seed);
    const AuxScore s = ScoreAux(effect, seed, 0);
    EXPECT_TRUE(s.inconsistent) << "error " << s.error_before;
    EXPECT_TRUE(s.first_right) << "suggestion: " << s.first;
    EXPECT_TRUE(s.order_right);
    for (const auto& [name, x] : s.parameter_errors)
      EXPECT_LE(x, 1.0) << name << ": error " << x << " x its tolerance";
    EXPECT_TRUE(s.consistent_after) << "error after " << s.error_after;
  }
}

TEST(CompareAuxTerm, ABiasFollowingASupplyVoltageIsFoundNamedEstimatedAndFixed) {
  ExpectAuxProof(AuxEffect::kSupplyVoltage, 711, 713);
}

TEST(CompareAuxTerm, AQuadraticTemperatureDependenceGetsOrderTwoByBic) {
  ExpectAuxProof(AuxEffect::kQuadraticTemperature, 721, 723);
}

// The loop on one recording: compare, add the suggestion, compare again: consistent.
TEST(CompareAuxTerm, TheLoopAddsTheAuxTermAndEndsConsistent) {
  auto c = MakeHiddenCase(714, {});
  testing::AddSupplyVoltageBias(AuxSignatureK(714), 714, &c);
  std::vector<ModelTerm> terms = DefaultTerms();
  const CompareResult first = Compare(c.input, terms, {});
  ASSERT_EQ(first.verdict.status, "inconsistent") << first.verdict.text;
  ASSERT_TRUE(first.verdict.suggestion.has_value());
  EXPECT_EQ(ToString(*first.verdict.suggestion), "aux:supply_voltage");
  terms.push_back(*first.verdict.suggestion);
  const CompareResult second = Compare(c.input, terms, {});
  EXPECT_EQ(second.verdict.status, "consistent") << second.verdict.text;
  ASSERT_GE(second.base.fitted.size(), 2u);
  EXPECT_EQ(second.base.fitted.back().term, "aux:supply_voltage");
}

// Controls: effect-free records with three innocent aux channels (temperature, supply_voltage,
// magnetic_field). The verdict suggests something in at most 10 % of the seeds (1 of 10). CI
// seeds 801-810 with the default (dithered: white angle noise) quantization and 821-830 with an
// undithered angle quantizer; design seeds 850-889 (CompareAuxStudy; docs/compare.md has the
// rates).
// How many of the control seeds seed0..seed1 get a suggestion; *report names them.
int SuggestedOverSeeds(AuxEffect control, int seed0, int seed1, std::string* report) {
  int suggested = 0;
  for (int seed = seed0; seed <= seed1; ++seed) {
    const AuxScore s = ScoreAux(control, seed, 0);
    suggested += s.suggested;
    if (s.suggested) *report += "seed " + std::to_string(seed) + ": " + s.first + "\n";
  }
  return suggested;
}

TEST(CompareAuxTerm, InnocentAuxChannelsAreRarelySuggested) {
  std::string report;
  EXPECT_LE(SuggestedOverSeeds(AuxEffect::kControl, 801, 810, &report), 1) << report;
}

TEST(CompareAuxTerm, InnocentAuxChannelsAreRarelySuggestedWithAnAngleQuantizer) {
  std::string report;
  EXPECT_LE(SuggestedOverSeeds(AuxEffect::kControlQuantizer, 821, 830, &report), 1) << report;
}

// The ratios of a study, "a,b,c" (FOGPIPE_STUDY_RATIOS), or {fallback} when not given.
std::vector<double> StudyRatios(const char* ratios, double fallback) {
  if (ratios == nullptr) return {fallback};
  std::vector<double> rho;
  std::stringstream ss(ratios);
  for (std::string tok; std::getline(ss, tok, ',');) rho.push_back(std::stod(tok));
  return rho;
}

// The seed study behind the aux tests (not run by ctest):
//   FOGPIPE_AUX_STUDY=supply_voltage FOGPIPE_STUDY_RATIOS=0,3 FOGPIPE_STUDY_SEEDS=1-20
//   model_compare_test --gtest_also_run_disabled_tests --gtest_filter='*CompareAuxStudy*'
// FOGPIPE_AUX_STUDY: supply_voltage, quadratic_temperature, control, control_quantizer. Ratio 0
// keeps the CI sizing. One line per recording: each criterion.
TEST(CompareAuxStudy, DISABLED_PassRates) {
  const char* name = std::getenv("FOGPIPE_AUX_STUDY");
  const char* ratios = std::getenv("FOGPIPE_STUDY_RATIOS");
  const char* seeds = std::getenv("FOGPIPE_STUDY_SEEDS");
  ASSERT_TRUE(name && seeds);
  std::optional<AuxEffect> effect;
  for (AuxEffect e : {AuxEffect::kSupplyVoltage, AuxEffect::kQuadraticTemperature,
                      AuxEffect::kControl, AuxEffect::kControlQuantizer})
    if (std::string(AuxEffectName(e)) == name) effect = e;
  ASSERT_TRUE(effect.has_value()) << name;
  int seed0 = 0, seed1 = 0;
  ASSERT_EQ(std::sscanf(seeds, "%d-%d", &seed0, &seed1), 2);
  const std::vector<double> rho = StudyRatios(ratios, 0.0);
  for (double r : rho) {
    for (int seed = seed0; seed <= seed1; ++seed) {
      const AuxScore s = ScoreAux(*effect, seed, r);
      std::printf(
          "AUX %s seed %d ratio %.2f | incons %d suggested %d first %d (%s) order %d "
          "params %d [",
          name, seed, r > 0 ? r : AuxSignatureK(seed), s.inconsistent, s.suggested, s.first_right,
          s.first.c_str(), s.order_right, s.ParametersNearTruth());
      for (const auto& [pn, x] : s.parameter_errors) std::printf(" %s=%.2f", pn.c_str(), x);
      std::printf(" ] consistent %d (%.2f->%.2f) failing: %s\n", s.consistent_after, s.error_before,
                  s.error_after, s.failures.c_str());
      std::fflush(stdout);
    }
  }
}

// Thermal hysteresis (AddThermalHysteresis: a bias +-a with the direction of the temperature,
// heating against cooling), on records with the three aux channels of the aux controls. The views
// pass on most such records (the square wave at the thermal period is absorbed by the fitted B
// and K); the long-tau check flags about half of them (long_tau_check_test.cpp). The proof per
// record: flagged before (inconsistent, or the long-tau check flags), aux_hysteresis:temperature
// the first suggestion, its coefficient within max(10 %, 3 SE) of a, and the model with it
// consistent and not flagged. Controls: effect-free records (the same aux channels), with the
// navigation-grade K and with K 30x it (long_tau_check_test.cpp's control, where the check is
// evaluated): how often aux_hysteresis is suggested at all.
enum class HysteresisCase { kHysteresis, kControl, kControlStrongWalk };

struct HysteresisScore {
  bool inconsistent = false, long_tau_flagged = false;
  bool first_right = false;
  std::string first = "none";
  bool hysteresis_suggested = false;  // any suggestion is an aux_hysteresis term
  bool first_clears = false;          // the first suggestion clears the long-tau flag
  double coefficient_error = std::numeric_limits<double>::max();  // / max(10 %, 3 SE)
  bool clean_after = false;  // consistent and not flagged with aux_hysteresis:temperature
  double error_before = 0, error_after = 0;
  bool Flagged() const { return inconsistent || long_tau_flagged; }
};

HysteresisScore ScoreHysteresis(HysteresisCase kind, int seed, double k) {
  HysteresisScore s;
  sim::GyroSimulatorOptions o = testing::HiddenEffectOptions(seed, {});
  if (kind == HysteresisCase::kControlStrongWalk) o.errors.k_rad_s_sqrt_s *= 30;
  auto c = testing::MakeHiddenCase(o);
  testing::AddInnocentAux(seed, &c);
  const double a = kind == HysteresisCase::kHysteresis ? testing::AddThermalHysteresis(k, &c) : 0;
  const CompareOptions options;
  const CompareResult before = Compare(c.input, DefaultTerms(), options);
  if (!HasResult(before.summary.termination)) return s;
  s.error_before = before.base.views.error;
  s.inconsistent = !before.base.views.consistent;
  s.long_tau_flagged = before.base.long_tau.flagged;
  const ModelTerm hysteresis = ModelTerm::Aux(AuxForm::kHysteresis, "temperature");
  if (!before.suggestions.empty()) s.first = ToString(before.suggestions.front().term);
  s.first_right = !before.suggestions.empty() && before.suggestions.front().term == hysteresis;
  s.first_clears = !before.suggestions.empty() && before.suggestions.front().clears_long_tau;
  for (const Suggestion& suggestion : before.suggestions)
    s.hysteresis_suggested |= suggestion.term.aux == AuxForm::kHysteresis;
  if (kind != HysteresisCase::kHysteresis) return s;
  std::vector<ModelTerm> terms = DefaultTerms();
  terms.push_back(hysteresis);
  const Evaluation after = EvaluateModel(c.input, terms, options);
  s.coefficient_error =
      CoefficientError(ParametersOf(after, hysteresis), "coefficient", DegH(a)).second;
  s.error_after = after.views.error;
  s.clean_after = after.views.consistent && !after.long_tau.flagged;
  return s;
}

// Design seeds 1-20 (HysteresisStudy; docs/compare.md), at 4x / 8x: flagged 14 / 19 (13 / 19 by
// the long-tau check), aux_hysteresis:temperature first 13 / 19 (every record the check flags,
// each time the trial clearing the flag), coefficient within max(10 %, 3 SE) 20 / 20, consistent
// and not flagged with the term 19 / 19 (seed 12 stays inconsistent). CI seeds 101-110 at both
// sizes, per size and criterion a one-sided binomial bound at a rate below the design's:
//   first at 8x, rate 0.8: at least 5 of 10 (P(X <= 4) = 0.6 % for Binomial(10, 0.8));
//   first at 4x, rate 0.5: at least 2 of 10 (P(X <= 1) = 1.1 %);
//   coefficient over the 20 records, rate 0.925 (1 - 3 / 40, the rule of three on 40 of 40):
//     at least 16 (P(X <= 15) = 1.4 % for Binomial(20, 0.925));
//   consistent and not flagged after, rate 0.9 (38 of 40): at least 15 (P(X <= 14) = 1.1 %).
TEST(CompareHysteresis, AThermalHysteresisIsFoundThroughTheLongTauFlagAndEstimated) {
  int coefficient_right = 0, clean_after = 0;
  for (double k : {8.0, 4.0}) {
    int first_right = 0;
    for (int seed = 101; seed <= 110; ++seed) {
      const HysteresisScore s = ScoreHysteresis(HysteresisCase::kHysteresis, seed, k);
      first_right += s.first_right;
      EXPECT_TRUE(!s.first_right || s.first_clears) << "seed " << seed << " k " << k;
      coefficient_right += s.coefficient_error <= 1.0;
      clean_after += s.clean_after;
    }
    EXPECT_GE(first_right, k == 8.0 ? 5 : 2) << "k " << k;
  }
  EXPECT_GE(coefficient_right, 16);
  EXPECT_GE(clean_after, 15);
}

// Controls: no aux_hysteresis suggestion on any of the design seeds 850-889 (three innocent aux
// channels) and 1-40 (K 30x), 80 records, so a rate of at most 3 / 80 < 0.04 (rule of three). CI
// seeds 801-810 and 101-110: at most 3 of 20 (P(X >= 4) = 0.7 % for Binomial(20, 0.04)).
TEST(CompareHysteresis, EffectFreeRecordsRarelyGetAHysteresisTerm) {
  int suggested = 0;
  std::string report;
  for (HysteresisCase kind : {HysteresisCase::kControl, HysteresisCase::kControlStrongWalk}) {
    const int seed0 = kind == HysteresisCase::kControl ? 801 : 101;
    for (int seed = seed0; seed < seed0 + 10; ++seed) {
      const HysteresisScore s = ScoreHysteresis(kind, seed, 0);
      suggested += s.hysteresis_suggested;
      if (s.hysteresis_suggested) report += "seed " + std::to_string(seed) + "\n";
    }
  }
  EXPECT_LE(suggested, 3) << report;
}

// The seed study behind the hysteresis tests (not run by ctest):
//   FOGPIPE_HYSTERESIS_CASE=hysteresis FOGPIPE_STUDY_RATIOS=4,8 FOGPIPE_STUDY_SEEDS=1-20
//   model_compare_test --gtest_also_run_disabled_tests --gtest_filter='*HysteresisStudy*'
// FOGPIPE_HYSTERESIS_CASE: hysteresis, control, control_strong_walk.
// A study's case (from `case_variable`), FOGPIPE_STUDY_SEEDS ("a-b") and FOGPIPE_STUDY_RATIOS
// (StudyRatios, `fallback` when not given); false when the case or the seeds are missing.
struct StudySettings {
  std::string kind;
  int seed0 = 0, seed1 = 0;
  std::vector<double> ratios;
};
bool ReadStudySettings(const char* case_variable, double fallback, StudySettings* settings) {
  const char* name = std::getenv(case_variable);
  const char* seeds = std::getenv("FOGPIPE_STUDY_SEEDS");
  if (!name || !seeds || std::sscanf(seeds, "%d-%d", &settings->seed0, &settings->seed1) != 2)
    return false;
  settings->kind = name;
  settings->ratios = StudyRatios(std::getenv("FOGPIPE_STUDY_RATIOS"), fallback);
  return true;
}

TEST(HysteresisStudy, DISABLED_PassRates) {
  StudySettings study;
  ASSERT_TRUE(ReadStudySettings("FOGPIPE_HYSTERESIS_CASE", 4.0, &study));
  const std::string& kind_name = study.kind;
  const char* name = kind_name.c_str();
  const HysteresisCase kind = kind_name == "control" ? HysteresisCase::kControl
                              : kind_name == "control_strong_walk"
                                  ? HysteresisCase::kControlStrongWalk
                                  : HysteresisCase::kHysteresis;
  const int seed0 = study.seed0, seed1 = study.seed1;
  const std::vector<double>& rho = study.ratios;
  for (double r : rho) {
    for (int seed = seed0; seed <= seed1; ++seed) {
      const HysteresisScore s = ScoreHysteresis(kind, seed, r);
      std::printf(
          "HYST %s seed %d k %.1f | flagged %d (incons %d long_tau %d) first %d (%s) "
          "hyst_suggested %d coef %.2f clean_after %d (%.2f->%.2f) first_clears %d\n",
          name, seed, r, s.Flagged(), s.inconsistent, s.long_tau_flagged, s.first_right,
          s.first.c_str(), s.hysteresis_suggested, s.coefficient_error, s.clean_after,
          s.error_before, s.error_after, s.first_clears);
      std::fflush(stdout);
    }
  }
}

// The AM line (aux_am:<name>): a line whose amplitude follows an aux channel, on records built in
// the test (independent_records.h: white noise, flicker, random walk and an angle quantizer written
// out there, not fogpipe's simulator), with the three aux channels temperature, supply_voltage and
// magnetic_field; the line's amplitude follows the temperature. The proof per record: the default
// model is inconsistent, the verdict's suggestion is aux_am:temperature, its parameters are within
// tolerance (frequency 3 SE; amplitude and modulation max(10 %, 3 SE); the modulation in
// quadrature, 0 in truth, within 3 SE), a base failure contains the line's frequency, and the model
// with the term is consistent. Controls: effect-free records of the same kind, dithered and
// undithered.
enum class AmCase { kAmLine, kControl, kControlUndithered };

// The AM line's signature (independent_records.h) in the tests.
constexpr double kAmSignature = 6.0;

struct AmScore {
  bool inconsistent = false, suggested = false, first_right = false, points_at_line = false;
  std::string first = "none", second = "none";
  bool am_suggested = false;                                     // any suggestion is an aux_am term
  std::vector<std::pair<std::string, double>> parameter_errors;  // error / tolerance, < 1 holds
  std::vector<std::pair<std::string, double>> z;                 // (estimate - truth) / SE
  bool consistent_after = false;
  double error_before = 0, error_after = 0;
  std::string failures, failures_after;
  bool ParametersNearTruth() const {
    if (parameter_errors.empty()) return false;
    for (const auto& [name, x] : parameter_errors)
      if (!(x <= 1.0)) return false;
    return true;
  }
};

// `base` is the model compared first (the default terms; with a sinusoid, the loop's state after
// a first `--add sinusoid`); the model "after" is it with aux_am:temperature.
AmScore ScoreAm(AmCase kind, int seed, double k,
                const std::vector<ModelTerm>& base = DefaultTerms()) {
  AmScore s;
  testing::IndependentRecordOptions ro;
  ro.quantizer = kind == AmCase::kControlUndithered ? testing::Quantizer::kUndithered
                                                    : testing::Quantizer::kDithered;
  ro.am_signature = kind == AmCase::kAmLine ? k : 0.0;
  const testing::IndependentRecord record = testing::MakeIndependentRecord(seed, ro);
  const CompareInput input = record.Input();
  const CompareOptions options;
  const CompareResult before = Compare(input, base, options);
  if (!HasResult(before.summary.termination)) return s;
  ReadBase(before, &s.error_before, &s.inconsistent, &s.failures);
  // angle_quantizer on an undithered control is its own explanation (see AuxScore).
  s.suggested =
      before.verdict.suggestion.has_value() && *before.verdict.suggestion != Term::kAngleQuantizer;
  if (!before.suggestions.empty()) s.first = ToString(before.suggestions.front().term);
  if (before.suggestions.size() > 1) s.second = ToString(before.suggestions[1].term);
  for (const Suggestion& suggestion : before.suggestions)
    s.am_suggested |= suggestion.term.aux == AuxForm::kAm && !suggestion.bic_rejects;
  if (!record.am) return s;
  const testing::AmLineTruth& am = *record.am;
  const ModelTerm hidden = ModelTerm::Aux(AuxForm::kAm, "temperature");
  s.first_right = s.suggested && *before.verdict.suggestion == hidden;
  for (const Failure& f : before.base.views.failures)
    s.points_at_line |= f.domain == ViewDomain::kFrequency && f.from <= am.frequency_hz * 1.001 &&
                        am.frequency_hz * 0.999 <= f.to;
  std::vector<ModelTerm> terms = base;
  terms.push_back(hidden);
  const Evaluation after = EvaluateModel(input, terms, options);
  const std::vector<Parameter> ps = ParametersOf(after, hidden);
  const std::vector<std::pair<std::string, double>> truth = {
      {"frequency", am.frequency_hz},
      {"amplitude", DegH(am.amplitude_rad_s)},
      {"modulation", DegH(am.modulation_rad_s_per_degc)},
      {"modulation_quadrature", 0.0}};
  for (const auto& [name, value] : truth) {
    const Parameter* q = Param(ps, name);
    if (q == nullptr) {
      s.parameter_errors.push_back({name, std::numeric_limits<double>::max()});
      continue;
    }
    const bool relative = name == "amplitude" || name == "modulation";
    s.parameter_errors.push_back(
        {name, std::abs(q->value - value) /
                   std::max(relative ? 0.1 * std::abs(value) : 0.0, 3.0 * q->standard_error)});
    s.z.push_back({name, (q->value - value) / q->standard_error});
  }
  s.error_after = after.views.error;
  s.consistent_after = after.views.consistent;
  for (const Failure& f : after.views.failures)
    s.failures_after += (s.failures_after.empty() ? "" : ", ") + FormatFailure(f);
  return s;
}

// Design seeds 1-60 at k = 6 (AmLineStudy; docs/compare.md): inconsistent 60 / 60, the failures
// containing the line's frequency 60 / 60, aux_am:temperature first 58 / 60 (seeds 25 and 52...
// see docs), parameters within tolerance 59 / 60, consistent with the term 58 / 60. CI seeds
// 101-112, per criterion a one-sided binomial bound at a rate below the design's:
//   inconsistent before and failures at the line, rate 0.95 (1 - 3 / 60, the rule of three on
//     60 of 60): at least 10 of 12 (P(X <= 9) = 2.0 % for Binomial(12, 0.95));
//   first suggestion, parameters, consistent after, rate 0.9: at least 9 of 12 (P(X <= 8) = 2.6 %).
// Calibration: z = (estimate - truth) / SE of frequency, amplitude, modulation and quadrature (48
// values, correlated within a record): for calibrated errors P(|z| > 3) = 0.27 % (a little more
// with the batch-means SE's 31 degrees of freedom); at most 2 of 48 may exceed 3 (P(X >= 3) =
// 1.2 % even at 1 % each), and the rms of z clipped at 4 is within [0.6, 1.45] (its sd is about
// sqrt(2 / n_eff) / 2 = 0.15 with n_eff ~ 24 independent values: 2.5-3 sd either side).
TEST(CompareAmLine, ALineWhoseAmplitudeFollowsTheTemperatureIsFoundNamedEstimatedAndFixed) {
  int inconsistent = 0, points = 0, first = 0, parameters = 0, consistent_after = 0, n = 0;
  int beyond_three = 0;
  double square = 0;
  std::string report;
  for (int seed = 101; seed <= 112; ++seed) {
    const AmScore s = ScoreAm(AmCase::kAmLine, seed, kAmSignature);
    inconsistent += s.inconsistent;
    points += s.points_at_line;
    first += s.first_right;
    parameters += s.ParametersNearTruth();
    consistent_after += s.consistent_after;
    for (const auto& [name, z] : s.z) {
      beyond_three += std::abs(z) > 3.0;
      square += std::min(z * z, 16.0);
      ++n;
    }
    report += "seed " + std::to_string(seed) + ": first " + s.first + ", error " +
              std::to_string(s.error_before) + " -> " + std::to_string(s.error_after) + "\n";
  }
  EXPECT_GE(inconsistent, 10) << report;
  EXPECT_GE(points, 10) << report;
  EXPECT_GE(first, 9) << report;
  EXPECT_GE(parameters, 9) << report;
  EXPECT_GE(consistent_after, 9) << report;
  ASSERT_EQ(n, 48);
  EXPECT_LE(beyond_three, 2);
  EXPECT_GT(std::sqrt(square / n), 0.6);
  EXPECT_LT(std::sqrt(square / n), 1.45);
}

// The loop after a first `--add sinusoid`: at k = 20 the sinusoid takes the carrier and leaves the
// sidebands failing the frequency view (at k = 6 the model with the sinusoid is consistent on 10
// of 10 design seeds: the sidebands are then below the view's reach, and only the modulation test
// sees them). Design seeds 1-30 from default + sinusoid: aux_am:temperature the verdict's
// suggestion on 29 of 30, consistent with it (beside the sinusoid) on 29 of 30. CI seeds 113-118:
// at least 4 of 6 each (P(X <= 3) = 1.6 % for Binomial(6, 0.9)).
TEST(CompareAmLine, AfterASinusoidTheLoopSuggestsTheAmLineNotASideband) {
  std::vector<ModelTerm> base = DefaultTerms();
  base.push_back(Term::kSinusoid);
  int first = 0, consistent_after = 0;
  std::string report;
  for (int seed = 113; seed <= 118; ++seed) {
    const AmScore s = ScoreAm(AmCase::kAmLine, seed, 20.0, base);
    first += s.first_right;
    consistent_after += s.consistent_after;
    report += "seed " + std::to_string(seed) + ": first " + s.first + ", then " + s.second + "\n";
  }
  EXPECT_GE(first, 4) << report;
  EXPECT_GE(consistent_after, 4) << report;
}

// Controls: effect-free records of the same kind with the three aux channels. Design seeds 1-40:
// something suggested on 1 of 40 dithered (seed 1: a sinusoid at a single failing bin) and 0 of
// 40 undithered (inconsistent on 22 of 40: the quantizer's tones, which aux_am is trialled on and
// never supported), aux_am on none of the 80: a rate of at most 3 / 80 (rule of three on 1 of
// 80, rounded up to 0.04). CI seeds 201-210 of each: at most 2 of 20 with a suggestion, and at
// most 2 with an aux_am one (P(X >= 3) = 4.4 % for Binomial(20, 0.04)); 2 of 20 is the 10 %
// the term's requirement allows.
TEST(CompareAmLine, EffectFreeRecordsWithThreeAuxChannelsRarelyGetASuggestion) {
  int suggested = 0, am = 0;
  std::string report;
  for (AmCase kind : {AmCase::kControl, AmCase::kControlUndithered}) {
    for (int seed = 201; seed <= 210; ++seed) {
      const AmScore s = ScoreAm(kind, seed, 0);
      suggested += s.suggested;
      am += s.am_suggested;
      if (s.suggested || s.am_suggested)
        report += "seed " + std::to_string(seed) + ": " + s.first + "\n";
    }
  }
  EXPECT_LE(suggested, 2) << report;
  EXPECT_LE(am, 2) << report;
}

// The seed study behind the AM tests (not run by ctest):
//   FOGPIPE_AM_CASE=am FOGPIPE_STUDY_RATIOS=4,6 FOGPIPE_STUDY_SEEDS=1-20
//   model_compare_test --gtest_also_run_disabled_tests --gtest_filter='*AmLineStudy*'
// FOGPIPE_AM_CASE: am, control, control_undithered; FOGPIPE_AM_BASE=sinusoid starts from the
// default model with a sinusoid.
TEST(AmLineStudy, DISABLED_PassRates) {
  StudySettings study;
  ASSERT_TRUE(ReadStudySettings("FOGPIPE_AM_CASE", kAmSignature, &study));
  const char* name = study.kind.c_str();
  const AmCase kind = study.kind == "control"              ? AmCase::kControl
                      : study.kind == "control_undithered" ? AmCase::kControlUndithered
                                                           : AmCase::kAmLine;
  std::vector<ModelTerm> base = DefaultTerms();
  if (const char* add = std::getenv("FOGPIPE_AM_BASE")) base.push_back(*ParseModelTerm(add));
  for (double r : study.ratios) {
    for (int seed = study.seed0; seed <= study.seed1; ++seed) {
      const AmScore s = ScoreAm(kind, seed, r, base);
      std::printf(
          "AM %s seed %d k %.2f | incons %d suggested %d first %d (%s, then %s) points %d "
          "am_suggested %d params %d [",
          name, seed, r, s.inconsistent, s.suggested, s.first_right, s.first.c_str(),
          s.second.c_str(), s.points_at_line, s.am_suggested, s.ParametersNearTruth());
      for (const auto& [pn, x] : s.parameter_errors) std::printf(" %s=%.2f", pn.c_str(), x);
      std::printf(" ] z [");
      for (const auto& [pn, x] : s.z) std::printf(" %s=%.2f", pn.c_str(), x);
      std::printf(" ] consistent %d (%.2f->%.2f) failing: %s; after: %s\n", s.consistent_after,
                  s.error_before, s.error_after, s.failures.c_str(), s.failures_after.c_str());
      std::fflush(stdout);
    }
  }
}

// The IEEE terms of compare's model under the five-term fit's reliability checks (noise_check).
TEST(Compare, MarksAnIeeeTermUnreliableWhereAHiddenEffectBendsTheAllanCurve) {
  // The default model has no term for a sinusoid's or a Gauss-Markov bump: a term that carries
  // the model there must be flagged, with its reason, and the read-offs shown beside it.
  for (sim::Term effect : {sim::Term::kSinusoid, sim::Term::kGaussMarkov}) {
    for (int seed = 101; seed <= 103; ++seed) {
      const auto c = MakeHiddenCase(seed, {effect});
      const Evaluation e = EvaluateModel(c.input, DefaultTerms(), {});
      ASSERT_TRUE(HasResult(e.termination)) << e.message;
      EXPECT_GE(allan::UnreliableTermCount(e.noise_check), 1) << "seed " << seed;
      EXPECT_FALSE(e.noise_check.misfit_ranges.empty()) << "seed " << seed;
      for (const allan::TermAssessment& a : e.noise_check.assessment)
        EXPECT_EQ(a.reliable, a.reason.empty()) << "seed " << seed;
      EXPECT_TRUE(std::isfinite(e.noise_check.slope_readoff.n_rad_sqrt_s)) << "seed " << seed;
      // The checked terms are compare's own, not a refit.
      EXPECT_EQ(e.noise_check.terms.n_rad_sqrt_s, e.stochastic.model.n_rad_sqrt_s);
    }
  }
}

TEST(Compare, FlagsNoIeeeTermOfRecordsThatFollowTheModel) {
  // Effect-free control seeds: at most 1 of 20 records (5 %) may have a term flagged. Without the
  // fit's shape tolerance in the point intervals, Q is flagged at the shortest tau on several.
  int flagged = 0;
  std::string reasons;
  for (int seed = 201; seed <= 220; ++seed) {
    const auto c = MakeHiddenCase(seed, {});
    const Evaluation e = EvaluateModel(c.input, DefaultTerms(), {});
    ASSERT_TRUE(HasResult(e.termination)) << e.message;
    if (allan::UnreliableTermCount(e.noise_check) == 0) continue;
    ++flagged;
    for (int j = 0; j < allan::kNoiseTermCount; ++j)
      if (!e.noise_check.assessment[j].reliable)
        reasons += "seed " + std::to_string(seed) + " " + allan::TermSymbol(j) + ": " +
                   e.noise_check.assessment[j].reason + "\n";
  }
  EXPECT_LE(flagged, 1) << reasons;
}

TEST(Compare, JudgesOnlyTheIeeeTermsInTheModel) {
  const auto c = MakeHiddenCase(201, {});
  const Evaluation e = EvaluateModel(c.input, {Term::kWhite}, {});
  ASSERT_TRUE(HasResult(e.termination)) << e.message;
  EXPECT_TRUE(std::isfinite(e.noise_check.terms.n_rad_sqrt_s));
  EXPECT_TRUE(std::isnan(e.noise_check.terms.b_rad_s));
  EXPECT_TRUE(std::isnan(e.noise_check.assessment[2].z));
}

}  // namespace
}  // namespace fogpipe::model
