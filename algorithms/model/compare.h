// Model against measurement (`fogpipe compare`): fit a gyro model, compare it with the recording
// in five views, report one dimensionless error, the failures, and a ranked list of the catalog
// terms that would fix the misfit.
//
//   EvaluateModel: deterministic least squares (deterministic_fit.h) -> Allan variance of the
//   residual -> stochastic NNLS fit (stochastic_fit.h) -> views, error, failures (views.h).
//   TrialTerms / RankSuggestions: every catalog term not in the model is added in turn and the
//   model re-evaluated. Compare() runs the trials and the base model's IMF view through a ForEach
//   (serial by default; the pipeline passes a oneTBB loop); each writes only its own slot, so the
//   numbers do not depend on the thread count.
//
// Aux terms (catalog.h) are trialled for every aux channel the aux view flags, and gated like the
// thermal terms (below): aux:<x> needs the residual to follow x, aux_rate:<x> its derivative. The
// polynomial's order is part of its fit (deterministic_fit.h), so its trial costs one evaluation.
// aux_am:<x> (a line whose amplitude follows x) is the exception: a line's modulation leaves no
// low-frequency trace for the aux view to score, so it is trialled for every channel whenever the
// frequency view fails, and supported by its own modulation test in its trial (the Wald
// chi-square of the amplitude's change with x, 2 degrees of freedom, at the aux view's per-test
// level; compare.cpp). A sinusoid fitted to such a line leaves its sidebands, which a second
// sinusoid would then take one at a time; aux_am explains the carrier and the sidebands together.
//
// Angle counters. Compare tests the recorded rate for an angle counter (angle_lattice.h,
// CompareResult::angle_lattice). angle_quantizer is trialled only when the counter is coarse (an
// undithered counter whose error is not white); its trial, like every evaluation with the term,
// replaces the counter's error in the rate by a draw of the angle within its steps before every
// fit and view (angle_quantizer.h). Its delta_bic is the counter's own evidence, the critical
// value minus the portmanteau of the increments beyond lag 1 (negative whenever it is trialled).
// Where the counter is coarse and no suggestion makes the model consistent, the verdict names it
// (NameCoarseQuantization).
//
// Slow effects. When the base model's long-tau check flags (B, K or R absorbing a slow effect,
// long_tau_check.h), the views may all pass: a thermal hysteresis, a square wave at the thermal
// period, is absorbed by the fitted B and K. Compare then also trials every term that could
// explain a slow effect (SlowEffectTrialTerms: bias_step, bias_levels, warmup, the thermal terms
// and, per aux channel, aux, aux_rate and aux_hysteresis, whatever the aux view says) and runs the
// long-tau check on those trials only (it costs a pass per tested tau). A trial `clears_long_tau`
// when its check is evaluated and does not flag, or finds B, K and R too small at every tau to
// absorb anything (LongTauCheck::nothing_to_absorb), and BIC accepts its term (delta_bic < 0,
// below); such a term is a candidate even when the views pass or the aux view does not support it.
// Without a flag nothing of this runs: the trials, their order and the ranking are those described
// below.
//
// Ranking. A trial is a candidate when the model is not consistent and the trial lowers the error
// by at least 10 % (`min_improvement`) or makes a failing view pass (`fixes`: a view with error
// above 1 in the base model and at most 1 in the trial; Views::view_errors). The error is the
// largest view error, so a correct term that fixes one view while another view dominates would
// otherwise be neither suggested nor credited. Terms that read an aux channel (thermal and aux
// terms) must in addition be supported by the aux view (|z| of the residual against the channel,
// resp. its derivative, above the aux view's critical value): such an explanation is only offered
// when the residual actually follows the channel, and, behind a first suggestion that reads
// another channel or none, only if it still does once that suggestion is in the model (its
// trial's aux view): a large step or warm-up otherwise leaks into the aux score. temperature and
// aux:temperature are nested (catalog.h): only the one whose order the polynomial fit's BIC
// chooses is listed (temperature for order 1).
// Candidates are ranked in groups: those that make a failing view pass, then those that clear the
// long-tau flag without fixing a view (the views already pass, or the trial fixes none), then
// those that only lower the error, then those whose delta_bic is positive (`bic_rejects`: BIC
// prefers the model without the term, so it is never ranked first, whatever it does to the error).
// Within a group they are sorted by error_after; those within 15 % (+0.05) of the group's best
// error_after are statistically indistinguishable on the error, and are ordered among themselves by
// delta_bic (the simpler explanation first, Schwarz 1978), those that clear the long-tau flag
// first; a supported aux_am against the sinusoid at its frequency (its nested model, whose
// comparison with it is the modulation test) takes the lower of their delta_bic and goes first on
// a tie.
// Several bias levels (bias_levels, bias_levels.h) are a candidate with at least two steps, where
// the base model's levels test shows levels or the trial clears the long-tau flag. Constant
// levels approximate any slow effect piece by piece, so bias_levels never leads while another
// candidate BIC accepts makes the model consistent and reads an aux channel or has a delta_bic
// at least as low, but bias_step
// (its one-step case, which the segmentation's BIC rejected) and gauss_markov where the levels read
// as two alternating levels: random telegraph switching has the Gauss-Markov spectrum, and the
// levels are what tells it; the levels then go ahead of a leading gauss_markov, whose evidence says
// what the levels say. The first suggestion is the one to add.
//
// Verdict. "consistent" when the base model is; "inconsistent" with the first suggestion when it
// makes a failing view pass (and, if the model with it still fails somewhere, the ranges that still
// fail with it); "unexplained" when no candidate that BIC accepts makes any failing view pass: the
// failing tau ranges, frequency bands, time windows and aux channels are reported as they are.
// With either status, the failures of views that no accepted candidate makes pass are listed as
// unexplained (a suggestion may fix the Allan view while an aux channel no term uses still
// fails). The verdict never says a term makes the model consistent unless its trial is consistent
// in every view.
//
// delta_bic. Rate-fitted terms: (n / lambda) ln(RSS_after / RSS_before) + dk ln(n / lambda), the
// Gaussian BIC with the sample count deflated by the long-run variance ratio lambda of the
// residual (coloured noise carries fewer independent samples than n). Allan-fitted terms:
// chi2_after - chi2_before + dk ln(J) with chi2 the weighted NNLS cost over J taus.
// bias_step and warmup, whose nonlinear parameter (step time, time constant) is found by a scan:
// c^2 - z^2, z the GLS t-statistic of the term under the noise refitted without it (the base
// model's time-view scan, targeted_tests.h) and c its family-wise critical value: -2 ln L with
// the look-elsewhere cost of the scan (c^2 ~ 2 ln of the number of effectively distinct
// alternatives; Davies 1987, Siegmund 1988) in place of ln n. An early step and a warm-up explain
// the start of a record about equally well; the step scan searches many more distinct
// alternatives than the smooth warm-up family, and pays for it here. bias_levels: penalty - (-2
// ln L drop) of its segmentation's modified BIC (bias_levels.h), for the same reason (its step
// times are searched): the base model's levels test's where it shows levels, else the fit's.
// aux_am: -W + dk ln(n / lambda), W the Wald chi-square of its four amplitudes under their
// batch-means sandwich covariance (deterministic_fit.h), which measures the residual's power near
// the line. The RSS form takes the residual as white at its total variance, which at 10 Hz the
// angle quantization's blue noise rules (2-4x the white noise's per sample, far less near a line
// below ~1 Hz): it priced the modulation's sidebands at a fraction of their evidence, and ranked
// the sinusoid first on 14 of 20 design records that the modulation test supports. (The sinusoid
// keeps the RSS form: its numbers and the tests on them are unchanged; the same argument applies
// to it.)
#pragma once

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/allan/noise_fit.h"
#include "algorithms/common/for_each.h"
#include "algorithms/common/status.h"
#include "algorithms/model/angle_lattice.h"
#include "algorithms/model/angle_quantizer.h"
#include "algorithms/model/catalog.h"
#include "algorithms/model/deterministic_fit.h"
#include "algorithms/model/imf_view.h"
#include "algorithms/model/long_tau_check.h"
#include "algorithms/model/stochastic_fit.h"
#include "algorithms/model/views.h"

