#include "algorithms/model/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numeric>

#include "algorithms/common/units.h"

namespace fogpipe::model {
namespace {

const AuxChannel* FindAux(const CompareInput& in, const std::string& name) {
  for (const auto& ch : in.aux)
    if (ch.name == name && in.rate_rad_s && ch.values.size() == in.rate_rad_s->size()) return &ch;
  return nullptr;
}

double DegH(double rad_s) { return units::RadPerSecondToDegPerHour(rad_s); }

// Rate-fitted terms with a nonlinear parameter found by a search (frequency, step time, time
// constant).
bool HasNonlinearParameter(Term t) {
  return t == Term::kSinusoid || t == Term::kBiasStep || t == Term::kWarmup;
}

std::string Format(const char* fmt, double a, double b = 0, double c = 0, double d = 0,
                   double e = 0) {
  char buf[512];
  std::snprintf(buf, sizeof(buf), fmt, a, b, c, d, e);
  return buf;
}

const DeterministicComponent* LastComponent(const Evaluation& e, Term t) {
  const DeterministicComponent* found = nullptr;
  for (const auto& c : e.deterministic.model.components)
    if (c.term == t) found = &c;
  return found;
}

std::vector<Parameter> ParametersOfComponent(const DeterministicComponent& c) {
  std::vector<Parameter> p;
  switch (c.term) {
    case Term::kTemperature:
      p.push_back(
          {"coefficient", DegH(c.coefficients[0]), DegH(c.coefficients_se[0]), "deg/h/degC"});
      break;
    case Term::kTemperatureRate:
      p.push_back(
          {"coefficient", DegH(c.coefficients[0]), DegH(c.coefficients_se[0]), "deg/h/(degC/s)"});
      break;
    case Term::kSinusoid: {
      const double a = c.coefficients[0], b = c.coefficients[1];
      const double w = std::hypot(a, b);
      const double se = w > 0 ? std::hypot(a * c.coefficients_se[0], b * c.coefficients_se[1]) / w
                              : std::hypot(c.coefficients_se[0], c.coefficients_se[1]);
      p.push_back({"frequency", c.nonlinear, c.nonlinear_se, "Hz"});
      p.push_back({"amplitude", DegH(w), DegH(se), "deg/h"});
      // a cos + b sin = W sin(2 pi f t + phase): W sin(phase) = a, W cos(phase) = b.
      p.push_back({"phase", std::atan2(a, b), w > 0 ? se / w : units::kPi, "rad"});
      break;
    }
    case Term::kBiasStep:
      p.push_back({"time", c.nonlinear, c.nonlinear_se, "s"});
      p.push_back({"size", DegH(c.coefficients[0]), DegH(c.coefficients_se[0]), "deg/h"});
      break;
    case Term::kWarmup:
      p.push_back({"amplitude", DegH(c.coefficients[0]), DegH(c.coefficients_se[0]), "deg/h"});
      p.push_back({"time_constant", c.nonlinear, c.nonlinear_se, "s"});
      break;
    default:
      break;
  }
  return p;
}

std::vector<Parameter> StochasticParameters(const StochasticModel& m, Term t) {
  using namespace units;
  switch (t) {
    case Term::kWhite:
      return {{"N", ArwToDegPerSqrtHour(m.n_rad_sqrt_s), ArwToDegPerSqrtHour(m.n_se), kArwUnit}};
    case Term::kQuantization:
      return {
          {"Q", QuantizationToArcsec(m.q_rad), QuantizationToArcsec(m.q_se), kQuantizationUnit}};
    case Term::kBiasInstability:
      return {{"B", BiasToDegPerHour(m.b_rad_s), BiasToDegPerHour(m.b_se), kBiasUnit}};
    case Term::kRateRandomWalk:
      return {{"K", RrwToDegPerHourSqrtHour(m.k_rad_s_sqrt_s), RrwToDegPerHourSqrtHour(m.k_se),
               kRrwUnit}};
    case Term::kRateRamp:
      return {{"R", RampToDegPerHour2(m.r_rad_s2), RampToDegPerHour2(m.r_se), kRampUnit}};
    case Term::kGaussMarkov:
      return {{"sigma", DegH(m.gm_sigma_rad_s), DegH(m.gm_sigma_se), "deg/h"},
              {"correlation_time", m.gm_correlation_time_s, m.gm_correlation_time_se, "s"}};
    default:
      return {};
  }
}

// The IEEE terms of the stochastic model in allan::NoiseTerms (NaN: not in the model), checked by
// the five-term fit's rules; the Gauss-Markov term is the rest of the model. Each point's
// interval includes the model-shape tolerance the fit was made with (stochastic_fit.h): the fit
// claims its model to that tolerance only, and at the shortest taus (EDF ~1e5) the sampling
// interval alone is narrower than the closed forms' idealisation of a sampled process, so
// records that follow the model would have Q flagged there (compare_test.cpp tests both sides).
allan::NoiseFitResult CheckIeeeTerms(const StochasticModel& m, const allan::AllanTable& table,
                                     double relative_tolerance) {
  constexpr double kAbsent = std::numeric_limits<double>::quiet_NaN();
  allan::NoiseTerms t;
  auto set = [&](Term term, double value, double se, double* out, double* out_se) {
    *out = m.Has(term) ? value : kAbsent;
    *out_se = m.Has(term) ? se : kAbsent;
  };
  set(Term::kQuantization, m.q_rad, m.q_se, &t.q_rad, &t.q_se);
  set(Term::kWhite, m.n_rad_sqrt_s, m.n_se, &t.n_rad_sqrt_s, &t.n_se);
  set(Term::kBiasInstability, m.b_rad_s, m.b_se, &t.b_rad_s, &t.b_se);
  set(Term::kRateRandomWalk, m.k_rad_s_sqrt_s, m.k_se, &t.k_rad_s_sqrt_s, &t.k_se);
  set(Term::kRateRamp, m.r_rad_s2, m.r_se, &t.r_rad_s2, &t.r_se);
  std::function<double(double)> other;
  if (m.Has(Term::kGaussMarkov))
    other = [&m](double tau) { return TermAllanVariance(m, Term::kGaussMarkov, tau); };
  return allan::AssessNoiseTerms(table, t, other, relative_tolerance, allan::NoiseFitOptions());
}

const AuxChannelView* AuxOf(const Evaluation& e, const std::string& name) {
  for (const auto& c : e.views.aux.channels)
    if (c.name == name) return &c;
  return nullptr;
}

std::string Evidence(const Evaluation& base, const Evaluation& trial, Term t) {
  const auto p = ParametersOf(trial, t);
  auto val = [&](const char* name) {
    for (const auto& q : p)
      if (q.name == name) return q.value;
    return 0.0;
  };
  const double e0 = base.views.error, e1 = trial.views.error;
  switch (t) {
    case Term::kTemperature: {
      const auto* a = AuxOf(base, "temperature");
      return Format(
          "the low-frequency residual follows the temperature, r = %.2f: a thermal "
          "bias sensitivity of %.3g deg/h/degC (error %.3g -> %.3g)",
          a ? a->r : 0.0, val("coefficient"), e0, e1);
    }
    case Term::kTemperatureRate: {
      const auto* a = AuxOf(base, "temperature");
      return Format(
          "the residual follows dT/dt of temperature, r = %.2f: Shupe effect in the "
          "fiber coil, %.3g deg/h per degC/min (error %.3g -> %.3g)",
          a ? a->r_derivative : 0.0, val("coefficient") / 60.0, e0, e1);
    }
    case Term::kSinusoid: {
      const double f = val("frequency");
      return Format(
          "a periodic rate at %.4g Hz (period %.4g s), amplitude %.3g deg/h; it shows in "
          "the Allan curve near tau = 0.371/f = %.4g s",
          f, f > 0 ? 1.0 / f : 0.0, val("amplitude"), f > 0 ? 0.371 / f : 0.0);
    }
    case Term::kGaussMarkov: {
      const double tc = val("correlation_time");
      return Format(
          "the Allan curve bulges near tau = 1.89 Tc = %.4g s where the power-law terms "
          "cannot follow: correlated (Gauss-Markov) noise, sigma = %.3g deg/h, "
          "Tc = %.4g s (error %.3g -> %.3g)",
          1.89 * tc, val("sigma"), tc, e0, e1);
    }
    case Term::kBiasStep: {
      const double ts = val("time");
      return Format(
          "the windowed mean jumps by %.3g deg/h at t = %.5g s (%.3g h into the "
          "record): a bias step (error %.3g -> %.3g)",
          val("size"), ts, ts / 3600.0, e0, e1);
    }
    case Term::kWarmup:
      return Format(
          "the rate settles from the start of the record with a time constant of %.4g "
          "s, amplitude %.3g deg/h: a start-up transient (error %.3g -> %.3g)",
          val("time_constant"), val("amplitude"), e0, e1);
    case Term::kWhite:
      return "the short-tau Allan slope -1/2 is not covered: white rate noise (angle random walk)";
    case Term::kQuantization:
      return "the Allan curve falls with slope -1 at the shortest taus: angle quantization noise";
    case Term::kBiasInstability:
      return "a flat Allan floor is not covered: bias instability (flicker rate noise)";
    case Term::kRateRandomWalk:
      return "the long-tau Allan curve rises with slope +1/2: rate random walk";
    case Term::kRateRamp:
      return "the long-tau Allan curve rises with slope +1: a rate ramp";
  }
  return "";
}

}  // namespace

bool CompareOptions::IsValid(std::string* error) const {
  if (!deterministic.IsValid(error) || !stochastic.IsValid(error) || !views.IsValid(error) ||
      !imf.IsValid(error))
    return false;
  if (!(min_improvement > 0 && min_improvement <= 1) || !(tie_ratio >= 1) || !(tie_offset >= 0)) {
    if (error) *error = "min_improvement in (0, 1], tie_ratio >= 1, tie_offset >= 0";
    return false;
  }
  return true;
}

std::vector<Parameter> ParametersOf(const Evaluation& e, Term t) {
  if (IsFittedOnRate(t)) {
    const auto* c = LastComponent(e, t);
    return c ? ParametersOfComponent(*c) : std::vector<Parameter>{};
  }
  return StochasticParameters(e.stochastic.model, t);
}

Evaluation EvaluateModel(const CompareInput& in, const std::vector<Term>& terms,
                         const CompareOptions& o, const std::vector<PreparedAux>* prepared) {
  Evaluation e;
  e.terms = terms;
  std::string err;
  if (!o.IsValid(&err)) {
    e.termination = Termination::kInvalidOptions;
    e.message = err;
    return e;
  }
  if (in.rate_rad_s == nullptr || !(in.sample_rate_hz > 0)) {
    e.termination = Termination::kInvalidOptions;
    e.message = "no rate or sample rate";
    return e;
  }
  const Eigen::VectorXd& y = *in.rate_rad_s;
  const double fs = in.sample_rate_hz;
  const AuxChannel* temp = FindAux(in, "temperature");
  // Coordinate descent re-searches each nonlinear parameter with the others fixed; with at most
  // one nonlinear term (every trial of the default model) a pass repeats the first search against
  // the same fixed design (deterministic_fit.cpp): the warm-up and step searches return the same
  // value, the sinusoid refinement a value within its golden-section tolerance. Skipped.
  DeterministicOptions d = o.deterministic;
  if (std::count_if(terms.begin(), terms.end(), HasNonlinearParameter) <= 1)
    d.refinement_passes = 0;
  // The temperature goes to the fit only when a term uses it: FitDeterministic otherwise still
  // centres it and computes its smoothed derivative (two passes over n samples per trial).
  const bool thermal = std::any_of(terms.begin(), terms.end(), NeedsTemperature);
  e.deterministic = FitDeterministic(y, fs, temp && thermal ? &temp->values : nullptr, terms, d);
  if (!HasResult(e.deterministic.summary.termination)) {
    e.termination = e.deterministic.summary.termination;
    e.message = e.deterministic.summary.message;
    return e;
  }
  e.allan = ResidualAllan(e.deterministic.residual, fs, o.views);
  e.stochastic = FitStochastic(e.allan.tau_s, e.allan.avar, e.allan.edf, fs, y.size() / fs, terms,
                               o.stochastic);
  if (!HasResult(e.stochastic.summary.termination)) {
    e.termination = e.stochastic.summary.termination;
    e.message = e.stochastic.summary.message;
    return e;
  }
  e.noise_check = CheckIeeeTerms(e.stochastic.model, e.allan.table, o.stochastic.relative_floor);
  std::vector<PreparedAux> own;
  if (prepared == nullptr) {
    own = PrepareAux(in.aux, y.size(), fs, o.views);
    prepared = &own;
  }
  e.views =
      ComputeViews(e.deterministic.residual, fs, *prepared, e.stochastic.model, e.allan, o.views);
  FittedTerm bias{"bias",
                  {{"bias", DegH(e.deterministic.model.bias_rad_s),
                    DegH(e.deterministic.model.bias_se_rad_s), "deg/h"}}};
  if (in.latitude_deg) {
    // Assumes the sensitive axis is vertical (up): it then sees Omega_E sin(latitude).
    const double earth = units::RadPerSecondToDegPerHour(units::kEarthRotationRateRadS) *
                         std::sin(*in.latitude_deg * units::kRadPerDeg);
    bias.parameters.push_back({"bias_net_of_earth_rate", bias.parameters[0].value - earth,
                               bias.parameters[0].standard_error, "deg/h"});
  }
  e.fitted.push_back(bias);
  std::vector<Term> seen;
  for (Term t : terms) {
    if (t == Term::kSinusoid) continue;
    if (std::find(seen.begin(), seen.end(), t) != seen.end()) continue;
    seen.push_back(t);
    e.fitted.push_back({ToString(t), ParametersOf(e, t)});
  }
  for (const auto& c : e.deterministic.model.components)
    if (c.term == Term::kSinusoid) e.fitted.push_back({"sinusoid", ParametersOfComponent(c)});
  e.message = "error " + std::to_string(e.views.error);
  return e;
}

std::vector<Term> TrialTerms(const CompareInput& in, const std::vector<Term>& terms) {
  std::vector<Term> out;
  const bool has_temp = FindAux(in, "temperature") != nullptr;
  for (Term t : CatalogTerms()) {
    const bool present = std::find(terms.begin(), terms.end(), t) != terms.end();
    if (present && t != Term::kSinusoid) continue;
    if (NeedsTemperature(t) && !has_temp) continue;
    out.push_back(t);
  }
  return out;
}

std::vector<Suggestion> RankSuggestions(const Evaluation& base, const std::vector<Term>& tt,
                                        const std::vector<Evaluation>& trials,
                                        const CompareOptions& o) {
  std::vector<Suggestion> out;
  if (!HasResult(base.termination) || base.views.consistent) return out;
  const double e0 = base.views.error;
  const auto* aux_t = AuxOf(base, "temperature");
  const double aux_crit = base.views.aux.critical;
  const double n = static_cast<double>(base.deterministic.residual.size());
  const double lambda = std::max(1.0, base.deterministic.long_run_variance_ratio);
  const double n_eff = n / lambda;
  const double j = static_cast<double>(std::max<size_t>(base.allan.tau_s.size(), 2));
  const std::vector<ViewDomain> failing = FailingViews(base.views);
  for (size_t i = 0; i < tt.size() && i < trials.size(); ++i) {
    const Evaluation& tr = trials[i];
    const Term t = tt[i];
    if (!HasResult(tr.termination)) continue;
    std::vector<ViewDomain> fixes;
    for (ViewDomain domain : failing)
      if (ViewErrorOf(tr.views, domain) <= 1.0) fixes.push_back(domain);
    if (!(tr.views.error <= o.min_improvement * e0) && fixes.empty()) continue;
    if (t == Term::kTemperature && !(aux_t && std::abs(aux_t->z) > aux_crit)) continue;
    if (t == Term::kTemperatureRate && !(aux_t && std::abs(aux_t->z_derivative) > aux_crit))
      continue;
    Suggestion s;
    s.term = t;
    s.error_after = tr.views.error;
    const TimeView& tv = base.views.time;
    if (t == Term::kBiasStep && tv.step_critical > 0) {
      s.delta_bic = tv.step_critical * tv.step_critical - tv.step_z * tv.step_z;
    } else if (t == Term::kWarmup && tv.warmup_critical > 0) {
      s.delta_bic = tv.warmup_critical * tv.warmup_critical - tv.warmup_z * tv.warmup_z;
    } else if (IsFittedOnRate(t)) {
      const double dk =
          tr.deterministic.summary.num_parameters - base.deterministic.summary.num_parameters;
      s.delta_bic =
          n_eff * std::log(tr.deterministic.rss / base.deterministic.rss) + dk * std::log(n_eff);
    } else {
      const double dk =
          tr.stochastic.summary.num_parameters - base.stochastic.summary.num_parameters;
      s.delta_bic = tr.stochastic.summary.weighted_rss - base.stochastic.summary.weighted_rss +
                    dk * std::log(j);
    }
    s.parameters = ParametersOf(tr, t);
    s.evidence = Evidence(base, tr, t);
    s.view_errors_after = tr.views.view_errors;
    s.fixes = fixes;
    s.bic_rejects = s.delta_bic > 0;
    out.push_back(s);
  }
  // Groups (compare.h): fixes a failing view, only lowers the error, rejected by BIC.
  const auto group = [](const Suggestion& s) {
    return s.bic_rejects ? 2 : s.fixes.empty() ? 1 : 0;
  };
  std::sort(out.begin(), out.end(), [&](const Suggestion& a, const Suggestion& b) {
    if (group(a) != group(b)) return group(a) < group(b);
    return a.error_after < b.error_after;
  });
  for (auto first = out.begin(); first != out.end();) {
    const auto last = std::find_if(first, out.end(),
                                   [&](const Suggestion& s) { return group(s) != group(*first); });
    const double limit = o.tie_ratio * first->error_after + o.tie_offset;
    const auto lead_end =
        std::find_if(first, last, [&](const Suggestion& s) { return s.error_after > limit; });
    std::stable_sort(first, lead_end, [](const Suggestion& a, const Suggestion& b) {
      return a.delta_bic < b.delta_bic;
    });
    first = last;
  }
  // A thermal term behind a non-thermal leader must still be supported once the leader is in the
  // model: a large step or warm-up leaves low-frequency residual that the aux score test, run
  // under a model that lacks it, can attribute to a slow temperature cycle. If the leader's trial
  // explains the aux failure away, the temperature was innocent.
  if (!out.empty() && !NeedsTemperature(out.front().term)) {
    const size_t lead =
        static_cast<size_t>(std::find(tt.begin(), tt.end(), out.front().term) - tt.begin());
    const Evaluation* leader = lead < trials.size() ? &trials[lead] : nullptr;
    const auto* aux_lead = leader ? AuxOf(*leader, "temperature") : nullptr;
    const double crit = leader ? leader->views.aux.critical : 0.0;
    out.erase(std::remove_if(out.begin() + 1, out.end(),
                             [&](const Suggestion& s) {
                               if (!NeedsTemperature(s.term) || leader == nullptr) return false;
                               if (aux_lead == nullptr) return true;
                               const double z = s.term == Term::kTemperature
                                                    ? aux_lead->z
                                                    : aux_lead->z_derivative;
                               return !(std::abs(z) > crit);
                             }),
              out.end());
  }
  return out;
}

std::string FormatFailure(const Failure& f) {
  if (f.domain == ViewDomain::kAux) return std::string(ToString(f.domain)) + " " + f.channel;
  const char* unit = f.domain == ViewDomain::kFrequency ? "Hz" : "s";
  char buf[160];
  std::snprintf(buf, sizeof(buf), "%s %.4g-%.4g %s", ToString(f.domain), f.from, f.to, unit);
  return buf;
}

namespace {

// The failures as one phrase, the most severe first, at most `limit` of them.
std::string FailureList(std::vector<Failure> failures, size_t limit = 4) {
  std::stable_sort(failures.begin(), failures.end(),
                   [](const Failure& a, const Failure& b) { return a.severity > b.severity; });
  std::string out;
  for (size_t i = 0; i < failures.size() && i < limit; ++i)
    out += (i ? ", " : "") + FormatFailure(failures[i]);
  if (failures.size() > limit) out += " and " + std::to_string(failures.size() - limit) + " more";
  return out;
}

std::string Join(const std::vector<ViewDomain>& v) {
  std::string out;
  for (ViewDomain x : v) out += (out.empty() ? "" : ", ") + std::string(ToString(x));
  return out;
}

}  // namespace

Verdict MakeVerdict(const Evaluation& base, const std::vector<Term>& tt,
                    const std::vector<Evaluation>& trials, const std::vector<Suggestion>& sug) {
  Verdict v;
  if (!HasResult(base.termination) || base.views.consistent) return v;
  std::vector<ViewDomain> fixable;
  for (const Suggestion& s : sug)
    if (!s.bic_rejects) fixable.insert(fixable.end(), s.fixes.begin(), s.fixes.end());
  for (const Failure& f : base.views.failures)
    if (std::find(fixable.begin(), fixable.end(), f.domain) == fixable.end())
      v.unexplained.push_back(f);
  // Only a suggestion that BIC accepts and that makes a failing view pass is offered; the ranking
  // puts such a suggestion first whenever there is one.
  if (!sug.empty() && !sug.front().bic_rejects && !sug.front().fixes.empty()) {
    const Suggestion& s = sug.front();
    const size_t i = static_cast<size_t>(std::find(tt.begin(), tt.end(), s.term) - tt.begin());
    v.status = "inconsistent";
    v.suggestion = s.term;
    v.fixes = s.fixes;
    if (i < trials.size()) {
      v.consistent_with_suggestion = trials[i].views.consistent;
      v.still_failing = trials[i].views.failures;
    }
    v.text = std::string("inconsistent: suggestion ") + ToString(s.term);
    if (v.consistent_with_suggestion)
      v.text += " (makes the model consistent)";
    else
      v.text += " (fixes " + Join(v.fixes) +
                "; still failing with it: " + FailureList(v.still_failing) + ")";
    if (!v.unexplained.empty()) v.text += "; unexplained: " + FailureList(v.unexplained);
    return v;
  }
  v.status = "unexplained";
  v.still_failing = base.views.failures;
  v.text = "unexplained: no catalog term makes any failing view (" +
           Join(FailingViews(base.views)) + ") pass; failing: " + FailureList(v.still_failing);
  if (!sug.empty()) {
    const Suggestion& s = sug.front();
    v.text += std::string("; the first candidate, ") + ToString(s.term) +
              (s.bic_rejects ? " (rejected by BIC)" : "") +
              Format(", only takes the error %.3g -> %.3g", base.views.error, s.error_after);
  }
  return v;
}

CompareResult Compare(const CompareInput& in, const std::vector<Term>& terms,
                      const CompareOptions& o, const ForEach& for_each) {
  CompareResult r;
  if (in.rate_rad_s == nullptr) {
    r.summary.termination = Termination::kInvalidOptions;
    r.summary.message = "no rate";
    return r;
  }
  const std::vector<PreparedAux> prepared =
      PrepareAux(in.aux, in.rate_rad_s->size(), in.sample_rate_hz, o.views);
  r.base = EvaluateModel(in, terms, o, &prepared);
  r.summary.termination = r.base.termination;
  r.summary.message = r.base.message;
  if (!HasResult(r.base.termination)) return r;
  // Tasks: the trials, those with a nonlinear search (the longest) first so that a parallel
  // ForEach finishes together, then the base model's IMF view (one EMD per compare). Trials are
  // needed only when the base model is not consistent. Each task writes only its own slot.
  const std::vector<Term> tt =
      r.base.views.consistent ? std::vector<Term>{} : TrialTerms(in, terms);
  r.trials.resize(tt.size());
  std::vector<int> order(tt.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_partition(order.begin(), order.end(),
                        [&](int i) { return HasNonlinearParameter(tt[i]); });
  const int count = 1 + static_cast<int>(tt.size());
  // The trials' own step and warm-up scans would never be read (RankSuggestions uses the base
  // model's), so they are skipped: a FitDeterministic scan and a noise refit each, per trial.
  CompareOptions trial_options = o;
  trial_options.views.targeted_scans = false;
  const auto task = [&](int k) {
    if (k == count - 1) {
      r.base.imf = ComputeImfView(r.base.deterministic.residual, in.sample_rate_hz, prepared,
                                  r.base.stochastic.model, o.imf);
      return;
    }
    const int i = order[k];
    std::vector<Term> with = terms;
    with.push_back(tt[i]);
    r.trials[i] = EvaluateModel(in, with, trial_options, &prepared);
  };
  if (for_each) {
    for_each(count, task);
  } else {
    for (int k = 0; k < count; ++k) task(k);
  }
  if (r.base.views.consistent) return r;
  r.summary.num_trials = static_cast<int>(tt.size());
  r.suggestions = RankSuggestions(r.base, tt, r.trials, o);
  r.verdict = MakeVerdict(r.base, tt, r.trials, r.suggestions);
  return r;
}

}  // namespace fogpipe::model
