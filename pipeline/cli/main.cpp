// fogpipe command-line entry point. Only main() may end the process; everything below returns.
#include <CLI/CLI.hpp>

#include <iostream>

#include "pipeline/cli/version.h"

int main(int argc, char** argv) {
  CLI::App app{"fogpipe: FOG test-campaign pipeline"};
  app.allow_config_extras(CLI::config_extras_mode::error);
  app.set_version_flag("--version", std::string(fogpipe::Version()) + " (" + fogpipe::GitCommit() + ")");
  app.require_subcommand(1);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
