// fogpipe compare: the model loop (fit a gyro model, compare it with a recording, add the missing
// effect the comparison suggests, repeat).
//
//   fogpipe compare RECORDING [--model FILE | --terms a,b,c] [--add TERM ...] [--axis A|all]
//   (TERM: a catalog name, aux:<channel>, aux_rate:<channel>, aux_hysteresis:<channel> or
//   aux_am:<channel>; algorithms/model/catalog.h)
//                   [--json] [-o RESULTS] [--save-model FILE] [--progress]
//   fogpipe compare --history RESULTS
//
// Fits the model (algorithms/model/compare.h), prints the error, the failures and the ranked
// suggestions and the verdict (or, with --json, one JSON object with exactly error, consistent,
// view_errors, verdict, failures, suggestions, model; with --axis all, {"file", "axes": [those
// objects, each with its "axis"]}), appends the step to RESULTS (one per axis) and optionally
// writes the model file that `compare --model` and `run --model` read. The trial fits and the IMF
// view run in parallel (model::Compare with graph::TbbForEach); the numbers do not depend on the
// thread count.
//
// Exit codes: 0 compared (consistent or not) or history printed; 1 a read/fit/write failed;
// 2 invalid options.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "algorithms/common/units.h"
#include "algorithms/model/compare.h"
#include "pipeline/cli/commands.h"
#include "pipeline/graph/progress.h"
#include "pipeline/graph/tbb_for_each.h"
#include "pipeline/io/isolated_reader.h"
#include "pipeline/io/model_history.h"
#include "pipeline/io/noise_fit_report.h"
#include "pipeline/io/recording_reader.h"

