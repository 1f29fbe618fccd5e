// fogpipe info RESULTS...: provenance and the paper's Tables 3 and 5 of results files.
// Exit codes: 0 ok, 1 a file could not be read as fogpipe-results-v1.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "pipeline/cli/commands.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/inputs.h"
#include "pipeline/io/results_reader.h"

namespace fogpipe::cli {

void AddInfoCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand("info", "Summary of results files, with Tables 3 and 5");
  auto paths = std::make_shared<std::vector<std::string>>();
  cmd->add_option("results", *paths, "Results files (*.fogpipe.h5)")->required();
  cmd->callback([paths, exit_code]() {
    hdf5::SilenceHdf5ErrorPrinter();
    *exit_code = 0;
    for (const std::string& path : *paths) {
      try {
        if (const std::string problem = io::RegularFileProblem(path); !problem.empty()) {
          throw std::runtime_error(path + ": not a results file: " + problem);
        }
        std::cout << io::FormatResultsSummaryIsolated(path) << "\n" << std::flush;
      } catch (const std::exception& e) {
        std::cerr << "fogpipe info: " << e.what() << "\n";
        *exit_code = 1;
      }
    }
  });
}

}  // namespace fogpipe::cli
