// fogpipe sweep: not yet implemented (placeholder registered so the CLI links; see the open issue).
#include <CLI/CLI.hpp>

#include <iostream>

#include "pipeline/cli/commands.h"

namespace fogpipe::cli {

void AddSweepCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand("sweep", "(not implemented yet)");
  cmd->callback([exit_code]() {
    std::cerr << "fogpipe sweep: not implemented yet\n";
    *exit_code = 2;
  });
}

}  // namespace fogpipe::cli
