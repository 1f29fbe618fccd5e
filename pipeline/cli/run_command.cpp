// fogpipe run INPUT... -o OUTDIR: the campaign (pipeline/graph/campaign.h).
//
// Exit codes: 0 every file ok or skipped; 1 at least one file failed (see OUTDIR/status.jsonl);
// 2 usage or configuration error (nothing was run); 130 / 143 interrupted by SIGINT / SIGTERM
// (finished files are complete, unfinished ones left no output a rerun would trust).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "pipeline/cli/commands.h"
#include "pipeline/graph/campaign.h"
#include "pipeline/graph/interrupt.h"
#include "pipeline/graph/memory_budget.h"
#include "pipeline/graph/run_config.h"
#include "pipeline/io/campaign_manifest.h"

namespace fogpipe::cli {
namespace {

int RunCampaignCommand(CLI::App* cmd, graph::RunConfig* config) {
  std::string error;
  if (!config->config_file.empty() && !graph::ApplyConfigFile(cmd, config->config_file, &error)) {
    std::cerr << "fogpipe run: " << error << "\n";
    return 2;
  }
  if (config->output_dir.empty()) {
    std::cerr << "fogpipe run: -o/--output OUTDIR is required\n";
    return 2;
  }
  if (config->inputs.empty() && config->manifest.empty()) {
    std::cerr << "fogpipe run: no input (give files, folders, globs or --manifest FILE)\n";
    return 2;
  }
  graph::CampaignOptions options;
  if (!graph::ToCampaignOptions(*config, &options, &error)) {
    std::cerr << "fogpipe run: " << error << "\n";
    return 2;
  }
  io::ShardBy shard_by = io::ShardBy::kStride;
  if (!io::ParseShardBy(config->shard_by, &shard_by) || config->shard >= config->num_shards) {
    std::cerr << "fogpipe run: need 0 <= --shard < --num-shards and --shard-by stride|size\n";
    return 2;
  }
  std::vector<std::string> input_errors;
  // Every shard lists the same sorted inputs and keeps its own part (io::SelectShard), so the
  // shards of an array job are disjoint and together cover the campaign.
  const auto inputs =
      io::SelectShard(io::ListInputs(config->inputs, config->manifest, &input_errors),
                      config->shard, config->num_shards, shard_by);
  for (const std::string& e : input_errors) std::cerr << "fogpipe run: " << e << "\n";
  if (inputs.empty()) {
    std::cerr << "fogpipe run: no recording to analyse\n";
    return input_errors.empty() ? 0 : 2;
  }
  options.redraw_progress = ::isatty(STDERR_FILENO) == 1;
  graph::InstallStopHandlers();
  graph::CampaignReport report;
  try {
    report = graph::RunCampaign(inputs, options);
  } catch (const std::exception& e) {
    std::cerr << "fogpipe run: " << e.what() << "\n";
    return 2;
  }
  if (options.dry_run) {
    std::cout << "dry run: " << inputs.size() << " recordings, " << options.threads
              << " threads, memory budget " << options.memory_budget_bytes << " bytes, about "
              << report.bytes_per_file << " bytes per recording in flight, so at most "
              << report.files_in_flight << " recordings at once\n";
    for (const auto& o : report.outcomes) {
      const char* what = o.status == graph::FileStatus::kSkipped  ? "skip (done)"
                         : o.status == graph::FileStatus::kFailed ? "FAIL"
                                                                  : "run ";
      std::cout << "  " << what << "  " << o.file << "  ->  " << o.output
                << (o.status == graph::FileStatus::kFailed ? "  (" + o.message + ")" : "") << "\n";
    }
    return report.failed > 0 ? 1 : 0;
  }
  std::cerr << "fogpipe run: " << report.ok << " ok"
            << (report.ok_with_warnings > 0 ? " (" + std::to_string(report.ok_with_warnings) +
                                                  " with data warnings in status.jsonl)"
                                            : "")
            << ", " << report.failed << " failed, " << report.skipped << " skipped"
            << (report.interrupted ? " (interrupted)" : "") << "; results in " << options.output_dir
            << ", status in " << options.output_dir << "/status.jsonl\n";
  return report.ExitCode();
}

}  // namespace

void AddRunCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand(
      "run",
      "Analyse recordings: EMD, per-IMF AR + Kalman, method 2, Allan; one results file each");
  auto config = std::make_shared<graph::RunConfig>();
  graph::AddRunOptions(cmd, config.get());
  cmd->footer(
      "Exit codes: 0 all files ok or skipped, 1 some file failed (OUTDIR/status.jsonl says why),\n"
      "2 usage/configuration error, 130/143 interrupted by SIGINT/SIGTERM.");
  cmd->callback([cmd, config, exit_code]() { *exit_code = RunCampaignCommand(cmd, config.get()); });
}

}  // namespace fogpipe::cli
