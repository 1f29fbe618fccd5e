// fogpipe command-line entry point. Only main() may end the process; everything below returns.
#include <CLI/CLI.hpp>
#include <iostream>
#include <string>

#include "pipeline/cli/commands.h"
#include "pipeline/cli/version.h"

int main(int argc, char** argv) {
  CLI::App app{"fogpipe: FOG test-campaign pipeline (EMD, per-IMF AR + Kalman, Allan variance)"};
  // Before any subcommand is added: CLI11 2.1 otherwise ignores misspelled config keys.
  app.allow_config_extras(CLI::config_extras_mode::error);
  app.set_version_flag("--version",
                       std::string(fogpipe::Version()) + " (" + fogpipe::GitCommit() + ")");
  app.require_subcommand(1);

  int exit_code = 0;
  fogpipe::cli::AddRunCommand(app, &exit_code);
  fogpipe::cli::AddAllanCommand(app, &exit_code);
  fogpipe::cli::AddInfoCommand(app, &exit_code);
  fogpipe::cli::AddValidateCommand(app, &exit_code);
  fogpipe::cli::AddSimulateCommand(app, &exit_code);
  fogpipe::cli::AddCompareCommand(app, &exit_code);
  fogpipe::cli::AddSweepCommand(app, &exit_code);
  fogpipe::cli::AddPlanCommand(app, &exit_code);
  fogpipe::cli::AddMergeCommand(app, &exit_code);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with exit code 0; every other parse error is a usage
    // error, which fogpipe documents as exit code 2 (not CLI11's own codes).
    const int cli_code = app.exit(e);
    return cli_code == 0 ? 0 : 2;
  }
  return exit_code;
}
