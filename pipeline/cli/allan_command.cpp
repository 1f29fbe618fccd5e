// fogpipe allan: not yet implemented (placeholder registered so the CLI links; see the open issue).
#include <CLI/CLI.hpp>

#include <iostream>

#include "pipeline/cli/commands.h"

namespace fogpipe::cli {

void AddAllanCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand("allan", "(not implemented yet)");
  cmd->callback([exit_code]() {
    std::cerr << "fogpipe allan: not implemented yet\n";
    *exit_code = 2;
  });
}

}  // namespace fogpipe::cli
