// fogpipe allan RECORDING: the Allan table and the five IEEE noise terms of one recording axis
// (or of every axis with --axis all), for people who want only that (no decomposition, no output
// file).
//
// Exit codes: 0 done, 1 the recording cannot be analysed (message names file and problem),
// 2 usage error.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include "algorithms/allan/allan.h"
#include "algorithms/allan/model_edf.h"
#include "algorithms/allan/noise_fit.h"
#include "pipeline/cli/commands.h"
#include "pipeline/graph/progress.h"
#include "pipeline/graph/run_config.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/allan_report.h"
#include "pipeline/io/isolated_reader.h"
#include "pipeline/io/recording_reader.h"

namespace fogpipe::cli {
namespace {

struct AllanArgs {
  std::string recording;
  std::string axis;  // empty: the first axis
  std::string deviation = allan::ToString(allan::AllanOptions{}.deviation);
  std::string taus = "octave";
  std::string noise_id = allan::ToString(allan::AllanOptions{}.noise_id);
  bool json = false;
  bool csv = false;
  double confidence = 0.683;
  long long max_nan_gap = 10;
  int threads = 0;
  bool progress = false;
};

// The analysis options from the arguments; false (a usage error, stderr says which) for a bad one.
bool ToAllanOptions(const AllanArgs& args, allan::AllanOptions* options) {
  options->confidence = args.confidence;
  options->threads = graph::ResolveThreads(args.threads);
  if (!allan::ParseNoiseIdRule(args.noise_id, &options->noise_id)) {
    std::cerr << "fogpipe allan: --noise-id must be calibrated or stable32, got '" << args.noise_id
              << "'\n";
    return false;
  }
  // Stable32's bounds come from its noise types and the EDF as Greenhall & Riley printed it.
  options->sampled_phase_edf = options->noise_id != allan::NoiseIdRule::kStable32;
  if (!allan::ParseDeviation(args.deviation, &options->deviation)) {
    std::cerr << "fogpipe allan: --deviation must be one of " << io::DeviationList() << ", got '"
              << args.deviation << "'\n";
    return false;
  }
  std::string error;
  if (!allan::ParseTauGrid(args.taus, &options->grid, &error) || !options->IsValid(&error)) {
    std::cerr << "fogpipe allan: " << error << "\n";
    return false;
  }
  return true;
}

// One axis read, its table computed and, for the deviations the IEEE model fits, its noise terms
// fitted. False (stderr says why) when the table has no result.
bool AnalyseAxis(const AllanArgs& args, const io::RecordingInfo& info, const std::string& name,
                 const allan::AllanOptions& options, graph::WorkProgress* progress,
                 io::AllanReport* report) {
  progress->Step("axis " + name + ": reading");
  io::ReadOptions read;
  read.max_nan_gap_samples = args.max_nan_gap;
  io::ReadReport read_report;
  const Eigen::VectorXd rate_rad_s =
      io::ReadAxisRadPerSecondIsolated(info, name, read, &read_report);
  report->file = args.recording;
  report->axis = name;
  report->rate_units = info.rate_units;
  report->rate_unit = info.rate_unit;
  report->sample_rate_hz = info.sample_rate_hz;
  report->samples = info.samples;
  report->nan_bridged = read_report.nan.bridged_samples;
  report->data_warning =
      io::DescribeRepeatedRun(read_report.repeats, info.sample_rate_hz, info.rate_units);
  report->taus = args.taus;
  report->confidence = options.confidence;
  progress->Step("axis " + name + ": " + args.deviation + " on the " + args.taus +
                 " grid and its intervals");
  allan::AllanResult allan = allan::ComputeAllan(rate_rad_s, report->sample_rate_hz, options);
  if (!HasResult(allan.summary.termination)) {
    std::cerr << "fogpipe allan: " << args.recording << ": axis " << report->axis << ": "
              << allan.summary.message << " [" << ToString(allan.summary.termination) << "]\n";
    return false;
  }
  report->table = std::move(allan.table);
  // The IEEE terms are coefficients of the Allan variance's response; on any other table
  // they would be wrong without saying so.
  report->fitted = allan::IeeeModelApplies(options.deviation);
  if (report->fitted) {
    progress->Step("axis " + name + ": noise terms and their EDF");
    report->fit = allan::FitNoiseTermsAndModelEdf(allan::NoiseFitOptions{}, options.confidence,
                                                  &report->table);
  }
  return true;
}

// One axis prints as it always has; several are labelled by an `axis` column (CSV) or an
// `axes` list (JSON) so that no row can be taken for another axis's.
void PrintReports(const AllanArgs& args, const std::vector<io::AllanReport>& reports) {
  const bool several = args.axis == io::kAllAxes;
  if (args.json) {
    std::cout << (several ? io::AllanReportJson(reports) : io::AllanReportJson(reports[0])).dump(2)
              << "\n";
  } else if (args.csv) {
    if (several)
      io::PrintAllanCsv(std::cout, reports);
    else
      io::PrintAllanCsv(std::cout, reports[0]);
  } else {
    for (size_t i = 0; i < reports.size(); ++i) {
      if (i > 0) std::cout << "\n";
      io::PrintAllanText(std::cout, reports[i]);
    }
  }
}

int RunAllan(const AllanArgs& args) {
  if (args.recording.empty()) {
    std::cerr << "fogpipe allan: give a RECORDING (see fogpipe allan --help)\n";
    return 2;
  }
  hdf5::SilenceHdf5ErrorPrinter();
  allan::AllanOptions options;
  if (!ToAllanOptions(args, &options)) return 2;
  std::vector<io::AllanReport> reports;
  bool redraw = false;
  std::FILE* progress_stream = graph::ProgressStream(args.progress, &redraw);
  // Steps only: the deviation sums and the fit take no ForEach to count tasks through.
  graph::WorkProgress progress("allan " + args.recording, progress_stream, redraw);
  try {
    // Inspected and read in child processes: a file that crashes HDF5 is named, not fatal.
    const io::RecordingInfo info = io::InspectRecordingIsolated(args.recording);
    const std::string axis_arg = args.axis.empty() ? "0" : args.axis;
    for (const int axis : io::SelectAxes(info, axis_arg)) {
      io::AllanReport report;
      if (!AnalyseAxis(args, info, info.axis_names[axis], options, &progress, &report)) return 1;
      reports.push_back(std::move(report));
    }
  } catch (const io::RecordingError& e) {
    std::cerr << "fogpipe allan: " << e.what() << " [" << e.kind() << "]\n";
    return 1;
  }
  progress.Finish();
  PrintReports(args, reports);
  return 0;
}

}  // namespace

void AddAllanCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<AllanArgs>();
  auto* cmd = app.add_subcommand(
      "allan",
      "Allan-type deviation table (tau, sigma in the recording's unit and deg/h, CI, EDF, count) "
      "and, for OADEV / ADEV, the noise terms Q, N, B, K, R of one recording axis, analysed as "
      "stored (`run` first drops --drop-start-s and replaces outliers, so its raw terms can "
      "differ). Exit code 0: done, 1: bad recording, 2: usage error.");
  cmd->add_option("RECORDING", args->recording, "HDF5 recording (input contract v1)");
  cmd->add_option("--axis", args->axis,
                  "Axis name (from the file's `axes`), index, or all (every axis, each labelled); "
                  "default 0");
  cmd->add_option("--deviation", args->deviation, io::DeviationHelp())->capture_default_str();
  cmd->add_option("--taus", args->taus,
                  "Tau grid: octave (1, 2, 4, ... samples), decade:K (K log-spaced per decade), "
                  "all (every m), log10 (allantools' taus='log10')")
      ->capture_default_str();
  auto* json = cmd->add_flag("--json", args->json, "Print one JSON object");
  auto* csv = cmd->add_flag("--csv", args->csv, "Print the table as CSV");
  json->excludes(csv);
  cmd->add_option("--noise-id", args->noise_id,
                  "Noise identification behind the intervals: calibrated (chosen by measured "
                  "coverage) or stable32 (Stable32's Alpha column and EDF convention, so that "
                  "bounds match its Min / Max Sigma)")
      ->capture_default_str();
  cmd->add_option("--confidence", args->confidence,
                  "Two-sided confidence level of the interval, a fraction (0.683: 68.3 %)")
      ->capture_default_str();
  cmd->add_option("--max-nan-gap", args->max_nan_gap,
                  "Longest run of missing (NaN) samples bridged by linear interpolation")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads,
                  "Threads for the deviation sums (0: SLURM_CPUS_PER_TASK if set, else all "
                  "cores); the numbers do not depend on it")
      ->check(CLI::Range(0, 4096));
  cmd->add_flag("--progress", args->progress,
                "Progress lines (each axis's steps) on stderr also when it is not a terminal (on "
                "a terminal they are always shown)");
  cmd->callback([args, exit_code]() { *exit_code = RunAllan(*args); });
}

}  // namespace fogpipe::cli
