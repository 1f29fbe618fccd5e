#include "algorithms/model/compare.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numeric>

#include "algorithms/common/units.h"
#include "algorithms/model/bias_levels.h"
#include "algorithms/model/spectrum.h"

namespace fogpipe::model {
namespace {

const AuxChannel* FindAux(const CompareInput& input, const std::string& name) {
  for (const auto& channel : input.aux)
    if (channel.name == name && input.rate_rad_s &&
        channel.values.size() == input.rate_rad_s->size())
      return &channel;
  return nullptr;
}

double DegH(double rad_s) { return units::RadPerSecondToDegPerHour(rad_s); }

// Rate-fitted terms with a nonlinear parameter found by a search (frequency, step time, time
// constant).
bool HasNonlinearParameter(const ModelTerm& term) {
  return IsLine(term) || term == Term::kBiasStep || term == Term::kBiasLevels ||
         term == Term::kWarmup;
}

// True when the base model's time view shows several levels (bias_levels.h).
bool LevelsShow(const TimeView& view) { return view.levels_ratio > 1.0; }

// The segment levels of a bias_levels component (bias + the sizes so far), rad/s, and their
// standard errors (the step size's: a level is known at least as well as the jump into it).
void SegmentLevelsOf(double bias_rad_s, const DeterministicComponent& component,
                     std::vector<double>* levels, std::vector<double>* levels_se) {
  double level = bias_rad_s;
  levels->assign(1, level);
  levels_se->assign(1, component.coefficients_se.empty() ? 0.0 : component.coefficients_se[0]);
  for (size_t j = 0; j < component.coefficients.size(); ++j) {
    level += component.coefficients[j];
    levels->push_back(level);
    levels_se->push_back(component.coefficients_se[j]);
  }
}

// The record's length, s, as the time view's windows tile it (up to less than one window).
double RecordSecondsOf(const Evaluation& evaluation) {
  const TimeView& time = evaluation.views.time;
  return time.center_s.empty() ? 0.0 : time.center_s.back() + 0.5 * time.window_s;
}

const DeterministicComponent* LastComponent(const Evaluation& evaluation, const ModelTerm& term) {
  const DeterministicComponent* found = nullptr;
  for (const auto& component : evaluation.deterministic.model.components)
    if (component.term == term) found = &component;
  return found;
}

// The trial of `term` (trials[i] is that of trial_terms[i]), nullptr where it was not trialled.
const Evaluation* TrialOf(const std::vector<ModelTerm>& trial_terms,
                          const std::vector<Evaluation>& trials, const ModelTerm& term) {
  const auto at = std::find(trial_terms.begin(), trial_terms.end(), term);
  const auto index = static_cast<size_t>(at - trial_terms.begin());
  return index < trials.size() ? &trials[index] : nullptr;
}

// How the levels of an evaluation's bias_levels component read (bias_levels.h); num_levels 0
// without the component.
LevelsReading LevelsReadingOf(const Evaluation& evaluation) {
  const DeterministicComponent* component = LastComponent(evaluation, Term::kBiasLevels);
  if (component == nullptr) return {};
  std::vector<double> levels, levels_se;
  SegmentLevelsOf(evaluation.deterministic.model.bias_rad_s, *component, &levels, &levels_se);
  return DescribeLevels(levels, levels_se, RecordSecondsOf(evaluation));
}

std::string Format(const char* fmt, double a, double b = 0, double c = 0, double d = 0,
                   double e = 0) {
  char buf[512];
  std::snprintf(buf, sizeof(buf), fmt, a, b, c, d, e);
  return buf;
}

// An aux channel's unit ("1" without one), parenthesised where it is compound ("(m/s^2)").
std::string AuxUnit(const std::string& units, bool parenthesised) {
  const std::string unit = units.empty() ? "1" : units;
  const bool compound = unit.find_first_of("/^* ") != std::string::npos;
  return parenthesised && compound ? "(" + unit + ")" : unit;
}

// The unit of a channel's rate of change: "V/s", "(m/s^2)/s".
std::string AuxRateUnit(const std::string& units) { return AuxUnit(units, true) + "/s"; }

// Engineer's units per unit of an aux channel: "deg/h/V", "deg/h/V^2", "deg/h/(V/s)"; a channel
// without units is per unit of its value ("1").
std::string PerAuxUnit(const std::string& units, int power, bool rate) {
  if (rate) return "deg/h/(" + AuxRateUnit(units) + ")";
  return "deg/h/" + AuxUnit(units, true) + (power > 1 ? "^" + std::to_string(power) : "");
}

// A line a cos(2 pi f t) + b sin(2 pi f t) (rad/s, standard errors se_a, se_b) as an engineer reads
// it: frequency, amplitude W and phase, a cos + b sin = W sin(2 pi f t + phase).
std::vector<Parameter> LineParameters(const DeterministicComponent& component, double a, double b,
                                      double se_a, double se_b) {
  const double amplitude = std::hypot(a, b);
  const double amplitude_se =
      amplitude > 0 ? std::hypot(a * se_a, b * se_b) / amplitude : std::hypot(se_a, se_b);
  // W sin(phase) = a, W cos(phase) = b.
  return {
      {"frequency", component.nonlinear, component.nonlinear_se, "Hz"},
      {"amplitude", DegH(amplitude), DegH(amplitude_se), "deg/h"},
      {"phase", std::atan2(a, b), amplitude > 0 ? amplitude_se / amplitude : units::kPi, "rad"}};
}

// aux_am's coefficient covariance (deterministic_fit.h) as a matrix; the diagonal of the squared
// standard errors when it is missing (a model file).
Eigen::Matrix4d AmCovariance(const DeterministicComponent& component) {
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
  if (component.coefficients_covariance.size() == 16) {
    for (int i = 0; i < 16; ++i) covariance(i / 4, i % 4) = component.coefficients_covariance[i];
  } else {
    for (int i = 0; i < 4 && i < static_cast<int>(component.coefficients_se.size()); ++i)
      covariance(i, i) = component.coefficients_se[i] * component.coefficients_se[i];
  }
  return covariance;
}

// aux_am: the carrier (frequency, amplitude a0, phase) and the change of the amplitude per unit of
// the channel, a1 = the component of (c1, s1) along the carrier's phasor (c0, s0), i.e.
// (c0 c1 + s0 s1) / |(c0, s0)|, with the part in quadrature, (s0 c1 - c0 s1) / |(c0, s0)| (a phase
// modulation; 0 for a pure amplitude modulation) beside it. Their standard errors by the delta
// method on the four coefficients' covariance, the carrier's direction included.
std::vector<Parameter> AmParameters(const DeterministicComponent& component) {
  const std::vector<double>& c = component.coefficients;
  const std::vector<double>& se = component.coefficients_se;
  std::vector<Parameter> parameters = LineParameters(component, c[0], c[1], se[0], se[1]);
  const double w = std::max(std::hypot(c[0], c[1]), 1e-300);
  const double in_phase = (c[0] * c[2] + c[1] * c[3]) / w;
  const double quadrature = (c[1] * c[2] - c[0] * c[3]) / w;
  const Eigen::Vector4d in_phase_gradient(c[2] / w - in_phase * c[0] / (w * w),
                                          c[3] / w - in_phase * c[1] / (w * w), c[0] / w, c[1] / w);
  const Eigen::Vector4d quadrature_gradient(-c[3] / w - quadrature * c[0] / (w * w),
                                            c[2] / w - quadrature * c[1] / (w * w), c[1] / w,
                                            -c[0] / w);
  const Eigen::Matrix4d covariance = AmCovariance(component);
  const auto se_of = [&](const Eigen::Vector4d& gradient) {
    return std::sqrt(std::max(0.0, gradient.dot(covariance * gradient)));
  };
  const std::string unit = PerAuxUnit(component.units, 1, false);
  parameters.push_back({"modulation", DegH(in_phase), DegH(se_of(in_phase_gradient)), unit});
  parameters.push_back(
      {"modulation_quadrature", DegH(quadrature), DegH(se_of(quadrature_gradient)), unit});
  parameters.push_back({"reference", component.reference, 0.0, AuxUnit(component.units, false)});
  return parameters;
}

std::vector<Parameter> AuxParameters(const DeterministicComponent& component) {
  if (component.term.aux == AuxForm::kAm) return AmParameters(component);
  if (component.term.aux == AuxForm::kHysteresis)
    return {{"coefficient", DegH(component.coefficients[0]), DegH(component.coefficients_se[0]),
             "deg/h"},
            {"dead_band", component.reference, 0.0, AuxRateUnit(component.units)}};
  if (component.term.aux == AuxForm::kRate)
    return {{"coefficient", DegH(component.coefficients[0]), DegH(component.coefficients_se[0]),
             PerAuxUnit(component.units, 1, true)}};
  const int order = static_cast<int>(component.coefficients.size());
  std::vector<Parameter> parameters = {{"order", static_cast<double>(order), 0.0, ""}};
  for (int k = 0; k < order; ++k)
    parameters.push_back({k == 0 ? "coefficient" : "coefficient_" + std::to_string(k + 1),
                          DegH(component.coefficients[k]), DegH(component.coefficients_se[k]),
                          PerAuxUnit(component.units, k + 1, false)});
  parameters.push_back({"reference", component.reference, 0.0, AuxUnit(component.units, false)});
  return parameters;
}

std::vector<Parameter> ParametersOfComponent(const DeterministicComponent& component) {
  if (component.term.IsAux()) return AuxParameters(component);
  std::vector<Parameter> parameters;
  switch (component.term.term) {
    case Term::kTemperature:
      parameters.push_back({"coefficient", DegH(component.coefficients[0]),
                            DegH(component.coefficients_se[0]), "deg/h/degC"});
      break;
    case Term::kTemperatureRate:
      parameters.push_back({"coefficient", DegH(component.coefficients[0]),
                            DegH(component.coefficients_se[0]), "deg/h/(degC/s)"});
      break;
    case Term::kSinusoid:
      return LineParameters(component, component.coefficients[0], component.coefficients[1],
                            component.coefficients_se[0], component.coefficients_se[1]);
    case Term::kBiasStep:
      parameters.push_back({"time", component.nonlinear, component.nonlinear_se, "s"});
      parameters.push_back(
          {"size", DegH(component.coefficients[0]), DegH(component.coefficients_se[0]), "deg/h"});
      break;
    case Term::kBiasLevels:
      parameters.push_back({"steps", static_cast<double>(component.step_times_s.size()), 0.0, "1"});
      for (size_t j = 0; j < component.step_times_s.size(); ++j) {
        const std::string index = std::to_string(j + 1);
        parameters.push_back(
            {"time_" + index, component.step_times_s[j], component.step_times_se_s[j], "s"});
        parameters.push_back({"size_" + index, DegH(component.coefficients[j]),
                              DegH(component.coefficients_se[j]), "deg/h"});
      }
      break;
    case Term::kWarmup:
      parameters.push_back({"amplitude", DegH(component.coefficients[0]),
                            DegH(component.coefficients_se[0]), "deg/h"});
      parameters.push_back({"time_constant", component.nonlinear, component.nonlinear_se, "s"});
      break;
    default:
      break;
  }
  return parameters;
}

// A band as an engineer reads it: centre, half-power bandwidth 2 zeta f0, damping ratio and rms.
std::vector<Parameter> BandParameters(const NarrowBand& band) {
  return {{"frequency", band.f0_hz, band.f0_se_hz, "Hz"},
          {"bandwidth", HalfPowerBandwidthHz(band), band.bandwidth_se_hz, "Hz"},
          {"damping_ratio", band.zeta, band.zeta_se, "1"},
          {"rms", DegH(band.sigma_rad_s), DegH(band.sigma_se_rad_s), "deg/h"}};
}

std::vector<Parameter> StochasticParameters(const StochasticModel& model, Term term) {
  using namespace units;
  switch (term) {
    case Term::kNarrowBand:
      return model.bands.empty() ? std::vector<Parameter>{} : BandParameters(model.bands.back());
    case Term::kWhite:
      return {{"N", ArwToDegPerSqrtHour(model.n_rad_sqrt_s), ArwToDegPerSqrtHour(model.n_se),
               kArwUnit}};
    case Term::kQuantization:
      return {{"Q", QuantizationToArcsec(model.q_rad), QuantizationToArcsec(model.q_se),
               kQuantizationUnit}};
    case Term::kBiasInstability:
      return {{"B", BiasToDegPerHour(model.b_rad_s), BiasToDegPerHour(model.b_se), kBiasUnit}};
    case Term::kRateRandomWalk:
      return {{"K", RrwToDegPerHourSqrtHour(model.k_rad_s_sqrt_s),
               RrwToDegPerHourSqrtHour(model.k_se), kRrwUnit}};
    case Term::kRateRamp:
      return {{"R", RampToDegPerHour2(model.r_rad_s2), RampToDegPerHour2(model.r_se), kRampUnit}};
    case Term::kGaussMarkov:
      return {{"sigma", DegH(model.gm_sigma_rad_s), DegH(model.gm_sigma_se), "deg/h"},
              {"correlation_time", model.gm_correlation_time_s, model.gm_correlation_time_se, "s",
               model.gm_correlation_time_low_s, model.gm_correlation_time_high_s}};
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
allan::NoiseFitResult CheckIeeeTerms(const StochasticModel& model, const allan::AllanTable& table,
                                     double relative_tolerance) {
  constexpr double kAbsent = std::numeric_limits<double>::quiet_NaN();
  allan::NoiseTerms noise_terms;
  auto set = [&](Term term, double value, double se, double* out, double* out_se) {
    *out = model.Has(term) ? value : kAbsent;
    *out_se = model.Has(term) ? se : kAbsent;
  };
  set(Term::kQuantization, model.q_rad, model.q_se, &noise_terms.q_rad, &noise_terms.q_se);
  set(Term::kWhite, model.n_rad_sqrt_s, model.n_se, &noise_terms.n_rad_sqrt_s, &noise_terms.n_se);
  set(Term::kBiasInstability, model.b_rad_s, model.b_se, &noise_terms.b_rad_s, &noise_terms.b_se);
  set(Term::kRateRandomWalk, model.k_rad_s_sqrt_s, model.k_se, &noise_terms.k_rad_s_sqrt_s,
      &noise_terms.k_se);
  set(Term::kRateRamp, model.r_rad_s2, model.r_se, &noise_terms.r_rad_s2, &noise_terms.r_se);
  std::function<double(double)> other;
  if (model.Has(Term::kGaussMarkov) || model.Has(Term::kNarrowBand))
    other = [&model](double tau) {
      return TermAllanVariance(model, Term::kGaussMarkov, tau) +
             TermAllanVariance(model, Term::kNarrowBand, tau);
    };
  return allan::AssessNoiseTerms(table, noise_terms, other, relative_tolerance,
                                 allan::NoiseFitOptions());
}

const AuxChannelView* AuxOf(const Evaluation& evaluation, const std::string& name) {
  for (const auto& channel : evaluation.views.aux.channels)
    if (channel.name == name) return &channel;
  return nullptr;
}

// aux_am's modulation test: the Wald chi-square (2 degrees of freedom) of the amplitude's change
// with the channel, (c1, s1) under its covariance, and its critical value at the aux view's
// per-test level: the aux view tests each channel's |z| against `critical` (Bonferroni over its
// tests), a two-sided tail p = erfc(critical / sqrt 2); the chi-square with 2 degrees of freedom
// has the tail exp(-x / 2), so the same p gives -2 ln p.
struct ModulationTest {
  double chi_square = 0, critical = std::numeric_limits<double>::infinity();
};
// The Wald chi-square of aux_am's coefficients [first, last) under their covariance.
double WaldChiSquare(const DeterministicComponent& component, int first, int last) {
  const int size = last - first;
  if (component.coefficients.size() != 4 || size <= 0) return 0.0;
  const Eigen::MatrixXd covariance = AmCovariance(component).block(first, first, size, size);
  Eigen::VectorXd beta(size);
  for (int j = 0; j < size; ++j) beta[j] = component.coefficients[first + j];
  const Eigen::LDLT<Eigen::MatrixXd> solver(covariance);
  if (solver.info() != Eigen::Success) return 0.0;
  return beta.dot(solver.solve(beta));
}

ModulationTest TestModulation(const Evaluation& trial, const ModelTerm& term) {
  ModulationTest test;
  const DeterministicComponent* component = LastComponent(trial, term);
  if (component == nullptr || component->coefficients.size() != 4) return test;
  test.chi_square = WaldChiSquare(*component, 2, 4);
  const double tail = std::erfc(trial.views.aux.critical / std::sqrt(2.0));
  test.critical = -2.0 * std::log(std::max(tail, 1e-300));
  return test;
}

// The delta_bic that orders a suggestion among those tied on the error (compare.h). A supported
// aux_am holds a sinusoid at its frequency (the nested model without the modulation), and the
// modulation test is the comparison of the two; their delta_bic are of different forms (Wald,
// RSS), so it takes the sinusoid's where that is lower, and goes first on a tie.
double TieBreakBic(const Suggestion& suggestion, const std::vector<Suggestion>& sinusoids) {
  if (suggestion.term.aux != AuxForm::kAm) return suggestion.delta_bic;
  const auto frequency = [](const Suggestion& s) -> const Parameter* {
    for (const Parameter& parameter : s.parameters)
      if (parameter.name == "frequency") return &parameter;
    return nullptr;
  };
  const Parameter* line = frequency(suggestion);
  double bic = suggestion.delta_bic;
  for (const Suggestion& sinusoid : sinusoids) {
    const Parameter* other = frequency(sinusoid);
    if (line && other &&
        std::abs(line->value - other->value) <=
            3.0 * std::hypot(line->standard_error, other->standard_error))
      bic = std::min(bic, sinusoid.delta_bic);
  }
  return bic;
}

// An AM line's parameters as the evidence and the verdict quote them.
struct AmLine {
  double frequency = 0, amplitude = 0, modulation = 0;
  std::string unit;  // the modulation's
};
AmLine AmLineOf(const std::vector<Parameter>& parameters) {
  AmLine line;
  for (const Parameter& parameter : parameters) {
    if (parameter.name == "frequency") line.frequency = parameter.value;
    if (parameter.name == "amplitude") line.amplitude = parameter.value;
    if (parameter.name == "modulation") {
      line.modulation = parameter.value;
      line.unit = parameter.units;
    }
  }
  return line;
}

std::string AuxEvidence(const Evaluation& base, const Evaluation& trial, const ModelTerm& term) {
  const auto* channel = AuxOf(base, term.channel);
  const auto parameters = ParametersOf(trial, term);
  const Parameter* coefficient = nullptr;
  for (const auto& parameter : parameters)
    if (parameter.name == "coefficient") coefficient = &parameter;
  const double error_before = base.views.error, error_after = trial.views.error;
  if (term.aux == AuxForm::kAm) {
    const AmLine line = AmLineOf(parameters);
    const ModulationTest test = TestModulation(trial, term);
    return Format("a line at %.5g Hz, amplitude %.3g deg/h, ", line.frequency, line.amplitude) +
           "whose amplitude follows " + term.channel + Format(" by %.3g ", line.modulation) +
           line.unit +
           Format(
               " (modulation chi-square %.3g against %.3g; its sidebands are not separate "
               "lines; error %.3g -> %.3g)",
               test.chi_square, test.critical, error_before, error_after);
  }
  if (term.aux == AuxForm::kHysteresis)
    return "the bias differs between rising and falling " + term.channel +
           Format(" (r = %.2f with its derivative): +-%.3g deg/h, a hysteresis",
                  channel ? channel->r_derivative : 0.0, coefficient ? coefficient->value : 0.0) +
           Format(" (error %.3g -> %.3g)", error_before, error_after);
  if (term.aux == AuxForm::kRate)
    return "the residual follows d(" + term.channel + ")/dt" +
           Format(", r = %.2f: ", channel ? channel->r_derivative : 0.0) +
           Format("%.3g ", coefficient ? coefficient->value : 0.0) +
           (coefficient ? coefficient->units : "") +
           Format(" (error %.3g -> %.3g)", error_before, error_after);
  const int order = static_cast<int>(parameters.empty() ? 1 : parameters.front().value);
  return "the low-frequency residual follows aux " + term.channel +
         Format(", r = %.2f: a bias polynomial of order %.0f in it (BIC), linear coefficient ",
                channel ? channel->r : 0.0, order) +
         Format("%.3g ", coefficient ? coefficient->value : 0.0) +
         (coefficient ? coefficient->units : "") +
         Format(" (error %.3g -> %.3g)", error_before, error_after);
}

std::string Evidence(const Evaluation& base, const Evaluation& trial, const ModelTerm& model_term) {
  if (model_term.IsAux()) return AuxEvidence(base, trial, model_term);
  const Term term = model_term.term;
  const auto parameters = ParametersOf(trial, term);
  auto val = [&](const char* name) {
    for (const auto& parameter : parameters)
      if (parameter.name == name) return parameter.value;
    return 0.0;
  };
  const double error_before = base.views.error, error_after = trial.views.error;
  switch (term) {
    case Term::kTemperature: {
      const auto* temperature = AuxOf(base, "temperature");
      return Format(
          "the low-frequency residual follows the temperature, r = %.2f: a thermal "
          "bias sensitivity of %.3g deg/h/degC (error %.3g -> %.3g)",
          temperature ? temperature->r : 0.0, val("coefficient"), error_before, error_after);
    }
    case Term::kTemperatureRate: {
      const auto* temperature = AuxOf(base, "temperature");
      return Format(
          "the residual follows dT/dt of temperature, r = %.2f: Shupe effect in the "
          "fiber coil, %.3g deg/h per degC/min (error %.3g -> %.3g)",
          temperature ? temperature->r_derivative : 0.0, val("coefficient") / 60.0, error_before,
          error_after);
    }
    case Term::kSinusoid: {
      const double frequency_hz = val("frequency");
      return Format(
          "a periodic rate at %.4g Hz (period %.4g s), amplitude %.3g deg/h; it shows in "
          "the Allan curve near tau = 0.371/f = %.4g s",
          frequency_hz, frequency_hz > 0 ? 1.0 / frequency_hz : 0.0, val("amplitude"),
          frequency_hz > 0 ? 0.371 / frequency_hz : 0.0);
    }
    case Term::kGaussMarkov: {
      const double correlation_time_s = val("correlation_time");
      // Random telegraph switching has the same Lorentzian spectrum (bias_levels.h): what the
      // levels say is added by RankSuggestions, which sees the bias_levels trial.
      return Format(
          "the Allan curve bulges near tau = 1.89 Tc = %.4g s where the power-law terms "
          "cannot follow: correlated (Gauss-Markov) noise, sigma = %.3g deg/h, "
          "Tc = %.4g s (error %.3g -> %.3g)",
          1.89 * correlation_time_s, val("sigma"), correlation_time_s, error_before, error_after);
    }
    case Term::kBiasStep: {
      const double step_time_s = val("time");
      return Format(
          "the windowed mean jumps by %.3g deg/h at t = %.5g s (%.3g h into the "
          "record): a bias step (error %.3g -> %.3g)",
          val("size"), step_time_s, step_time_s / 3600.0, error_before, error_after);
    }
    case Term::kBiasLevels: {
      if (LastComponent(trial, Term::kBiasLevels) == nullptr) return "";
      const std::string found =
          LevelsShow(base.views.time)
              ? Format("(%.0f steps, -2 ln L drop %.3g times their penalty)", val("steps"),
                       base.views.time.levels_ratio)
              : Format(
                    "(%.0f steps chosen by the segmentation's BIC; found where the long-tau "
                    "check flags)",
                    val("steps"));
      return "the residual falls into constant levels " + found +
             Format(", which no Gaussian noise term makes (error %.3g -> %.3g); ", error_before,
                    error_after) +
             Format(
                 "without them the jumps pass for rate random walk (K %.3g -> %.3g "
                 "deg/h/sqrt(h)); ",
                 units::RrwToDegPerHourSqrtHour(base.stochastic.model.k_rad_s_sqrt_s),
                 units::RrwToDegPerHourSqrtHour(trial.stochastic.model.k_rad_s_sqrt_s)) +
             LevelsReadingOf(trial).text;
    }
    case Term::kWarmup:
      return Format(
          "the rate settles from the start of the record with a time constant of %.4g "
          "s, amplitude %.3g deg/h: a start-up transient (error %.3g -> %.3g)",
          val("time_constant"), val("amplitude"), error_before, error_after);
    case Term::kNarrowBand:
      return Format(
          "a band of excess power centred at %.4g Hz, half-power width %.3g Hz, rms %.3g deg/h: "
          "vibration or a structural resonance (error %.3g -> %.3g)",
          val("frequency"), val("bandwidth"), val("rms"), error_before, error_after);
    case Term::kAngleQuantizer: {
      const AngleLattice& lattice = trial.angle_quantizer.lattice;
      return Format(
          "the rate is an angle counter of step %.4g arcsec whose increments are correlated "
          "beyond lag 1 (%.4g against %.4g): an undithered counter's coarse error, its idle "
          "tones; the angle drawn within the steps (error %.3g -> %.3g)",
          val("step"), lattice.whiteness_statistic, lattice.whiteness_critical, error_before,
          error_after);
    }
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

// The narrow bands of a model with `count` narrow_band terms, one after the other: each starts
// from the most severe failing band of the frequency view under the model fitted so far (the
// bands found before it included), is fitted on the residual's Welch PSD against that model as
// background (narrow_band.h), and the Allan-fitted terms are refitted with the bands as a known
// offset. Fewer bands than asked when the frequency view has no failing band left.
void FitBands(int count, double fs, int num_views, const CompareOptions& options,
              Evaluation* evaluation) {
  const Eigen::VectorXd& residual = evaluation->deterministic.residual;
  const Spectrum welch = FrequencyViewPsd(residual, fs, options.views);
  if (welch.psd.empty()) return;
  std::vector<NarrowBand> bands;
  std::string note;
  for (int b = 0; b < count; ++b) {
    const StochasticModel& model = evaluation->stochastic.model;
    const std::vector<Failure> failures =
        FrequencyFailuresOf(residual, fs, model, options.views, num_views);
    const Failure* worst = nullptr;
    for (const Failure& failure : failures)
      if (worst == nullptr || failure.severity > worst->severity) worst = &failure;
    if (worst == nullptr) {
      note = "; narrow_band: no failing frequency band to fit";
      break;
    }
    StochasticModel without_bands = model;
    without_bands.bands.clear();
    std::vector<double> background(welch.frequency_hz.size()), fixed(background.size(), 0.0);
    for (size_t k = 0; k < background.size(); ++k) {
      background[k] = ModelOneSidedPsd(without_bands, welch.frequency_hz[k], fs);
      for (const NarrowBand& band : bands)
        fixed[k] += NarrowBandOneSidedPsd(band, welch.frequency_hz[k]);
    }
    const NarrowBandFitResult fit =
        FitNarrowBand(welch, background, fixed, FirstTestedBin(options.views),
                      {worst->from, worst->to, worst->center_hz, worst->excess_power});
    if (!fit.ok) {
      note = "; narrow_band: " + fit.message;
      break;
    }
    bands.push_back(fit.band);
    const StochasticFit refit = FitStochastic(
        evaluation->allan.tau_s, evaluation->allan.avar, evaluation->allan.edf, fs,
        residual.size() / fs, CatalogTermsOf(evaluation->terms), options.stochastic, bands);
    if (!HasResult(refit.summary.termination)) break;
    evaluation->stochastic = refit;
  }
  evaluation->stochastic.summary.message += note;
}

}  // namespace

bool CompareOptions::IsValid(std::string* error) const {
  if (!deterministic.IsValid(error) || !stochastic.IsValid(error) || !views.IsValid(error) ||
      !imf.IsValid(error) || !long_tau.IsValid(error) || !angle_lattice.IsValid(error) ||
      !angle_quantizer.IsValid(error))
    return false;
  if (!(min_improvement > 0 && min_improvement <= 1) || !(tie_ratio >= 1) || !(tie_offset >= 0)) {
    if (error) *error = "min_improvement in (0, 1], tie_ratio >= 1, tie_offset >= 0";
    return false;
  }
  return true;
}

std::vector<Parameter> ParametersOf(const Evaluation& evaluation, const ModelTerm& term) {
  if (IsFittedOnRate(term)) {
    const auto* component = LastComponent(evaluation, term);
    return component ? ParametersOfComponent(*component) : std::vector<Parameter>{};
  }
  if (term == Term::kAngleQuantizer) {
    const AngleQuantizerFit& fit = evaluation.angle_quantizer;
    if (!fit.ok) return {};
    const double step = fit.lattice.step_rad, step_se = fit.lattice.step_se_rad;
    const double per_second = fit.rate_step_rad_s / step;  // the sample rate
    return {{"step", units::QuantizationToArcsec(step), units::QuantizationToArcsec(step_se),
             units::kQuantizationUnit},
            {"rate_step", DegH(fit.rate_step_rad_s), DegH(step_se * per_second), "deg/h"},
            {"noise_per_sample", units::QuantizationToArcsec(fit.noise_per_sample_rad), 0.0,
             units::kQuantizationUnit}};
  }
  return StochasticParameters(evaluation.stochastic.model, term.term);
}

Evaluation EvaluateModel(const CompareInput& input, const std::vector<ModelTerm>& terms,
                         const CompareOptions& options, const std::vector<PreparedAux>* prepared) {
  Evaluation evaluation;
  evaluation.terms = terms;
  std::string err;
  if (!options.IsValid(&err)) {
    evaluation.termination = Termination::kInvalidOptions;
    evaluation.message = err;
    return evaluation;
  }
  if (input.rate_rad_s == nullptr || !(input.sample_rate_hz > 0)) {
    evaluation.termination = Termination::kInvalidOptions;
    evaluation.message = "no rate or sample rate";
    return evaluation;
  }
  const double fs = input.sample_rate_hz;
  // angle_quantizer: the counter's error is replaced by a draw of the angle within its boxes
  // before everything else (angle_quantizer.h), with the white noise of the model fitted to the
  // raw counter.
  Eigen::VectorXd imputed;
  if (std::find(terms.begin(), terms.end(), ModelTerm(Term::kAngleQuantizer)) != terms.end()) {
    std::vector<ModelTerm> without;
    for (const ModelTerm& term : terms)
      if (term != Term::kAngleQuantizer) without.push_back(term);
    CompareOptions raw_options = options;
    raw_options.views.targeted_scans = false;
    raw_options.long_tau.enabled = false;
    const Evaluation raw = EvaluateModel(input, without, raw_options, prepared);
    const AngleLattice lattice = DetectAngleLattice(*input.rate_rad_s, fs, options.angle_lattice);
    double sigma =
        HasResult(raw.termination) ? raw.stochastic.model.n_rad_sqrt_s / std::sqrt(fs) : 0.0;
    // Stochastic EM (Celeux & Diebolt 1985): draw with sigma, refit N on the draw, until N moves
    // by less than the tolerance; the moves after the first are extrapolated (angle_quantizer.h).
    double previous_sigma = 0, previous_refitted = 0;
    for (int round = 0; round < options.angle_quantizer.max_rounds; ++round) {
      imputed = ImputeAngleOnLattice(*input.rate_rad_s, fs, lattice, sigma, options.angle_quantizer,
                                     &evaluation.angle_quantizer);
      evaluation.angle_quantizer.rounds = round + 1;
      if (!evaluation.angle_quantizer.ok || round + 1 == options.angle_quantizer.max_rounds) break;
      CompareInput drawn = input;
      drawn.rate_rad_s = &imputed;
      const Evaluation refit = EvaluateModel(drawn, without, raw_options, prepared);
      if (!HasResult(refit.termination)) break;
      const double refitted = refit.stochastic.model.n_rad_sqrt_s / std::sqrt(fs);
      bool settled = false;
      const double next = NextEmNoise(sigma, refitted, previous_sigma, previous_refitted,
                                      options.angle_quantizer, &settled);
      previous_sigma = sigma;
      previous_refitted = refitted;
      sigma = next;
      if (settled) break;
    }
    if (!evaluation.angle_quantizer.ok) {
      evaluation.termination = Termination::kInsufficientData;
      evaluation.message = evaluation.angle_quantizer.message;
      return evaluation;
    }
  }
  if (imputed.size() > 0) evaluation.angle_quantizer_rate_rad_s = imputed;
  const Eigen::VectorXd& rate = imputed.size() > 0 ? imputed : *input.rate_rad_s;
  // Coordinate descent re-searches each nonlinear parameter with the others fixed; with at most
  // one nonlinear term (every trial of the default model) a pass repeats the first search against
  // the same fixed design (deterministic_fit.cpp): the warm-up and step searches return the same
  // value, the sinusoid refinement a value within its golden-section tolerance. Skipped.
  DeterministicOptions deterministic_options = options.deterministic;
  if (std::count_if(terms.begin(), terms.end(), HasNonlinearParameter) <= 1)
    deterministic_options.refinement_passes = 0;
  // A channel goes to the fit only when a term reads it: FitDeterministic otherwise still
  // centres the temperature (a pass over n samples per trial).
  std::vector<AuxSeries> aux;
  for (const ModelTerm& term : terms) {
    const std::string name = AuxChannelOf(term);
    const AuxChannel* channel = name.empty() ? nullptr : FindAux(input, name);
    if (channel && std::none_of(aux.begin(), aux.end(),
                                [&](const AuxSeries& series) { return series.name == name; }))
      aux.push_back({channel->name, channel->units, &channel->values});
  }
  evaluation.deterministic = FitDeterministic(rate, fs, aux, terms, deterministic_options);
  if (!HasResult(evaluation.deterministic.summary.termination)) {
    evaluation.termination = evaluation.deterministic.summary.termination;
    evaluation.message = evaluation.deterministic.summary.message;
    return evaluation;
  }
  evaluation.allan = ResidualAllan(evaluation.deterministic.residual, fs, options.views);
  evaluation.stochastic =
      FitStochastic(evaluation.allan.tau_s, evaluation.allan.avar, evaluation.allan.edf, fs,
                    rate.size() / fs, CatalogTermsOf(terms), options.stochastic);
  if (!HasResult(evaluation.stochastic.summary.termination)) {
    evaluation.termination = evaluation.stochastic.summary.termination;
    evaluation.message = evaluation.stochastic.summary.message;
    return evaluation;
  }
  std::vector<PreparedAux> own;
  if (prepared == nullptr) {
    own = PrepareAux(input.aux, rate.size(), fs, options.views);
    prepared = &own;
  }
  const int band_count =
      static_cast<int>(std::count(terms.begin(), terms.end(), Term::kNarrowBand));
  if (band_count > 0)
    FitBands(band_count, fs, ScoredViewCount(!prepared->empty()), options, &evaluation);
  evaluation.noise_check = CheckIeeeTerms(evaluation.stochastic.model, evaluation.allan.table,
                                          options.stochastic.relative_floor);
  evaluation.views = ComputeViews(evaluation.deterministic.residual, fs, *prepared,
                                  evaluation.stochastic.model, evaluation.allan, options.views);
  evaluation.long_tau = CheckLongTauTerms(evaluation.deterministic.residual, fs,
                                          evaluation.stochastic.model, options.long_tau);
  FittedTerm bias{"bias",
                  {{"bias", DegH(evaluation.deterministic.model.bias_rad_s),
                    DegH(evaluation.deterministic.model.bias_se_rad_s), "deg/h"}}};
  if (input.latitude_deg) {
    // Assumes the sensitive axis is vertical (up): it then sees Omega_E sin(latitude).
    const double earth = units::RadPerSecondToDegPerHour(units::kEarthRotationRateRadS) *
                         std::sin(*input.latitude_deg * units::kRadPerDeg);
    bias.parameters.push_back({"bias_net_of_earth_rate", bias.parameters[0].value - earth,
                               bias.parameters[0].standard_error, "deg/h"});
  }
  evaluation.fitted.push_back(bias);
  std::vector<ModelTerm> seen;
  for (const ModelTerm& term : terms) {
    if (term == Term::kSinusoid || term == Term::kNarrowBand) continue;
    if (std::find(seen.begin(), seen.end(), term) != seen.end()) continue;
    seen.push_back(term);
    evaluation.fitted.push_back({ToString(term), ParametersOf(evaluation, term)});
  }
  for (const auto& component : evaluation.deterministic.model.components)
    if (component.term == Term::kSinusoid)
      evaluation.fitted.push_back({"sinusoid", ParametersOfComponent(component)});
  for (const NarrowBand& band : evaluation.stochastic.model.bands)
    evaluation.fitted.push_back({"narrow_band", BandParameters(band)});
  evaluation.message = "error " + std::to_string(evaluation.views.error);
  return evaluation;
}

std::vector<ModelTerm> TrialTerms(const CompareInput& input, const std::vector<ModelTerm>& terms) {
  std::vector<ModelTerm> trial_terms;
  const auto present = [&](const ModelTerm& term) {
    return std::find(terms.begin(), terms.end(), term) != terms.end();
  };
  const bool has_temp = FindAux(input, "temperature") != nullptr;
  // A thermal catalog term held by an aux term of the model (ThermalTermWithin) is not tried.
  const auto held = [&](Term term) {
    return std::any_of(terms.begin(), terms.end(),
                       [&](const ModelTerm& t) { return ThermalTermWithin(t) == term; });
  };
  for (Term term : CatalogTerms()) {
    if (held(term)) continue;
    if (present(term) && term != Term::kSinusoid && term != Term::kNarrowBand) continue;
    if (NeedsTemperature(term) && !has_temp) continue;
    trial_terms.push_back(term);
  }
  for (const AuxChannel& channel : input.aux) {
    if (FindAux(input, channel.name) != &channel) continue;  // other length, or a repeated name
    const ModelTerm value = ModelTerm::Aux(AuxForm::kValue, channel.name);
    const ModelTerm rate = ModelTerm::Aux(AuxForm::kRate, channel.name);
    // aux:temperature is tried beside temperature only while the model lacks it; aux_rate:
    // temperature never, as it is the temperature_rate term, tried as such.
    const std::optional<Term> value_within = ThermalTermWithin(value);
    if (!present(value) && !(value_within && present(*value_within))) trial_terms.push_back(value);
    if (!present(rate) && !ThermalTermWithin(rate)) trial_terms.push_back(rate);
    const ModelTerm am = ModelTerm::Aux(AuxForm::kAm, channel.name);
    if (!present(am)) trial_terms.push_back(am);
  }
  return trial_terms;
}

namespace {

// Terms that could explain a slow effect (SlowEffectTrialTerms).
bool ExplainsSlowEffect(const ModelTerm& term) {
  return (term.IsAux() && !IsLine(term)) || term == Term::kBiasStep || term == Term::kBiasLevels ||
         term == Term::kWarmup || term == Term::kTemperature || term == Term::kTemperatureRate;
}

}  // namespace

std::vector<ModelTerm> SlowEffectTrialTerms(const CompareInput& input,
                                            const std::vector<ModelTerm>& terms) {
  std::vector<ModelTerm> trial_terms;
  for (const ModelTerm& term : TrialTerms(input, terms))
    if (ExplainsSlowEffect(term)) trial_terms.push_back(term);
  for (const AuxChannel& channel : input.aux) {
    if (FindAux(input, channel.name) != &channel) continue;  // other length, or a repeated name
    const ModelTerm hysteresis = ModelTerm::Aux(AuxForm::kHysteresis, channel.name);
    if (std::find(terms.begin(), terms.end(), hysteresis) == terms.end())
      trial_terms.push_back(hysteresis);
  }
  return trial_terms;
}

bool AuxViewSupports(const Evaluation& evaluation, const ModelTerm& term) {
  const std::string channel = AuxChannelOf(term);
  if (channel.empty()) return true;
  if (term.aux == AuxForm::kAm) {
    const ModulationTest test = TestModulation(evaluation, term);
    return test.chi_square > test.critical;
  }
  const auto* view = AuxOf(evaluation, channel);
  if (view == nullptr) return false;
  return std::abs(UsesDerivative(term) ? view->z_derivative : view->z) >
         evaluation.views.aux.critical;
}

std::vector<Suggestion> RankSuggestions(const Evaluation& base,
                                        const std::vector<ModelTerm>& trial_terms,
                                        const std::vector<Evaluation>& trials,
                                        const CompareOptions& options) {
  std::vector<Suggestion> suggestions;
  const bool flagged = base.long_tau.flagged;
  if (!HasResult(base.termination) || (base.views.consistent && !flagged)) return suggestions;
  const double base_error = base.views.error;
  // temperature and aux:temperature are one nested family (catalog.h): the polynomial fit's BIC
  // (deterministic_fit.h) chooses between them, with the long-run variance of the residual once
  // the thermal effect is modelled, so exactly one of them is listed: temperature when the order
  // is 1, aux:temperature otherwise.
  const ModelTerm thermal_polynomial = ModelTerm::Aux(AuxForm::kValue, "temperature");
  const auto polynomial_order = [&]() -> size_t {
    const Evaluation* trial = TrialOf(trial_terms, trials, thermal_polynomial);
    if (trial == nullptr || !HasResult(trial->termination)) return 0;
    const auto* component = LastComponent(*trial, thermal_polynomial);
    return component ? component->coefficients.size() : 0;
  }();
  const bool temperature_trialled = std::find(trial_terms.begin(), trial_terms.end(),
                                              ModelTerm(Term::kTemperature)) != trial_terms.end();
  const double num_samples = static_cast<double>(base.deterministic.residual.size());
  const double lambda = std::max(1.0, base.deterministic.long_run_variance_ratio);
  const double n_eff = num_samples / lambda;
  const double num_taus = static_cast<double>(std::max<size_t>(base.allan.tau_s.size(), 2));
  const std::vector<ViewDomain> failing = FailingViews(base.views);
  for (size_t i = 0; i < trial_terms.size() && i < trials.size(); ++i) {
    const Evaluation& trial = trials[i];
    const ModelTerm& term = trial_terms[i];
    if (!HasResult(trial.termination)) continue;
    std::vector<ViewDomain> fixes;
    for (ViewDomain domain : failing)
      if (ViewErrorOf(trial.views, domain) <= 1.0) fixes.push_back(domain);
    const bool improves =
        !base.views.consistent &&
        (trial.views.error <= options.min_improvement * base_error || !fixes.empty());
    // Clears the flag, BIC permitting (checked below).
    // (A check evaluated without a flag, or one that finds B, K and R too small to absorb
    // anything; one that could not be evaluated otherwise, e.g. a singular covariance, says
    // nothing.)
    const bool unflags = flagged && !trial.long_tau.flagged &&
                         (trial.long_tau.evaluated || trial.long_tau.nothing_to_absorb);
    if (!improves && !unflags) continue;
    // aux_am's evidence is its own modulation test, in its trial; every other aux term's is the
    // base model's aux view.
    const bool supported = AuxViewSupports(term.aux == AuxForm::kAm ? trial : base, term);
    if (!unflags && !supported) continue;
    if (term == thermal_polynomial && temperature_trialled && polynomial_order <= 1) continue;
    if (term == Term::kTemperature && polynomial_order >= 2) continue;
    // bias_levels only with at least two steps (one is bias_step's; bias_levels.h), where the
    // base model's levels test shows levels or its trial clears the long-tau flag.
    if (term == Term::kBiasLevels) {
      const DeterministicComponent* levels = LastComponent(trial, Term::kBiasLevels);
      if (levels == nullptr || levels->step_times_s.size() < 2 ||
          !(LevelsShow(base.views.time) || unflags))
        continue;
    }
    Suggestion suggestion;
    suggestion.term = term;
    suggestion.error_after = trial.views.error;
    const TimeView& time_view = base.views.time;
    if (term == Term::kBiasStep && time_view.step_critical > 0) {
      suggestion.delta_bic =
          time_view.step_critical * time_view.step_critical - time_view.step_z * time_view.step_z;
    } else if (term == Term::kWarmup && time_view.warmup_critical > 0) {
      suggestion.delta_bic = time_view.warmup_critical * time_view.warmup_critical -
                             time_view.warmup_z * time_view.warmup_z;
    } else if (term == Term::kBiasLevels) {
      // The segmentation's own modified BIC (bias_levels.h): penalty - (-2 ln L drop), the base
      // model's levels test's where it shows levels, else (a long-tau flag) the fit's, under the
      // residual's own variance ratio.
      suggestion.delta_bic = LevelsShow(time_view)
                                 ? time_view.levels_penalty * (1.0 - time_view.levels_ratio)
                                 : LastComponent(trial, Term::kBiasLevels)->levels_delta_bic;
    } else if (term == Term::kNarrowBand &&
               trial.stochastic.model.bands.size() > base.stochastic.model.bands.size()) {
      // Whittle -2 ln L drop of the new band over the window it was fitted in (the rest of the
      // spectrum is unchanged by it), 3 parameters, n = the effectively independent Welch bins.
      const NarrowBand& band = trial.stochastic.model.bands.back();
      suggestion.delta_bic =
          -band.minus_two_log_likelihood_drop + 3.0 * std::log(std::max(band.effective_bins, 2.0));
    } else if (term == Term::kAngleQuantizer && trial.angle_quantizer.ok) {
      // The evidence is the counter's own: the portmanteau of its increments beyond lag 1 against
      // its critical value (angle_lattice.h), as bias_step's scan statistic against its own.
      const AngleLattice& lattice = trial.angle_quantizer.lattice;
      suggestion.delta_bic = lattice.whiteness_critical - lattice.whiteness_statistic;
    } else if (term.aux == AuxForm::kAm && LastComponent(trial, term) != nullptr) {
      // Wald form (compare.h): the four amplitudes and the frequency.
      const double added_parameters =
          trial.deterministic.summary.num_parameters - base.deterministic.summary.num_parameters;
      suggestion.delta_bic =
          -WaldChiSquare(*LastComponent(trial, term), 0, 4) + added_parameters * std::log(n_eff);
    } else if (IsFittedOnRate(term)) {
      const double added_parameters =
          trial.deterministic.summary.num_parameters - base.deterministic.summary.num_parameters;
      suggestion.delta_bic = n_eff * std::log(trial.deterministic.rss / base.deterministic.rss) +
                             added_parameters * std::log(n_eff);
    } else {
      const double added_parameters =
          trial.stochastic.summary.num_parameters - base.stochastic.summary.num_parameters;
      suggestion.delta_bic = trial.stochastic.summary.weighted_rss -
                             base.stochastic.summary.weighted_rss +
                             added_parameters * std::log(num_taus);
    }
    suggestion.parameters = ParametersOf(trial, term);
    suggestion.evidence = Evidence(base, trial, term);
    suggestion.view_errors_after = trial.views.view_errors;
    suggestion.fixes = fixes;
    suggestion.bic_rejects = suggestion.delta_bic > 0;
    suggestion.clears_long_tau = unflags && suggestion.delta_bic < 0;
    // A term that only clears the flag is offered when BIC accepts it; one the aux view does not
    // support, only then.
    if (!suggestion.clears_long_tau && (!improves || !supported)) continue;
    suggestions.push_back(suggestion);
  }
  // Groups (compare.h): fixes a failing view, clears the long-tau flag without fixing one, only
  // lowers the error, rejected by BIC.
  const auto group = [](const Suggestion& suggestion) {
    if (suggestion.bic_rejects) return 3;
    if (!suggestion.fixes.empty()) return 0;
    return suggestion.clears_long_tau ? 1 : 2;
  };
  std::sort(suggestions.begin(), suggestions.end(),
            [&](const Suggestion& lhs, const Suggestion& rhs) {
              if (group(lhs) != group(rhs)) return group(lhs) < group(rhs);
              return lhs.error_after < rhs.error_after;
            });
  std::vector<Suggestion> sinusoids;
  for (const Suggestion& suggestion : suggestions)
    if (suggestion.term == Term::kSinusoid) sinusoids.push_back(suggestion);
  for (auto first = suggestions.begin(); first != suggestions.end();) {
    const auto last = std::find_if(first, suggestions.end(), [&](const Suggestion& suggestion) {
      return group(suggestion) != group(*first);
    });
    const double limit = options.tie_ratio * first->error_after + options.tie_offset;
    const auto lead_end = std::find_if(
        first, last, [&](const Suggestion& suggestion) { return suggestion.error_after > limit; });
    std::stable_sort(first, lead_end, [&](const Suggestion& lhs, const Suggestion& rhs) {
      if (lhs.clears_long_tau != rhs.clears_long_tau) return lhs.clears_long_tau;
      const double lhs_bic = TieBreakBic(lhs, sinusoids), rhs_bic = TieBreakBic(rhs, sinusoids);
      if (lhs_bic != rhs_bic) return lhs_bic < rhs_bic;
      return lhs.term.aux == AuxForm::kAm && rhs.term.aux != AuxForm::kAm;
    });
    first = last;
  }
  // bias_levels approximates any slow effect (a temperature cycle, a warm-up, a Gauss-Markov
  // wander) piece by piece. Another candidate that BIC accepts and that makes the model
  // consistent leads where it reads an aux channel (the residual follows the channel: a recorded
  // cause, which a staircase only imitates) or where its delta_bic is at least as low (both are
  // -2 ln L drops less a penalty, the levels' with the look-elsewhere cost of their searched
  // times); bias_step excepted: it is the one-step case, which the
  // segmentation's BIC has rejected; gauss_markov excepted too where the levels read as two
  // alternating levels: random telegraph switching has the Gauss-Markov spectrum (bias_levels.h),
  // and the levels are what tells it.
  const LevelsReading levels_reading = [&]() {
    const Evaluation* trial = TrialOf(trial_terms, trials, Term::kBiasLevels);
    return trial != nullptr ? LevelsReadingOf(*trial) : LevelsReading{};
  }();
  const bool two_levels = levels_reading.num_levels == 2;
  if (!suggestions.empty() && suggestions.front().term == Term::kBiasLevels) {
    const double levels_bic = suggestions.front().delta_bic;
    const auto other =
        std::find_if(suggestions.begin() + 1, suggestions.end(), [&](const Suggestion& suggestion) {
          return suggestion.term != Term::kBiasStep &&
                 !(two_levels && suggestion.term == Term::kGaussMarkov) &&
                 !suggestion.bic_rejects && suggestion.error_after <= 1.0 &&
                 (!AuxChannelOf(suggestion.term).empty() || suggestion.delta_bic <= levels_bic);
        });
    if (other != suggestions.end()) std::rotate(suggestions.begin(), other, other + 1);
  }
  if (two_levels && !suggestions.empty() && suggestions.front().term == Term::kGaussMarkov) {
    const auto levels =
        std::find_if(suggestions.begin() + 1, suggestions.end(), [](const Suggestion& suggestion) {
          return suggestion.term == Term::kBiasLevels && !suggestion.bic_rejects &&
                 (!suggestion.fixes.empty() || suggestion.clears_long_tau);
        });
    if (levels != suggestions.end()) std::rotate(suggestions.begin(), levels, levels + 1);
  }
  // A Gauss-Markov suggestion says what the levels say: the same spectrum from two alternating
  // levels is random telegraph switching, and the Gauss-Markov reading is then not the only one.
  const bool levels_listed = std::any_of(
      suggestions.begin(), suggestions.end(),
      [](const Suggestion& suggestion) { return suggestion.term == Term::kBiasLevels; });
  for (Suggestion& suggestion : suggestions) {
    if (suggestion.term != Term::kGaussMarkov) continue;
    if (levels_listed) {
      suggestion.evidence +=
          two_levels ? "; but the residual falls into two alternating levels (bias_levels: " +
                           levels_reading.text + "), which a Gaussian process does not"
                     : "; bias_levels also explains the record (" + levels_reading.text + ")";
    } else if (!LevelsShow(base.views.time)) {
      double sigma = 0, correlation_time_s = 0;
      for (const Parameter& parameter : suggestion.parameters) {
        if (parameter.name == "sigma") sigma = parameter.value;
        if (parameter.name == "correlation_time") correlation_time_s = parameter.value;
      }
      suggestion.evidence += Format(
          "; random telegraph switching between two levels %.3g deg/h apart with mean dwell "
          "%.4g s would have the same spectrum, and the levels test finds no levels: this record "
          "cannot tell them apart",
          2 * sigma, 2 * correlation_time_s);
    }
  }
  // A term that reads an aux channel, behind a leader that reads another channel or none, must
  // still be supported once the leader is in the model: a large step or warm-up leaves
  // low-frequency residual that the aux score test, run under a model that lacks it, can attribute
  // to a slow temperature cycle (or any slow channel). If the leader's trial explains the aux
  // failure away, the channel was innocent.
  if (!suggestions.empty()) {
    const std::string leader_channel = AuxChannelOf(suggestions.front().term);
    const Evaluation* leader = TrialOf(trial_terms, trials, suggestions.front().term);
    suggestions.erase(
        std::remove_if(suggestions.begin() + 1, suggestions.end(),
                       [&](const Suggestion& suggestion) {
                         const std::string channel = AuxChannelOf(suggestion.term);
                         // Their own evidence: the flag, the modulation test.
                         if (suggestion.clears_long_tau || IsLine(suggestion.term)) return false;
                         if (channel.empty() || channel == leader_channel || leader == nullptr)
                           return false;
                         return !AuxViewSupports(*leader, suggestion.term);
                       }),
        suggestions.end());
  }
  return suggestions;
}

std::string FormatFailure(const Failure& failure) {
  if (failure.domain == ViewDomain::kAux)
    return std::string(ToString(failure.domain)) + " " + failure.channel;
  const char* unit = failure.domain == ViewDomain::kFrequency ? "Hz" : "s";
  char buf[160];
  std::snprintf(buf, sizeof(buf), "%s %.4g-%.4g %s", ToString(failure.domain), failure.from,
                failure.to, unit);
  return buf;
}

namespace {

// The failures as one phrase, the most severe first, at most `limit` of them.
std::string FailureList(std::vector<Failure> failures, size_t limit = 4) {
  std::stable_sort(failures.begin(), failures.end(), [](const Failure& lhs, const Failure& rhs) {
    return lhs.severity > rhs.severity;
  });
  std::string out;
  for (size_t i = 0; i < failures.size() && i < limit; ++i)
    out += (i ? ", " : "") + FormatFailure(failures[i]);
  if (failures.size() > limit) out += " and " + std::to_string(failures.size() - limit) + " more";
  return out;
}

// The term as the verdict names it: a narrow band with its centre, width and rms; an AM line with
// its frequency, amplitude and modulation.
std::string SuggestionLabel(const Suggestion& suggestion) {
  std::string label = ToString(suggestion.term);
  if (suggestion.term.aux == AuxForm::kAm) {
    const AmLine line = AmLineOf(suggestion.parameters);
    return label +
           Format(" at %.5g Hz (amplitude %.3g deg/h, modulation %.3g ", line.frequency,
                  line.amplitude, line.modulation) +
           line.unit + ")";
  }
  if (suggestion.term == Term::kAngleQuantizer) {
    for (const Parameter& parameter : suggestion.parameters)
      if (parameter.name == "step") return label + Format(" (step %.4g arcsec)", parameter.value);
    return label;
  }
  if (suggestion.term == Term::kBiasLevels && !suggestion.parameters.empty())
    return label + Format(" with %.0f steps", suggestion.parameters.front().value);
  if (suggestion.term != Term::kNarrowBand) return label;
  double frequency = 0, bandwidth = 0, rms = 0;
  for (const Parameter& parameter : suggestion.parameters) {
    if (parameter.name == "frequency") frequency = parameter.value;
    if (parameter.name == "bandwidth") bandwidth = parameter.value;
    if (parameter.name == "rms") rms = parameter.value;
  }
  return label + Format(" at %.4g Hz (half-power width %.3g Hz, rms %.3g deg/h)", frequency,
                        bandwidth, rms);
}

std::string Join(const std::vector<ViewDomain>& domains) {
  std::string joined;
  for (ViewDomain domain : domains)
    joined += (joined.empty() ? "" : ", ") + std::string(ToString(domain));
  return joined;
}

}  // namespace

Verdict MakeVerdict(const Evaluation& base, const std::vector<ModelTerm>& trial_terms,
                    const std::vector<Evaluation>& trials,
                    const std::vector<Suggestion>& suggestions) {
  Verdict verdict;
  if (!HasResult(base.termination) || base.views.consistent) return verdict;
  std::vector<ViewDomain> fixable;
  for (const Suggestion& suggestion : suggestions)
    if (!suggestion.bic_rejects)
      fixable.insert(fixable.end(), suggestion.fixes.begin(), suggestion.fixes.end());
  for (const Failure& failure : base.views.failures)
    if (std::find(fixable.begin(), fixable.end(), failure.domain) == fixable.end())
      verdict.unexplained.push_back(failure);
  // Only a suggestion that BIC accepts and that makes a failing view pass is offered; the ranking
  // puts such a suggestion first whenever there is one.
  if (!suggestions.empty() && !suggestions.front().bic_rejects &&
      !suggestions.front().fixes.empty()) {
    const Suggestion& suggestion = suggestions.front();
    verdict.status = "inconsistent";
    verdict.suggestion = suggestion.term;
    verdict.fixes = suggestion.fixes;
    if (const Evaluation* trial = TrialOf(trial_terms, trials, suggestion.term)) {
      verdict.consistent_with_suggestion = trial->views.consistent;
      verdict.still_failing = trial->views.failures;
    }
    verdict.text = "inconsistent: suggestion " + SuggestionLabel(suggestion);
    if (verdict.consistent_with_suggestion)
      verdict.text += " (makes the model consistent)";
    else
      verdict.text += " (fixes " + Join(verdict.fixes) +
                      "; still failing with it: " + FailureList(verdict.still_failing) + ")";
    if (!verdict.unexplained.empty())
      verdict.text += "; unexplained: " + FailureList(verdict.unexplained);
    return verdict;
  }
  verdict.status = "unexplained";
  verdict.still_failing = base.views.failures;
  verdict.text = "unexplained: no catalog term makes any failing view (" +
                 Join(FailingViews(base.views)) +
                 ") pass; failing: " + FailureList(verdict.still_failing);
  // The first candidate that lowers the error (one that only clears the long-tau flag may rank
  // above it; the warning names that one).
  const auto lowers =
      std::find_if(suggestions.begin(), suggestions.end(),
                   [&](const Suggestion& s) { return s.error_after < base.views.error; });
  if (lowers != suggestions.end()) {
    verdict.text +=
        "; the first candidate, " + SuggestionLabel(*lowers) +
        (lowers->bic_rejects ? " (rejected by BIC)" : "") +
        Format(", only takes the error %.3g -> %.3g", base.views.error, lowers->error_after);
  }
  return verdict;
}

void NameCoarseQuantization(const AngleLattice& lattice, Verdict* verdict) {
  if (!lattice.coarse || verdict->status == "consistent") return;
  if (verdict->suggestion && *verdict->suggestion == Term::kAngleQuantizer) {
    verdict->coarse_angle_quantization = true;  // the suggestion names it
    return;
  }
  if (verdict->consistent_with_suggestion) return;
  const double step_arcsec = lattice.step_rad * units::kArcsecPerRad;
  const std::string prefix = "unexplained: ";
  if (verdict->status == "unexplained" && verdict->text.compare(0, prefix.size(), prefix) == 0) {
    verdict->text = prefix +
                    Format(
                        "coarse angle quantization (an undithered angle counter, step %.4g "
                        "arcsec, whose error is not white; angle_quantizer does not make a "
                        "failing view pass either); ",
                        step_arcsec) +
                    verdict->text.substr(prefix.size());
  } else {
    verdict->text += Format(
        "; the recording is an undithered angle counter (step %.4g arcsec) "
        "whose coarse quantization error is not white, which may be what "
        "still fails",
        step_arcsec);
  }
  verdict->coarse_angle_quantization = true;
}

namespace {

// The terms Compare trials: those of TrialTerms when the base model is not consistent (aux terms
// where the aux view supports them), and when its long-tau check flags, the SlowEffectTrialTerms
// too (also in *slow_terms: their trials run the check).
std::vector<ModelTerm> TrialsToRun(const CompareInput& input, const std::vector<ModelTerm>& terms,
                                   const Evaluation& base, const AngleLattice& lattice,
                                   std::vector<ModelTerm>* slow_terms) {
  std::vector<ModelTerm> trial_terms;
  if (!base.views.consistent) {
    for (const ModelTerm& term : TrialTerms(input, terms)) {
      // aux_am, a line, is trialled where the frequency view fails (its support, the modulation
      // test, is read from its trial).
      const bool trialled = term.aux == AuxForm::kAm
                                ? ViewErrorOf(base.views, ViewDomain::kFrequency) > 1.0
                                : !term.IsAux() || AuxViewSupports(base, term);
      if (trialled) trial_terms.push_back(term);
    }
  }
  if (base.long_tau.flagged) *slow_terms = SlowEffectTrialTerms(input, terms);
  for (const ModelTerm& term : *slow_terms)
    if (std::find(trial_terms.begin(), trial_terms.end(), term) == trial_terms.end())
      trial_terms.push_back(term);
  // A narrow band is fitted at a failing frequency band (FitBands): without one its trial would
  // be the base model again.
  if (ViewErrorOf(base.views, ViewDomain::kFrequency) <= 1.0)
    trial_terms.erase(std::remove(trial_terms.begin(), trial_terms.end(), Term::kNarrowBand),
                      trial_terms.end());
  // angle_quantizer only for a coarse counter: a white error is the Q term's (angle_lattice.h).
  if (!lattice.coarse)
    trial_terms.erase(std::remove(trial_terms.begin(), trial_terms.end(), Term::kAngleQuantizer),
                      trial_terms.end());
  return trial_terms;
}

}  // namespace

CompareResult Compare(const CompareInput& input, const std::vector<ModelTerm>& terms,
                      const CompareOptions& options, const ForEach& for_each) {
  CompareResult result;
  if (input.rate_rad_s == nullptr) {
    result.summary.termination = Termination::kInvalidOptions;
    result.summary.message = "no rate";
    return result;
  }
  const std::vector<PreparedAux> prepared =
      PrepareAux(input.aux, input.rate_rad_s->size(), input.sample_rate_hz, options.views);
  result.base = EvaluateModel(input, terms, options, &prepared);
  result.summary.termination = result.base.termination;
  result.summary.message = result.base.message;
  if (!HasResult(result.base.termination)) return result;
  // With angle_quantizer in the model EvaluateModel has tested this rate with these options
  // already, and its fit holds the lattice.
  const bool has_quantizer =
      std::find(terms.begin(), terms.end(), ModelTerm(Term::kAngleQuantizer)) != terms.end();
  result.angle_lattice = has_quantizer ? result.base.angle_quantizer.lattice
                                       : DetectAngleLattice(*input.rate_rad_s, input.sample_rate_hz,
                                                            options.angle_lattice);
  // Tasks: the trials, those with a nonlinear search (the longest) first so that a parallel
  // ForEach finishes together, then the base model's IMF view (one EMD per compare). Each task
  // writes only its own slot.
  const bool flagged = result.base.long_tau.flagged;
  std::vector<ModelTerm> slow_terms;
  const std::vector<ModelTerm> trial_terms =
      TrialsToRun(input, terms, result.base, result.angle_lattice, &slow_terms);
  result.trials.resize(trial_terms.size());
  std::vector<int> order(trial_terms.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_partition(order.begin(), order.end(), [&](int i) {
    return HasNonlinearParameter(trial_terms[i]) || trial_terms[i] == Term::kNarrowBand ||
           trial_terms[i] == Term::kAngleQuantizer;
  });
  const int count = 1 + static_cast<int>(trial_terms.size());
  // The trials' own step and warm-up scans would never be read (RankSuggestions and the verdict
  // use the base model's), so they are skipped: a FitDeterministic scan and a noise refit each per
  // trial. So is their long-tau check (a pass per tested tau), but on the slow-effect trials of a
  // flagged base model, where it is what RankSuggestions reads.
  CompareOptions trial_options = options;
  trial_options.views.targeted_scans = false;
  trial_options.long_tau.enabled = false;
  CompareOptions slow_trial_options = trial_options;
  slow_trial_options.long_tau.enabled = options.long_tau.enabled;
  CompareInput drawn_input = input;
  drawn_input.rate_rad_s =
      result.base.angle_quantizer.ok ? &result.base.angle_quantizer_rate_rad_s : nullptr;
  const auto task = [&](int task_index) {
    if (task_index == count - 1) {
      result.base.imf = ComputeImfView(result.base.deterministic.residual, input.sample_rate_hz,
                                       prepared, result.base.stochastic.model, options.imf);
      return;
    }
    const int i = order[task_index];
    std::vector<ModelTerm> with_term = terms;
    with_term.push_back(trial_terms[i]);
    const bool slow =
        std::find(slow_terms.begin(), slow_terms.end(), trial_terms[i]) != slow_terms.end();
    const CompareOptions& trial_options_i = slow ? slow_trial_options : trial_options;
    if (drawn_input.rate_rad_s == nullptr) {
      result.trials[i] = EvaluateModel(input, with_term, trial_options_i, &prepared);
      return;
    }
    // angle_quantizer in the model: every trial fits the base model's draw (one draw per compare,
    // and the trials differ from the base by their term only), and carries its fit.
    std::vector<ModelTerm> on_draw;
    for (const ModelTerm& term : with_term)
      if (term != Term::kAngleQuantizer) on_draw.push_back(term);
    result.trials[i] = EvaluateModel(drawn_input, on_draw, trial_options_i, &prepared);
    result.trials[i].terms = with_term;
    result.trials[i].angle_quantizer = result.base.angle_quantizer;
  };
  if (for_each) {
    for_each(count, task);
  } else {
    for (int task_index = 0; task_index < count; ++task_index) task(task_index);
  }
  if (!result.base.views.consistent || flagged) {
    result.summary.num_trials = static_cast<int>(trial_terms.size());
    result.suggestions = RankSuggestions(result.base, trial_terms, result.trials, options);
    result.verdict = MakeVerdict(result.base, trial_terms, result.trials, result.suggestions);
    // With angle_quantizer in the model the counter is accounted for; what fails is not it.
    if (!has_quantizer) NameCoarseQuantization(result.angle_lattice, &result.verdict);
    // A bias_levels trial that fitted nothing because its segmentation outgrew the dense fit
    // (bias_levels.h, max_design_bytes) is said, not passed over.
    const Evaluation* levels_trial = TrialOf(trial_terms, result.trials, Term::kBiasLevels);
    const DeterministicComponent* levels =
        levels_trial != nullptr ? LastComponent(*levels_trial, Term::kBiasLevels) : nullptr;
    if (levels != nullptr && levels->levels_too_many_steps > 0) {
      result.verdict.text += Format(
          "; bias_levels not fitted: its segmentation finds %.0f steps, more than the %.0f a dense "
          "fit of this record holds",
          static_cast<double>(levels->levels_too_many_steps),
          static_cast<double>(levels->levels_max_design_steps));
    }
  }
  // Whatever the views say: a consistent model whose K absorbs a step is the case this warns of.
  if (flagged) {
    result.verdict.absorbing_slow_effect = true;
    result.verdict.text += "; warning: " + result.base.long_tau.message;
    const auto clears = std::find_if(result.suggestions.begin(), result.suggestions.end(),
                                     [](const Suggestion& s) { return s.clears_long_tau; });
    if (clears != result.suggestions.end())
      result.verdict.text += "; adding " + ToString(clears->term) + " clears it";
  }
  return result;
}

}  // namespace fogpipe::model