namespace fogpipe::cli {
namespace {

struct CompareArguments {
  std::string recording;
  std::string model_file;
  std::string terms;
  std::vector<std::string> add;
  std::string axis = "0";
  bool json = false;
  std::string results;
  std::string save_model;
  std::string history;
  bool progress = false;
};

// " (95 % interval LOW .. HIGH UNITS)" for a parameter whose error is not symmetric, else "".
std::string IntervalText(const model::Parameter& p) {
  if (!std::isfinite(p.low) || !std::isfinite(p.high)) return "";
  char text[96];
  std::snprintf(text, sizeof(text), " (95 %% interval %.3g .. %.3g %s)", p.low, p.high,
                p.units.c_str());
  return text;
}

// The IMF view (diagnostic, not part of the error): one line per IMF, '*' where it carries misfit.
void PrintImfView(const model::ImfView& v) {
  if (!HasResult(v.summary.termination)) {
    std::printf("IMF view: %s\n", v.summary.message.c_str());
    return;
  }
  std::printf(
      "IMF view (residual decimated %ldx to %.4g Hz; energy against the fitted noise "
      "model; flagged: z > %.3g): %s\n",
      v.decimation, v.sample_rate_hz, v.critical, v.summary.message.c_str());
  std::printf("  %-4s %-11s %-15s %-7s %-9s", "imf", "period [s]", "energy/expected", "z",
              "AR fit %");
  for (const auto& name : v.aux_names) std::printf(" r(%s) r(d/dt)", name.c_str());
  std::printf("\n");
  for (size_t k = 0; k < v.energy.size(); ++k) {
    std::printf("%s %-4zu %-11.4g %-15.3g %-7.3g %-9.4g", v.flagged[k] ? " *" : "  ", k + 1,
                v.mean_period_s[k], v.ratio[k], v.z[k], v.ar_fit_percent[k]);
    for (size_t c = 0; c < v.aux_names.size(); ++c)
      std::printf(" %*.2f %7.2f", static_cast<int>(v.aux_names[c].size()) + 3, v.aux_r[c][k],
                  v.aux_r_derivative[c][k]);
    std::printf("\n");
  }
}

// The long-tau terms' check (diagnostic, not part of the error), one line per tested tau.
void PrintLongTauCheck(const model::LongTauCheck& c) {
  std::printf("long-tau check (do B, K and R fit the block means' increments?): %s\n",
              c.message.c_str());
  if (c.points.empty()) return;
  std::printf("  %-10s %-7s %-18s %-6s %-16s %-16s %-20s\n", "tau [s]", "blocks", "dominant",
              "share", "kurtosis z/crit", "Ljung-Box/crit", "low-freq ratio [band]");
  for (const auto& p : c.points)
    std::printf("%s %-10.4g %-7d %-18s %-6.2f %6.3g / %-7.3g %6.3g / %-7.3g %.3g [%.3g, %.3g]\n",
                p.flagged ? " *" : "  ", p.tau_s, p.blocks, p.dominant_term.c_str(), p.share,
                p.kurtosis_z, p.kurtosis_critical, p.portmanteau, p.portmanteau_critical,
                p.low_frequency, p.low_frequency_low, p.low_frequency_high);
}

void PrintText(const model::CompareResult& r) {
  const auto& v = r.base.views;
  std::printf("error %.3g (%s; 1 = the family-wise 95 %% band)\n", v.error,
              v.consistent ? "consistent" : "NOT consistent");
  std::printf("  per view:");
  for (const auto& e : v.view_errors)
    std::printf(" %s %.3g%s", model::ToString(e.domain), e.error, e.error > 1 ? " (fails)" : "");
  std::printf("\n");
  for (const auto& f : v.failures) {
    if (f.domain == model::ViewDomain::kAux)
      std::printf("  fails in aux: channel %s, severity %.3g\n", f.channel.c_str(), f.severity);
    else if (f.domain == model::ViewDomain::kFrequency)
      std::printf(
          "  fails in frequency: band %.4g .. %.4g Hz (centre %.4g, peak %.4g Hz at %.3gx the "
          "model psd, %d failing bins), excess power %.3g (deg/h)^2, severity %.3g\n",
          f.from, f.to, f.center_hz, f.peak_hz, f.peak_ratio, f.failing_bins,
          f.excess_power * std::pow(units::RadPerSecondToDegPerHour(1.0), 2), f.severity);
    else
      std::printf("  fails in %s: %.4g .. %.4g %s, severity %.3g\n", model::ToString(f.domain),
                  f.from, f.to, f.domain == model::ViewDomain::kFrequency ? "Hz" : "s", f.severity);
  }
  std::printf("verdict: %s\n", r.verdict.text.c_str());
  for (size_t i = 0; i < r.suggestions.size(); ++i) {
    const auto& s = r.suggestions[i];
    std::string fixes;
    for (model::ViewDomain domain : s.fixes)
      fixes += (fixes.empty() ? "" : ", ") + std::string(model::ToString(domain));
    const bool add = i == 0 && r.verdict.suggestion && *r.verdict.suggestion == s.term;
    std::printf("%s %s: error after %.3g, delta BIC %.3g%s%s%s%s\n  %s\n", add ? "ADD" : "   ",
                model::ToString(s.term).c_str(), s.error_after, s.delta_bic,
                s.bic_rejects ? " (BIC rejects it)" : "", fixes.empty() ? "" : ", fixes ",
                fixes.c_str(), s.clears_long_tau ? ", clears the long-tau flag" : "",
                s.evidence.c_str());
    for (const auto& p : s.parameters)
      std::printf("    %s = %.5g +- %.2g %s%s\n", p.name.c_str(), p.value, p.standard_error,
                  p.units.c_str(), IntervalText(p).c_str());
  }
  PrintImfView(r.base.imf);
  PrintLongTauCheck(r.base.long_tau);
  std::printf("angle lattice (is the rate an angle counter, and is its error white?): %s\n",
              r.angle_lattice.message.c_str());
  std::printf("model:\n");
  for (const auto& ft : r.base.fitted)
    for (const auto& p : ft.parameters)
      std::printf("  %-18s %-24s %.5g +- %.2g %s%s\n", ft.term.c_str(), p.name.c_str(), p.value,
                  p.standard_error, p.units.c_str(), IntervalText(p).c_str());
  // The same reliability checks and read-offs as `allan`, `run`, `info` and `merge` show
  // (allan::AssessNoiseTerms), on the curve these terms were fitted to.
  std::cout << "\nThe IEEE terms above against the residual's Allan curve (the checks and slope "
               "read-offs of `fogpipe allan`):";
  io::PrintNoiseFitText(std::cout, r.base.noise_check);
  std::cout << std::flush;
  std::printf(
      "note: these stochastic terms are fitted jointly with the deterministic part above, on the\n"
      "  Allan variance of its residual, with the extra terms chosen here (e.g. Gauss-Markov) and "
      "a\n"
      "  model-shape tolerance; `fogpipe allan`, `run`, `info` and `merge` report the five IEEE\n"
      "  terms alone fitted to the whole record (generalised least squares). Both are judged by\n"
      "  the same reliability checks. The two differ wherever the deterministic part or the extra\n"
      "  terms carry Allan variance.\n");
}

int PrintHistory(const std::string& results) {
  std::cout << io::FormatHistory(io::ReadHistory(results)) << std::flush;
  return 0;
}

// The model's terms: the model file's, --terms or the default ones, then each --add. False (a
// usage error, stderr says which) for an unknown term.
bool ChooseTerms(const CompareArguments& a, std::vector<model::ModelTerm>* terms) {
  if (!a.model_file.empty()) {
    *terms = io::ReadModelFile(a.model_file).terms;
  } else if (!a.terms.empty()) {
    std::string err;
    if (!model::ParseTermList(a.terms, terms, &err)) {
      std::cerr << "fogpipe compare: --terms: " << err << "\n";
      return false;
    }
  } else {
    *terms = model::DefaultTerms();
  }
  for (const auto& name : a.add) {
    std::string err;
    if (!model::ParseTermList(name, terms, &err)) {
      std::cerr << "fogpipe compare: --add: " << err << "\n";
      return false;
    }
  }
  return true;
}

// Every aux channel of the recording, read once for all axes. A constant channel is read as it
// is: only a constant rate column has no noise to analyse (ReadOptions::reject_constant).
std::vector<model::AuxChannel> ReadAuxChannels(const io::RecordingInfo& info,
                                               const io::ReadOptions& ro) {
  std::vector<model::AuxChannel> aux;
  for (const auto& ch : info.aux) {
    io::ReadOptions ao = ro;
    ao.reject_constant = false;
    aux.push_back({ch.name, ch.units, io::ReadAuxIsolated(info, ch.name, ao)});
  }
  return aux;
}

// One axis's comparison printed (or, with --axis all and --json, kept in *all for the one JSON
// object), appended to RESULTS and saved as a model file, as asked.
void ReportAxis(const CompareArguments& a, const std::string& name, bool several, bool first,
                const model::CompareResult& r, nlohmann::json* all) {
  if (a.json && several) {
    nlohmann::json j = io::CompareJson(r);
    j["axis"] = name;
    all->push_back(std::move(j));
  } else if (a.json) {
    std::cout << io::CompareJson(r).dump(2) << "\n";
  } else {
    if (several) std::printf("%saxis %s\n", first ? "" : "\n", name.c_str());
    PrintText(r);
  }
  // Each axis is a step of its own, named by the axis's name (never an index or "all").
  if (!a.results.empty()) io::AppendHistory(a.results, a.recording, name, r);
  if (!a.save_model.empty()) io::WriteModelFile(a.save_model, r.base);
}

int Run(const CompareArguments& a) {
  if (!a.history.empty()) return PrintHistory(a.history);
  if (a.recording.empty()) {
    std::cerr << "fogpipe compare: RECORDING is required (or --history RESULTS)\n";
    return 2;
  }
  std::vector<model::ModelTerm> terms;
  if (!ChooseTerms(a, &terms)) return 2;
  const io::RecordingInfo info = io::InspectRecordingIsolated(a.recording);
  const std::vector<int> axes = io::SelectAxes(info, a.axis);
  const bool several = a.axis == io::kAllAxes;
  if (several && !a.save_model.empty()) {
    std::cerr << "fogpipe compare: --save-model writes one axis's model; give --axis NAME\n";
    return 2;
  }
  const io::ReadOptions ro;
  const std::vector<model::AuxChannel> aux = ReadAuxChannels(info, ro);
  bool redraw = false;
  std::FILE* progress_stream = graph::ProgressStream(a.progress, &redraw);
  graph::WorkProgress progress("compare " + a.recording, progress_stream, redraw);
  nlohmann::json all = nlohmann::json::array();
  for (const int axis : axes) {
    const std::string& name = info.axis_names[axis];
    progress.Step("axis " + name + ": reading");
    const Eigen::VectorXd rate = io::ReadAxisRadPerSecondIsolated(info, name, ro);
    model::CompareInput in;
    in.rate_rad_s = &rate;
    in.sample_rate_hz = info.sample_rate_hz;
    in.latitude_deg = info.latitude_deg;
    in.aux = aux;
    const model::CompareOptions options;
    // Stage 1 is the trial fits of the missing terms and the IMF view, after the model's fit.
    progress.Step("axis " + name + ": fitting the model, then the trials");
    const model::CompareResult r =
        model::Compare(in, terms, options, progress.Counting(graph::TbbForEach));
    progress.Finish();
    if (!HasResult(r.summary.termination)) {
      std::cerr << "fogpipe compare: axis " << name << ": " << ToString(r.summary.termination)
                << ": " << r.summary.message << "\n";
      return 1;
    }
    ReportAxis(a, name, several, axis == axes.front(), r, &all);
  }
  if (a.json && several)
    std::cout << nlohmann::json{{"file", a.recording}, {"axes", all}}.dump(2) << "\n";
  return 0;
}

}  // namespace

void AddCompareCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<CompareArguments>();
  auto* cmd = app.add_subcommand("compare",
                                 "Compare a gyro model with a recording; name the missing effect");
  cmd->add_option("recording", args->recording, "Contract-v1 recording (HDF5)");
  auto* model = cmd->add_option("--model", args->model_file, "Model file (JSON) to start from");
  cmd->add_option("--terms", args->terms,
                  "Comma-separated terms: catalog names, aux:<channel> (bias polynomial in an "
                  "/aux channel, order by BIC), aux_rate:<channel> (in its derivative), "
                  "aux_hysteresis:<channel> (+- while it rises or falls), aux_am:<channel> (a "
                  "line whose amplitude follows it); bias is implicit")
      ->excludes(model);
  cmd->add_option("--add", args->add,
                  "Add a term: a catalog name, aux:<channel>, aux_rate:<channel>, "
                  "aux_hysteresis:<channel> or aux_am:<channel> (repeatable)");
  cmd->add_option("--axis", args->axis,
                  "Axis name, index, or all (every axis: one section, JSON object and history "
                  "step per axis)")
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "Print one JSON object");
  cmd->add_option("-o,--results", args->results, "Append the step to this RESULTS file (HDF5)");
  cmd->add_option("--save-model", args->save_model, "Write the fitted model file (JSON)");
  cmd->add_option("--history", args->history, "Print the model history of a RESULTS file");
  cmd->add_flag("--progress", args->progress,
                "Progress lines on stderr also when it is not a terminal (on a terminal they are "
                "always shown)");
  cmd->callback([args, exit_code]() {
    try {
      *exit_code = Run(*args);
    } catch (const std::exception& e) {
      std::cerr << "fogpipe compare: " << e.what() << "\n";
      *exit_code = 1;
    }
  });
}

}  // namespace fogpipe::cli
