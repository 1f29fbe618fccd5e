// Each fogpipe subcommand lives in its own file and registers itself on the app.
// A command's callback stores its exit code in *exit_code; nothing below main() exits.
#pragma once

namespace CLI {
class App;
}

namespace fogpipe::cli {

void AddRunCommand(CLI::App& app, int* exit_code);       // run_command.cpp      (campaigns)
void AddAllanCommand(CLI::App& app, int* exit_code);     // allan_command.cpp    (quick Allan table)
void AddInfoCommand(CLI::App& app, int* exit_code);      // info_command.cpp     (results summary)
void AddValidateCommand(CLI::App& app, int* exit_code);  // validate_command.cpp (schemas/)
void AddSimulateCommand(CLI::App& app, int* exit_code);  // simulate_command.cpp (v1 recordings)
void AddCompareCommand(CLI::App& app, int* exit_code);   // compare_command.cpp  (model loop)
void AddSweepCommand(CLI::App& app, int* exit_code);     // sweep_command.cpp    (AR/Q/R grids)
void AddPlanCommand(CLI::App& app, int* exit_code);      // plan_command.cpp     (Slurm manifests)
void AddMergeCommand(CLI::App& app, int* exit_code);     // merge_command.cpp    (campaign table)
void AddImportCommand(CLI::App& app, int* exit_code);    // import_command.cpp   (text, MATLAB)

}  // namespace fogpipe::cli
