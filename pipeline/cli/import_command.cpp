// fogpipe import INPUT... -o OUT: turns the files gyro engineers have (CSV and other text tables,
// MATLAB v7.3 MAT-files) into contract-v1 recordings that every other command reads.
//
// One recording per input: -o names the output file for one input, or a folder that receives
// <input stem>.h5 for each. The kind of each input is found from its content (HDF5: MATLAB v7.3;
// an older MAT-file: refused with advice; anything else: text) unless --format says it. Each
// output is written under a temporary name, checked with the recording checks `run` and
// `validate` use, and renamed into place only when they admit it (pipeline/io/recording_import.h).
//
// Exit codes: 0 every input imported; 1 some input failed (each is named with its reason);
// 2 invalid options.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/cli/commands.h"
#include "pipeline/graph/campaign.h"
#include "pipeline/graph/interrupt.h"
#include "pipeline/io/isolated_call.h"
#include "pipeline/io/matlab_import.h"
#include "pipeline/io/recording_import.h"
#include "pipeline/io/text_import.h"
#include "pipeline/io/version.h"

namespace fogpipe::cli {
namespace {

namespace fs = std::filesystem;

struct ImportArguments {
  std::vector<std::string> inputs;
  std::string output;
  std::string format = "auto";
  bool force = false;
  std::vector<std::string> aux;  // NAME=SOURCE:UNITS, parsed into metadata.aux
  io::ImportMetadataOptions metadata;
  io::TextImportOptions text;
  io::MatlabImportOptions matlab;
  // Options that apply to one kind of input only; given for the other kind they are an error
  // rather than silently ignored.
  std::vector<CLI::Option*> text_only;
  std::vector<CLI::Option*> matlab_only;
};

std::string GivenOptions(const std::vector<CLI::Option*>& options) {
  std::string names;
  for (const CLI::Option* option : options) {
    if (option->count() > 0) names += (names.empty() ? "" : ", ") + option->get_name();
  }
  return names;
}

std::string Seconds(double seconds) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f s", seconds);
  return buffer;
}

// The output path of every input, or "" after printing why there is none (a usage error).
std::vector<std::string> PlanOutputs(const ImportArguments& a) {
  const bool folder = a.inputs.size() > 1 || fs::is_directory(a.output) ||
                      (!a.output.empty() && a.output.back() == '/');
  if (!folder) return {a.output};
  std::error_code ec;
  fs::create_directories(a.output, ec);
  if (ec) {
    std::cerr << "fogpipe import: cannot create the folder " << a.output << ": " << ec.message()
              << "\n";
    return {};
  }
  std::vector<std::string> outputs;
  std::map<std::string, std::string> taken;  // output -> input
  for (const std::string& input : a.inputs) {
    const std::string output = (fs::path(a.output) / fs::path(input).stem()).string() + ".h5";
    const auto [it, inserted] = taken.emplace(output, input);
    if (!inserted) {
      std::cerr << "fogpipe import: " << it->second << " and " << input << " would both be written"
                << " to " << output << "; import them into different folders\n";
      return {};
    }
    outputs.push_back(output);
  }
  return outputs;
}

// Imports one input; prints what happened. Returns false when it failed.
bool ImportOneUnguarded(const ImportArguments& a, const std::string& input,
                        const std::string& output) {
  std::error_code ec;
  if (!a.force && fs::exists(output, ec)) {
    std::cerr << "fogpipe import: " << output << " exists; give --force to replace it\n";
    return false;
  }
  if (fs::equivalent(input, output, ec)) {
    std::cerr << "fogpipe import: " << input << ": the output would replace the input\n";
    return false;
  }
  bool text = a.format == "text";
  if (a.format == "auto") {
    std::string error;
    const std::optional<io::ImportSourceKind> kind = io::DetectImportSourceKind(input, &error);
    if (!kind) {
      std::cerr << "fogpipe import: " << error << "\n";
      return false;
    }
    if (*kind == io::ImportSourceKind::kOldMatFile) {
      std::cerr << "fogpipe import: " << io::OldMatFileMessage(input) << "\n";
      return false;
    }
    text = *kind == io::ImportSourceKind::kText;
  }
  const std::string misplaced = GivenOptions(text ? a.matlab_only : a.text_only);
  if (!misplaced.empty()) {
    std::cerr << "fogpipe import: " << input << ": " << misplaced << ": for "
              << (text ? "MATLAB/HDF5" : "text") << " files only, and this is a "
              << (text ? "text" : "MATLAB/HDF5") << " file\n";
    return false;
  }

  const auto start = std::chrono::steady_clock::now();
  io::ImportResult result =
      text ? io::ImportText(input, a.text) : io::ImportMatlab(input, a.matlab);
  if (!result.ok()) {
    std::cerr << "fogpipe import: " << result.error << "\n";
    return false;
  }
  const auto read = std::chrono::steady_clock::now();
  for (const std::string& note : result.recording.notes) {
    std::cerr << "fogpipe import: " << input << ": note: " << note << "\n";
  }
  for (const std::string& warning : result.recording.warnings) {
    std::cerr << "fogpipe import: " << input << ": warning: " << warning << "\n";
  }
  result.recording.provenance["fogpipe_version"] = Version();
  result.recording.provenance["git_commit"] = GitCommit();
  const double sample_rate_hz = result.recording.data.sample_rate_hz;
  const std::string units = units::ToString(result.recording.rate_unit);
  const io::ImportWriteResult written =
      io::WriteImportedRecording(output, std::move(result.recording));
  if (!written.ok()) {
    std::cerr << "fogpipe import: " << written.error << "\n";
    return false;
  }
  const auto end = std::chrono::steady_clock::now();
  const double read_s = std::chrono::duration<double>(read - start).count();
  const double write_s = std::chrono::duration<double>(end - read).count();
  char rows_per_s[32];
  std::snprintf(rows_per_s, sizeof rows_per_s, "%.3g",
                written.info.samples / std::max(read_s, 1e-9));
  std::cerr << "fogpipe import: wrote " << output << " from " << input << " ("
            << written.info.samples << " samples x " << written.info.axis_count
            << (written.info.axis_count == 1 ? " axis at " : " axes at ") << sample_rate_hz
            << " Hz, " << units << "; read in " << Seconds(read_s) << ", " << rows_per_s
            << " rows/s; written and checked in " << Seconds(write_s) << ")\n";
  return true;
}

// A MATLAB/HDF5 input's metadata checked in a child under the short default limit
// (isolated_call.h): a loop in damaged metadata is found in seconds, not at the end of the long
// limit of the import itself. Returns false after printing why the input is refused.
bool MetadataPassesIsolated(const ImportArguments& a, const std::string& input) {
  io::IsolationLimits limits;
  limits.stop = graph::StopRequested;
  const io::IsolatedOutcome outcome = io::RunIsolatedLockingHdf5(
      [&](std::string* out) {
        *out = io::CheckMatlabVariables(input, a.matlab);
        return 0;
      },
      limits);
  const bool exited = outcome.end == io::IsolatedOutcome::End::kExited && outcome.exit_code == 0;
  if (exited && outcome.output.empty()) return true;
  if (exited) {
    std::cerr << "fogpipe import: " << outcome.output << "\n";
  } else if (outcome.Interrupted()) {
    std::cerr << "fogpipe import: " << input << ": interrupted; nothing written\n";
  } else {
    std::cerr << "fogpipe import: " << input << ": reading its metadata, the HDF5 library "
              << outcome.Describe(limits)
              << " (damaged metadata); the failure was contained in a child process, nothing "
                 "written\n";
  }
  return false;
}

// The child's exit codes.
constexpr int kImportFailed = 1;  // the child printed why
constexpr int kImportOutOfMemory = 3;

// What the parent says when the import's child did not end by itself.
void ReportImportChild(const std::string& input, const io::IsolatedOutcome& outcome,
                       const io::IsolationLimits& limits) {
  if (outcome.Interrupted()) {
    std::cerr << "fogpipe import: " << input << ": interrupted; nothing written\n";
  } else if (outcome.end == io::IsolatedOutcome::End::kExited &&
             outcome.exit_code == kImportOutOfMemory) {
    std::cerr << "fogpipe import: " << input << ": needed more than the "
              << (limits.extra_memory_bytes >> 20)
              << " MiB allowed for this input (a damaged or implausible file); not imported\n";
  } else {
    std::cerr << "fogpipe import: " << input << ": reading it, the HDF5 library "
              << outcome.Describe(limits)
              << " (damaged metadata, or a file that blocks); the failure was contained in a "
                 "child process, nothing written\n";
  }
}

// Each input is imported in a child process (isolated_call.h): a MATLAB file whose damaged
// metadata crashes or hangs the HDF5 library, or that declares more data than memory holds, is
// that input's named failure and the next input is imported. The child prints its own report.
bool ImportOne(const ImportArguments& a, const std::string& input, const std::string& output) {
  const std::string folder = fs::absolute(output).parent_path().string();
  const std::string name = fs::path(output).filename().string();
  graph::RemoveStaleTempFiles(folder, name);  // left by an import that was killed
  std::string error;
  const auto kind = io::DetectImportSourceKind(input, &error);  // reads 8 bytes, no HDF5
  if (kind && *kind == io::ImportSourceKind::kHdf5 && a.format != "text" &&
      !MetadataPassesIsolated(a, input)) {
    return false;
  }
  io::IsolationLimits limits;
  limits.seconds = 3600.0;  // a day at 100 Hz takes seconds; a slow network disk more
  std::error_code ec;
  const auto input_bytes = fs::is_regular_file(input, ec) ? fs::file_size(input, ec) : 0;
  // What a well-formed import needs (the parser's rows, the matrix, its copy for the writer) is
  // a few times the input; anything beyond is a damaged or implausible file.
  limits.extra_memory_bytes += 8 * static_cast<std::uint64_t>(ec ? 0 : input_bytes);
  limits.stop = graph::StopRequested;
  const io::IsolatedOutcome outcome = io::RunIsolatedLockingHdf5(
      [&](std::string*) {
        try {
          return ImportOneUnguarded(a, input, output) ? 0 : kImportFailed;
        } catch (const std::bad_alloc&) {
          return kImportOutOfMemory;
        } catch (const std::exception& e) {
          std::cerr << "fogpipe import: " << input << ": " << e.what() << "\n";
          return kImportFailed;
        }
      },
      limits);
  if (outcome.end == io::IsolatedOutcome::End::kExited) {
    if (outcome.exit_code == 0) return true;
    if (outcome.exit_code == kImportFailed) return false;
  }
  graph::RemoveStaleTempFiles(folder, name);
  ReportImportChild(input, outcome, limits);
  return false;
}

int RunImport(ImportArguments& a) {
  for (const std::string& spec : a.aux) {
    io::AuxImportSpec parsed;
    std::string error;
    if (!io::ParseAuxImportSpec(spec, &parsed, &error)) {
      std::cerr << "fogpipe import: --" << error << "\n";
      return 2;
    }
    a.metadata.aux.push_back(parsed);
  }
  a.text.metadata = a.metadata;
  a.matlab.metadata = a.metadata;
  std::string error;
  if (!a.text.IsValid(&error) || !a.matlab.IsValid(&error)) {
    std::cerr << "fogpipe import: " << error << "\n";
    return 2;
  }
  const std::vector<std::string> outputs = PlanOutputs(a);
  if (outputs.empty()) return 2;
  graph::InstallStopHandlers();
  int failures = 0;
  for (std::size_t k = 0; k < a.inputs.size(); ++k) {
    if (graph::StopRequested()) {
      std::cerr << "fogpipe import: " << a.inputs[k] << ": not started: interrupted\n";
      ++failures;
      continue;
    }
    if (!ImportOne(a, a.inputs[k], outputs[k])) ++failures;
  }
  if (graph::StopRequested()) return graph::InterruptedExitCode();
  if (a.inputs.size() > 1) {
    std::cerr << "fogpipe import: " << a.inputs.size() - failures << " of " << a.inputs.size()
              << " inputs imported\n";
  }
  return failures == 0 ? 0 : 1;
}

void AddInputOutputOptions(CLI::App* cmd, ImportArguments* a) {
  cmd->add_option("INPUT", a->inputs, "Text or MATLAB v7.3 file(s), opened read-only")->required();
  cmd->add_option("-o,--output", a->output,
                  "Output recording for one input; or a folder (several inputs, an existing "
                  "folder, or a path ending in '/') that receives <input stem>.h5 for each")
      ->required();
  cmd->add_option("--format", a->format,
                  "Input kind: auto (HDF5 content: MATLAB v7.3; otherwise text), text or matlab")
      ->check(CLI::IsMember({"auto", "text", "matlab"}))
      ->capture_default_str();
  cmd->add_flag("--force", a->force, "Replace existing output files (default: refuse them)");
}

// What every input needs.
void AddMetadataOptions(CLI::App* cmd, ImportArguments* a) {
  io::ImportMetadataOptions& metadata = a->metadata;
  cmd->add_option("--units", metadata.rate_units,
                  "Unit of the rate after --scale-factor: deg/h, deg/s or rad/s (required)")
      ->check(CLI::IsMember({"deg/h", "deg/s", "rad/s"}))
      ->required();
  cmd->add_option("--scale-factor", metadata.scale_factor,
                  "rate = value x scale factor, in --units per source unit (e.g. per count); 1 "
                  "keeps the values bit for bit")
      ->capture_default_str();
  cmd->add_option("--sample-rate-hz", metadata.sample_rate_hz,
                  "Sample rate in Hz (default: none, from --time-column or "
                  "--sample-rate-variable; with --time-column both must agree)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--axes", metadata.axes,
                  "Axis names, comma-separated, one per rate column (default: the header's names "
                  "of the rate columns, else none: axis0, axis1, ...)")
      ->delimiter(',');
  cmd->add_option("--aux", a->aux,
                  "Aux channel NAME=SOURCE:UNITS, e.g. temperature=T:degC; SOURCE is a column "
                  "(text) or a variable (MATLAB) of N values; repeatable (default: none)");
  cmd->add_option("--instrument", metadata.instrument,
                  "Root attribute `instrument` (default: none, omitted)");
  cmd->add_option("--serial", metadata.serial, "Root attribute `serial` (default: none, omitted)");
  cmd->add_option("--start-time-utc", metadata.start_time_utc,
                  "Root attribute `start_time_utc`, ISO 8601 UTC time of the first sample, e.g. "
                  "2026-03-01T08:00:00Z (default: none, omitted)");
  cmd->add_option("--latitude-deg", metadata.latitude_deg,
                  "Root attribute `latitude_deg`, site latitude in deg, [-90, 90] (default: none, "
                  "omitted)")
      ->check(CLI::Range(-90.0, 90.0));
}

// Options for text inputs; returned so that they can be refused for MATLAB inputs.
std::vector<CLI::Option*> AddTextOptions(CLI::App* cmd, io::TextImportOptions* text) {
  return {
      cmd->add_option("--delimiter", text->delimiter,
                      "Field delimiter: auto (the first of tab, ';', ',' and blanks that splits "
                      "the first lines evenly), comma or ',', semicolon or ';', tab, or space "
                      "(runs of blanks)")
          ->capture_default_str(),
      cmd->add_option("--skip-rows", text->skip_rows,
                      "Lines dropped at the top of the file whatever they hold, in lines")
          ->check(CLI::NonNegativeNumber)
          ->capture_default_str(),
      cmd->add_option("--header", text->header,
                      "Header line: auto (the first kept line when none of its fields is a "
                      "number), yes or no")
          ->check(CLI::IsMember({"auto", "yes", "no"}))
          ->capture_default_str(),
      cmd->add_option("--comment", text->comment_prefix,
                      "Lines starting with this (after blanks) are skipped; \"\" keeps every line")
          ->capture_default_str(),
      cmd->add_flag("--decimal-comma", text->decimal_comma,
                    "Numbers use a decimal comma, 1,5 (default: off, a decimal point)"),
      cmd->add_option("--rate-columns", text->rate_columns,
                      "Rate columns, comma-separated header names or 0-based indices, one per "
                      "axis (default: the only column not used by --time-column or --aux)")
          ->delimiter(','),
      cmd->add_option("--time-column", text->time_column,
                      "Column of time stamps (name or 0-based index): gives the sample rate, and "
                      "its steps are checked to be uniform (default: none)"),
      cmd->add_option("--time-units", text->time_units, "Unit of --time-column: s, ms, us or ns")
          ->check(CLI::IsMember({"s", "ms", "us", "ns"}))
          ->capture_default_str(),
      cmd->add_option("--time-tolerance-percent", text->time_tolerance_percent,
                      "Largest deviation of a time step from the median step, in % of the "
                      "median; a larger one is refused, naming its line")
          ->check(CLI::Range(0.001, 49.0))
          ->capture_default_str(),
  };
}

// Options for MATLAB inputs; returned so that they can be refused for text inputs.
std::vector<CLI::Option*> AddMatlabOptions(CLI::App* cmd, io::MatlabImportOptions* matlab) {
  return {
      cmd->add_option("--variable", matlab->variable,
                      "Variable holding the rate: an N x A matrix (one row per sample) or a "
                      "vector; a struct field a.b or an HDF5 path /a/b (required for MATLAB "
                      "files; default: none)"),
      cmd->add_option("--sample-rate-variable", matlab->sample_rate_variable,
                      "Scalar variable holding the sample rate in Hz (default: none; then "
                      "--sample-rate-hz)"),
  };
}

}  // namespace

void AddImportCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<ImportArguments>();
  auto* cmd = app.add_subcommand(
      "import",
      "Turn text tables (CSV, TSV, blank-separated) and MATLAB v7.3 MAT-files into contract-v1 "
      "recordings. Exit code 0: all imported, 1: some input failed, 2: usage error.");
  AddInputOutputOptions(cmd, args.get());
  AddMetadataOptions(cmd, args.get());
  args->text_only = AddTextOptions(cmd, &args->text);
  args->matlab_only = AddMatlabOptions(cmd, &args->matlab);
  cmd->callback([args, exit_code]() { *exit_code = RunImport(*args); });
}

}  // namespace fogpipe::cli
