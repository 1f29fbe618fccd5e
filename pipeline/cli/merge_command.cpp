// fogpipe merge OUTDIR -o campaign.h5: the campaign table (pipeline/io/campaign_table.h).
//
// Safe to run again at any time, e.g. by the Slurm merge job (afterany) and again after a
// resubmitted shard: the table is rebuilt from OUTDIR and replaces the old one atomically.
//
// Exit codes: 0 every recording ok; 1 the table was written but some recording failed or is
// missing (its row says which), or a results file could not be read; 2 usage error or the table
// could not be written.
#include <fcntl.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "pipeline/cli/commands.h"
#include "pipeline/io/campaign_table.h"
#include "pipeline/io/text_output_file.h"

namespace fogpipe::cli {
namespace {

struct MergeConfig {
  std::string outdir;
  std::string output;
  std::string manifest;
  std::string csv;
};

int RunMerge(const MergeConfig& config) {
  std::error_code ec;
  if (!std::filesystem::is_directory(config.outdir, ec)) {
    std::cerr << "fogpipe merge: " << config.outdir << ": not a folder\n";
    return 2;
  }
  const std::string output = config.output.empty() ? config.outdir + "/campaign.h5" : config.output;
  io::CampaignTable table;
  try {
    table = io::CollectCampaign(config.outdir, config.manifest);
    io::WriteCampaignTable(output, table);
  } catch (const std::exception& e) {
    std::cerr << "fogpipe merge: " << e.what() << "\n";
    return 2;
  }
  if (!config.csv.empty()) {
    try {
      io::WriteTextFileAtomically(config.csv, io::FormatCampaignCsv(table));
    } catch (const std::exception& e) {
      std::cerr << "fogpipe merge: " << e.what() << "\n";
      return 2;
    }
  }

  for (const std::string& p : table.problems) std::cerr << "fogpipe merge: " << p << "\n";
  const io::CampaignCounts counts = io::CountRecordings(table);
  std::cerr << "fogpipe merge: " << table.recordings << " recordings (" << counts.ok << " ok, "
            << counts.failed << " failed, " << counts.missing << " missing), " << table.rows.size()
            << " rows, " << table.duplicate_results << " duplicate results files ignored -> "
            << output << "\n";
  return counts.failed + counts.missing > 0 || !table.problems.empty() ? 1 : 0;
}

}  // namespace

void AddMergeCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand(
      "merge", "Merge a campaign's results files into one table (one row per recording and axis)");
  auto config = std::make_shared<MergeConfig>();
  cmd->add_option("outdir", config->outdir, "Results folder of `fogpipe run` (all shards)")
      ->required();
  cmd->add_option("-o,--output", config->output, "Campaign table (default OUTDIR/campaign.h5)");
  cmd->add_option("--manifest", config->manifest,
                  "Manifest of the campaign: recordings listed but never processed become "
                  "'missing' rows");
  cmd->add_option("--csv", config->csv, "Also write the table as CSV");
  cmd->footer("Exit codes: 0 all ok, 1 written but some recording failed or is missing, 2 error.");
  cmd->callback([config, exit_code]() { *exit_code = RunMerge(*config); });
}

}  // namespace fogpipe::cli
