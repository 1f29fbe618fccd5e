// fogpipe sweep RECORDING... --ar-order 2:12 --q-scale 0.1,1,10 --r-scale 0.1,1,10
//               [--emd-sifts 10] [--rank-by rms_error] [--config grid.toml] -o OUT
// The parameter sweep (pipeline/graph/sweep_runner.h): per recording OUT/<stem>.sweep.h5 and
// OUT/<stem>.sweep.csv, and the ranked summary on stdout. Every method option other than the grid
// is `fogpipe run`'s default (graph::RunConfig), so q_scale = r_scale = 1 is what `run` does.
//
// Exit codes: 0 every recording swept; 1 some recording failed (stderr says why); 2 usage error.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "pipeline/cli/commands.h"
#include "pipeline/graph/run_config.h"
#include "pipeline/graph/sweep_runner.h"

namespace fogpipe::cli {
namespace {

struct SweepConfig {
  std::vector<std::string> recordings;
  std::string output_dir;
  std::string config_file;
  std::string ar_order = "2:12";
  std::string q_scale = "0.1,1,10";
  std::string r_scale = "0.1,1,10";
  std::string emd_sifts = "10";
  std::string rank_by = "rms_error";
  std::string kalman_start = "paper";
  int top = 5;
  bool progress = false;
  /// `run`'s options that sweep shares (--threads), with run's defaults for the rest.
  graph::RunConfig run;
};

int RunSweepCommand(CLI::App* cmd, const SweepConfig& config) {
  std::string error;
  // The grids are texts ("2:12", "0.1,1,10"); in the file they may also be TOML arrays.
  if (!config.config_file.empty() &&
      !graph::ApplyConfigFile(cmd, config.config_file, &error,
                              {"ar-order", "q-scale", "r-scale", "emd-sifts"})) {
    std::cerr << "fogpipe sweep: " << error << "\n";
    return 2;
  }
  graph::CampaignOptions campaign;
  if (!graph::ToCampaignOptions(config.run, &campaign, &error)) {
    std::cerr << "fogpipe sweep: " << error << "\n";
    return 2;
  }
  graph::SweepRunOptions options;
  options.sweep.method = campaign.method;
  // The Kalman start (algorithms/kalman/ar_kalman.h): the paper's (default, more accurate on the
  // slow IMFs) or the steady-state start (faster, no time-varying phase).
  options.sweep.method.component.kalman.initial_covariance =
      config.kalman_start == "steady" ? kalman::InitialCovariance::kSteadyState
                                      : kalman::InitialCovariance::kSampleVariance;
  options.read = campaign.read;
  options.threads = campaign.threads;
  options.output_dir = config.output_dir;
  options.rank_by = config.rank_by;
  options.top = config.top;
  options.progress = config.progress;
  method::SweepGrid& grid = options.sweep.grid;
  if (!method::ParseIntList(config.ar_order, &grid.ar_orders, &error) ||
      !method::ParseScaleList(config.q_scale, &grid.q_scales, &error) ||
      !method::ParseScaleList(config.r_scale, &grid.r_scales, &error) ||
      !method::ParseIntList(config.emd_sifts, &options.emd_sifts, &error) ||
      !options.sweep.IsValid(&error)) {
    std::cerr << "fogpipe sweep: " << error << "\n";
    return 2;
  }
  int failed = 0;
  for (const std::string& recording : config.recordings) {
    std::vector<graph::SweepTable> tables;
    if (!graph::SweepRecording(recording, options, &tables, &error)) {
      std::cerr << "fogpipe sweep: " << error << "\n";
      ++failed;
    }
  }
  std::cerr << "fogpipe sweep: " << config.recordings.size() - failed << " of "
            << config.recordings.size() << " recordings swept over " << grid.size()
            << " settings; tables in " << config.output_dir << "\n";
  return failed > 0 ? 1 : 0;
}

}  // namespace

void AddSweepCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand(
      "sweep", "Sweep AR order and Kalman q/R scales (EMD once per recording and axis)");
  auto c = std::make_shared<SweepConfig>();
  cmd->add_option("recordings", c->recordings, "Recordings (v1 HDF5)")->required();
  cmd->add_option("-o,--output", c->output_dir, "Output folder")->required();
  cmd->add_option("--config", c->config_file,
                  "TOML file of options (keys are the long option names, at the top or under "
                  "[sweep]; e.g. ar-order = [2, 4, 8] or \"2:12\")");
  cmd->add_option("--ar-order", c->ar_order, "AR orders: FROM:TO[:STEP] or a list");
  cmd->add_option("--q-scale", c->q_scale, "Multipliers of the default q: list or FROM:TO:COUNT");
  cmd->add_option("--r-scale", c->r_scale, "Multipliers of the default R: list or FROM:TO:COUNT");
  cmd->add_option("--emd-sifts", c->emd_sifts, "EMD sifts per IMF (one decomposition each)");
  cmd->add_option("--rank-by", c->rank_by,
                  "Ranking criterion (rms_error needs a truth sidecar; else n is used)")
      ->check(CLI::IsMember(method::RankCriteria()));
  cmd->add_option("--kalman-start", c->kalman_start,
                  "Kalman P(0|0): paper (var(z) I, eq. 7; more accurate on slow IMFs) or steady "
                  "(the DARE's steady state; faster, no time-varying phase)")
      ->check(CLI::IsMember({"paper", "steady"}));
  cmd->add_option("--top", c->top, "Ranked settings printed per axis")
      ->check(CLI::Range(0, 100000));
  cmd->add_flag("--progress", c->progress,
                "Progress lines on stderr also when it is not a terminal (on a terminal they are "
                "always shown)");
  graph::AddRunOptions(cmd, &c->run, {"threads"});
  cmd->footer("Exit codes: 0 all swept, 1 some recording failed, 2 usage error.");
  cmd->callback([cmd, c, exit_code]() { *exit_code = RunSweepCommand(cmd, *c); });
}

}  // namespace fogpipe::cli
