// fogpipe validate FILE...: checks recordings and results files against schemas/.
//
// Exit codes: 0 every file valid, 1 at least one file invalid, 2 usage error (no file given,
// schema not found or broken).
#include <CLI/CLI.hpp>
#include <iostream>
#include <string>
#include <vector>

#include "pipeline/cli/commands.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/file_validation.h"

namespace fogpipe::cli {
namespace {

struct ValidateArgs {
  std::vector<std::string> files;
  io::FileValidationOptions options;
  bool no_data = false;
  bool quiet = false;
};

int RunValidate(const ValidateArgs& args) {
  if (args.files.empty()) {
    std::cerr << "fogpipe validate: give at least one FILE (see fogpipe validate --help)\n";
    return 2;
  }
  hdf5::SilenceHdf5ErrorPrinter();
  io::FileValidationOptions options = args.options;
  options.check_data = !args.no_data;
  int exit_code = 0;
  for (const std::string& file : args.files) {
    // In a child process: a file that crashes or hangs HDF5 is one INVALID file, not the end of
    // the command. Reading every sample of a long recording may take minutes.
    io::IsolationLimits limits;
    limits.seconds = 1800.0;
    const io::FileValidation v = io::ValidateFileIsolated(file, options, limits);
    if (!v.usage_error.empty()) {
      std::cerr << "fogpipe validate: " << file << ": " << v.usage_error << "\n";
      return 2;
    }
    if (v.valid()) {
      if (!args.quiet) {
        std::cout << file << ": valid " << v.detected << " (schema " << v.schema << ", "
                  << v.objects_checked << " objects checked";
        if (v.samples_checked > 0) std::cout << ", " << v.samples_checked << " values read";
        std::cout << ")\n";
      }
      for (const io::SchemaProblem& w : v.warnings) {
        std::cout << "  " << file << ": warning: " << w.object << ": " << w.message << "\n";
      }
      continue;
    }
    exit_code = 1;
    std::cout << file << ": INVALID"
              << (v.schema.empty() ? std::string() : " (schema " + v.schema + ")") << ", "
              << v.problems.size() << " problem" << (v.problems.size() == 1 ? "" : "s") << "\n";
    for (const io::SchemaProblem& p : v.problems) {
      std::cout << "  " << file << ": " << p.object << ": " << p.message << "\n";
    }
  }
  return exit_code;
}

}  // namespace

void AddValidateCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<ValidateArgs>();
  auto* cmd = app.add_subcommand(
      "validate",
      "Check recordings (input contract v1) and results files against the layouts in schemas/. "
      "Exit code 0: all valid, 1: some file invalid, 2: usage error.");
  cmd->add_option("FILE", args->files, "HDF5 recording(s) or fogpipe results file(s)");
  cmd->add_option("--schemas", args->options.schemas_dir,
                  "Folder of schema files (default: $FOGPIPE_SCHEMAS_DIR, <prefix>/share/fogpipe/"
                  "schemas, then the source tree's schemas/). Recordings are held to the "
                  "recording-v1 layout built into fogpipe, the one `run` uses, unless --schemas "
                  "or --schema is given");
  cmd->add_option("--schema", args->options.schema,
                  "Use this schema (name such as recording-v1, or a .json path) instead of "
                  "detecting it from the root attribute fogpipe_format");
  cmd->add_flag("--no-data", args->no_data,
                "Check layout and metadata only; do not read the samples of recordings");
  cmd->add_option("--max-nan-gap", args->options.max_nan_gap_samples,
                  "Longest run of NaN samples a recording may have (bridged by the reader)")
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "Print only invalid files");
  cmd->callback([args, exit_code]() { *exit_code = RunValidate(*args); });
}

}  // namespace fogpipe::cli