namespace fogpipe::model {

/// One recording axis and its aux channels (non-owning view of the rate).
struct CompareInput {
  const Eigen::VectorXd* rate_rad_s = nullptr;
  double sample_rate_hz = 0;
  std::vector<AuxChannel> aux;  ///< "temperature" (degC) feeds the thermal terms; every channel
                                ///< its aux terms (catalog.h)
  std::optional<double> latitude_deg;  ///< root attribute latitude_deg, for the Earth-rate bias
};

struct CompareOptions {
  DeterministicOptions deterministic;
  StochasticFitOptions stochastic;
  ViewOptions views;
  ImfViewOptions imf;  ///< the IMF view (base model only; diagnostic, not part of the error)
  LongTauCheckOptions long_tau;       ///< the long-tau terms' check (diagnostic, not in the error)
  AngleLatticeOptions angle_lattice;  ///< the angle-counter test of the rate (angle_lattice.h)
  AngleQuantizerOptions angle_quantizer;  ///< the angle_quantizer term's draw (angle_quantizer.h)
  double min_improvement = 0.9;           ///< a suggestion must bring error_after <= this * error
  double tie_ratio = 1.15;                ///< error_after within tie_ratio * best + tie_offset ...
  double tie_offset = 0.05;               ///< ... are ranked by delta_bic
  bool IsValid(std::string* error) const;
};

/// A parameter as reported: value and standard error in engineer's units.
struct Parameter {
  std::string name;
  double value = 0;
  double standard_error = 0;
  std::string units;
  /// A 95 % interval [low, high] where the error is not symmetric (the Gauss-Markov correlation
  /// time's profile interval, stochastic_fit.h); NaN where value +- 1.96 SE serves.
  double low = std::numeric_limits<double>::quiet_NaN();
  double high = std::numeric_limits<double>::quiet_NaN();
};

struct FittedTerm {
  std::string term;  ///< catalog name, or "bias"
  std::vector<Parameter> parameters;
};

/// One evaluated model.
struct Evaluation {
  std::vector<ModelTerm> terms;
  DeterministicFit deterministic;
  StochasticFit stochastic;
  AllanData allan;
  Views views;
  ImfView imf;  ///< filled for the base model by Compare() (not for trials: one EMD per compare)
  std::vector<FittedTerm> fitted;  ///< bias first, then each term with its parameters
  /// The IEEE terms of `stochastic` (Q, N, B, K, R; NaN where not in the model) under the
  /// five-term fit's reliability checks on the residual's Allan table, with that table's slope
  /// read-offs (allan::AssessNoiseTerms; the Gauss-Markov term counts as part of the model).
  allan::NoiseFitResult noise_check;
  /// Do the long-tau data behave as the fitted B, K and R say, or do they absorb a slow effect
  /// (long_tau_check.h)? A diagnostic: not part of `views.error`.
  LongTauCheck long_tau;
  /// With angle_quantizer in the model: the counter and the draw that replaced its error in the
  /// rate before every fit and view (angle_quantizer.h).
  AngleQuantizerFit angle_quantizer;
  /// ... and the rate with the draw, which the model was fitted to (empty without the term;
  /// Compare's trials of a model with the term fit the base model's).
  Eigen::VectorXd angle_quantizer_rate_rad_s;
  Termination termination = Termination::kSuccess;
  std::string message;
};

struct Suggestion {
  ModelTerm term = Term::kWhite;
  double error_after = 0;
  double delta_bic = 0;
  std::vector<Parameter> parameters;
  std::string evidence;
  std::vector<ViewError> view_errors_after;  ///< the trial's per-view errors
  std::vector<ViewDomain> fixes;  ///< views that fail in the base model and pass in the trial
  bool bic_rejects = false;       ///< delta_bic > 0: never ranked first
  /// The base model's long-tau check flags, the trial's runs and does not, and BIC accepts the
  /// term (delta_bic < 0): the term explains the slow effect that B, K or R absorbed.
  bool clears_long_tau = false;
};

/// What compare concludes (see the header comment).
struct Verdict {
  std::string status = "consistent";        ///< "consistent" | "inconsistent" | "unexplained"
  std::optional<ModelTerm> suggestion;      ///< "inconsistent": the term to add
  std::vector<ViewDomain> fixes;            ///< the views the suggestion makes pass
  bool consistent_with_suggestion = false;  ///< the suggestion's trial passes every view
  /// "inconsistent": the failures left with the suggestion in the model (empty when it makes the
  /// model consistent); "unexplained": the base model's failures.
  std::vector<Failure> still_failing;
  /// The base model's failures in the failing views that no candidate BIC accepts makes pass:
  /// what the catalog cannot explain (all failures when the status is "unexplained").
  std::vector<Failure> unexplained;
  /// The base model's long-tau check flags B, K or R as absorbing a slow effect (Evaluation::
  /// long_tau); `text` then ends with "; warning: " and its finding, whatever the status, and
  /// with "; adding TERM clears it" when a suggestion clears_long_tau (the first such).
  bool absorbing_slow_effect = false;
  /// The rate is a coarse angle counter (CompareResult::angle_lattice) and the verdict names it as
  /// the likely cause of what no suggestion makes consistent (NameCoarseQuantization).
  bool coarse_angle_quantization = false;
  std::string text = "consistent";  ///< one line, e.g. "unexplained: ... failing: frequency ..."
};

struct CompareSummary {
  Termination termination = Termination::kSuccess;
  std::string message;
  int num_trials = 0;
};

struct CompareResult {
  Evaluation base;
  AngleLattice angle_lattice;      ///< is the recorded rate an angle counter, and is it coarse?
  std::vector<Evaluation> trials;  ///< one per TrialTerms() entry
  std::vector<Suggestion> suggestions;
  Verdict verdict;
  CompareSummary summary;
};

/// Fits `terms` (bias implicit) and computes the views. `prepared` (from PrepareAux on the
/// input's aux channels) may be shared between evaluations of one input; null: prepared here.
Evaluation EvaluateModel(const CompareInput& input, const std::vector<ModelTerm>& terms,
                         const CompareOptions& options,
                         const std::vector<PreparedAux>* prepared = nullptr);

/// The terms to trial-fit: every catalog term not in `terms` (sinusoid always: there may be
/// several), thermal terms only with an aux "temperature"; then, per aux channel of the rate's
/// length, aux:<channel>, aux_rate:<channel> and aux_am:<channel> unless in `terms` (not
/// aux_rate:temperature, which is temperature_rate, nor aux:temperature beside temperature, whose
/// linear part it repeats).
std::vector<ModelTerm> TrialTerms(const CompareInput& input, const std::vector<ModelTerm>& terms);

/// The trial terms that could explain a slow effect absorbed by B, K or R (see the header
/// comment): those of TrialTerms that are bias_step, warmup, a thermal or an aux term, then
/// aux_hysteresis:<channel> per aux channel of the rate's length unless in `terms`.
std::vector<ModelTerm> SlowEffectTrialTerms(const CompareInput& input,
                                            const std::vector<ModelTerm>& terms);

/// True when the base model's aux view supports a term that reads an aux channel: |z| of the
/// residual against the channel (its derivative for temperature_rate and aux_rate) above the aux
/// view's critical value. Terms that read no channel: always true. aux_am: `evaluation` is a model
/// with the term, and its modulation test passes (see the header comment).
bool AuxViewSupports(const Evaluation& evaluation, const ModelTerm& term);

/// Builds the ranked suggestions from the base evaluation and the trials (trial i adds
/// TrialTerms()[i]).
std::vector<Suggestion> RankSuggestions(const Evaluation& base,
                                        const std::vector<ModelTerm>& trial_terms,
                                        const std::vector<Evaluation>& trials,
                                        const CompareOptions& options);

/// The verdict from the base evaluation, the trials and the ranked suggestions.
Verdict MakeVerdict(const Evaluation& base, const std::vector<ModelTerm>& trial_terms,
                    const std::vector<Evaluation>& trials,
                    const std::vector<Suggestion>& suggestions);

/// Names a coarse angle counter (lattice.coarse) in a verdict that is not consistent and that no
/// suggestion makes consistent: its quantization error is not white, and the comb of idle tones
/// it leaves is outside the catalog (angle_lattice.h). "unexplained" gets it as the cause ahead of
/// the failures; "inconsistent" (the suggestion fixes some views only) gets it as what may remain.
/// Sets verdict->coarse_angle_quantization when it names it; otherwise leaves the verdict as is.
void NameCoarseQuantization(const AngleLattice& lattice, Verdict* verdict);

/// One failure as text: "tau 0.1-2 s", "frequency 17.9-24.6 Hz", "time 0-156 s", "aux temperature".
std::string FormatFailure(const Failure& failure);

/// Runs body(i) for i in [0, n); bodies are independent (each writes only its own slot). The
/// same type as method::ForEach (algorithms/common/for_each.h), so graph::TbbForEach fits.
using fogpipe::ForEach;

/// EvaluateModel of the base model, then (through for_each, null: in order) the base model's IMF
/// view and every trial, then RankSuggestions. Trials are run only when the base model is not
/// consistent, and aux terms only where AuxViewSupports them (RankSuggestions would drop the
/// others unread; aux_am where the frequency view fails); when the base model's long-tau check
/// flags, also the SlowEffectTrialTerms, with their long-tau check.
CompareResult Compare(const CompareInput& input, const std::vector<ModelTerm>& terms,
                      const CompareOptions& options, const ForEach& for_each = nullptr);

/// The parameters of `term` in an evaluation (the last sinusoid for kSinusoid), engineer's units.
/// aux:<x>: "order" (chosen by BIC), "coefficient", "coefficient_2", ... in deg/h per unit^k of x,
/// and "reference" (x_ref, the unit of x); aux_rate:<x>: "coefficient" in deg/h/(unit/s);
/// aux_hysteresis:<x>: "coefficient" in deg/h (the bias while x rises; minus it while x falls) and
/// "dead_band" (the switch's half-width w, unit/s); aux_am:<x>: "frequency" (Hz), "amplitude"
/// (a0, deg/h) and "phase" (rad) of the line at x = x_ref, as the sinusoid's, "modulation" (a1,
/// deg/h per unit of x: the amplitude's change in phase with the line), "modulation_quadrature"
/// (deg/h per unit: the part 90 degrees from it, 0 for a pure amplitude modulation) and
/// "reference" (x_ref, the unit of x).
std::vector<Parameter> ParametersOf(const Evaluation& e, const ModelTerm& term);

}  // namespace fogpipe::model
