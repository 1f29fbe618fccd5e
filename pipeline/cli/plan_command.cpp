// fogpipe plan INPUT... -o manifest.txt: the campaign's sorted list of recordings with sizes
// (pipeline/io/campaign_manifest.h), the input of a Slurm job array.
//
// With --shard I --num-shards N it writes only shard I's part of the list (by stride or balanced by
// size), which `fogpipe run --manifest` then processes as a whole; scripts/slurm uses this when the
// `run` command it finds has no --shard option of its own.
//
// Exit codes: 0 written; 1 written, but some input was missing or unreadable (listed on stderr);
// 2 usage error or nothing to list.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "pipeline/cli/commands.h"
#include "pipeline/io/campaign_manifest.h"
#include "pipeline/io/inputs.h"

namespace fogpipe::cli {
namespace {

struct PlanConfig {
  std::vector<std::string> inputs;
  std::string manifest;
  std::string output;
  int shard = 0;
  int num_shards = 1;
  std::string shard_by = "stride";
};

int RunPlan(const PlanConfig& config) {
  io::ShardBy by = io::ShardBy::kStride;
  if (!io::ParseShardBy(config.shard_by, &by) || config.shard >= config.num_shards) {
    std::cerr << "fogpipe plan: need 0 <= --shard < --num-shards and --shard-by stride|size\n";
    return 2;
  }
  std::vector<std::string> errors;
  auto inputs = io::ListInputs(config.inputs, config.manifest, &errors);
  // A plan lists recordings that exist: one named but missing (or a FIFO, a folder) is an error
  // here, not a line that every shard would then fail on.
  std::vector<io::InputFile> readable;
  for (io::InputFile& input : inputs) {
    const std::string problem = io::RegularFileProblem(input.path);
    if (problem.empty()) {
      readable.push_back(std::move(input));
    } else {
      errors.push_back(input.path + ": not planned: " + problem);
    }
  }
  inputs = std::move(readable);
  for (const std::string& e : errors) std::cerr << "fogpipe plan: " << e << "\n";
  if (inputs.empty()) {
    std::cerr << "fogpipe plan: no recording found\n";
    return 2;
  }
  inputs = io::SelectShard(inputs, config.shard, config.num_shards, by);
  std::string error;
  if (!io::WriteManifest(config.output, inputs, &error)) {
    std::cerr << "fogpipe plan: " << error << "\n";
    return 2;
  }
  std::uintmax_t total = 0;
  for (const auto& input : inputs) total += input.size_bytes;
  std::cerr << "fogpipe plan: " << inputs.size() << " recordings, " << total << " bytes";
  if (config.num_shards > 1) {
    std::cerr << " (shard " << config.shard << " of " << config.num_shards << ", by "
              << config.shard_by << ")";
  }
  std::cerr << " -> " << config.output << "\n";
  return errors.empty() ? 0 : 1;
}

}  // namespace

void AddPlanCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand(
      "plan",
      "Write a campaign manifest: recordings sorted by path, with sizes (for Slurm arrays)");
  auto config = std::make_shared<PlanConfig>();
  cmd->add_option("inputs", config->inputs,
                  "Recordings: files, folders (recursive *.h5) or quoted glob patterns");
  cmd->add_option("--manifest", config->manifest,
                  "An existing manifest to read (e.g. to shard it)");
  cmd->add_option("-o,--output", config->output, "Manifest to write")->required();
  cmd->add_option("--shard", config->shard, "Write only this shard (0-based)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--num-shards", config->num_shards, "Number of shards")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--shard-by", config->shard_by, "stride (every N-th file) or size (balanced)")
      ->check(CLI::IsMember({"stride", "size"}));
  cmd->footer("Exit codes: 0 written, 1 written but some input was missing, 2 usage error.");
  cmd->callback([config, exit_code]() { *exit_code = RunPlan(*config); });
}

}  // namespace fogpipe::cli
