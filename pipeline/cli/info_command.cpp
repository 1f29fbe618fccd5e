// fogpipe info FILE...: a summary of any file fogpipe writes, recognised by its root attribute
// fogpipe_format (none: a recording):
//   recording  samples, rate, duration, axes and units, attributes, aux channels
//   results    provenance and the paper's Tables 3 and 5; the model history when compare -o
//              appended one
//   campaign   rows, recordings ok / failed / missing, per row the raw N, B, K with standard
//              errors and the flags
//   sweep      per axis the grid size, the top settings by the ranking criterion, the default
//              and hardest settings and the reference filters (the lines `sweep` prints)
//   compare    the model history (the table `compare --history` prints)
// Exit codes: 0 ok, 1 a file could not be read as any of these.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "pipeline/cli/commands.h"
#include "pipeline/graph/sweep_runner.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/campaign_table.h"
#include "pipeline/io/file_validation.h"
#include "pipeline/io/inputs.h"
#include "pipeline/io/isolated_call.h"
#include "pipeline/io/model_history.h"
#include "pipeline/io/recording_check.h"
#include "pipeline/io/results_layout.h"
#include "pipeline/io/results_reader.h"

namespace fogpipe::cli {
namespace {

/// The sweep settings shown per table, as many as `sweep` prints by default.
constexpr int kTopSettings = 5;

std::string ModelHistory(const std::string& path) {
  return "model history (fogpipe compare; error 1 = the family-wise 95 % band)\n" +
         io::FormatHistory(io::ReadHistory(path));
}

/// The summary of one file, by its kind. Runs in a child process (io::SummarizeIsolated).
std::string Summarize(const std::string& path) {
  const std::string tag = io::ReadFormatTag(path);
  if (tag.empty()) return io::FormatRecordingSummary(io::InspectRecording(path));
  if (tag == io::results::kFormat) {
    std::string text = io::FormatSummary(io::ReadResultsSummary(path));
    bool has_history = false;
    {
      auto lock = hdf5::LockHdf5();
      has_history = io::OpenHdf5ReadOnly(path).Root().KindOf("compare") == hdf5::ObjectKind::kGroup;
    }
    return has_history ? text + "\n" + ModelHistory(path) : text;
  }
  if (tag == io::results::kPreviousFormat) {
    throw std::runtime_error(path + ": " + io::PreviousLayoutText());
  }
  if (tag == io::kCampaignFormat) {
    return io::FormatCampaignSummary(path, io::ReadCampaignTable(path));
  }
  if (tag == graph::kSweepFormat) {
    return path + "\n" + graph::FormatSweepRanking(graph::ReadSweepSummary(path, kTopSettings));
  }
  if (tag == io::kCompareFormat) return path + "\n" + ModelHistory(path);
  throw std::runtime_error(path + ": fogpipe_format '" + tag +
                           "' is no file kind fogpipe info knows (recording, " +
                           io::results::kFormat + ", " + io::kCampaignFormat + ", " +
                           graph::kSweepFormat + ", " + io::kCompareFormat + ")");
}

}  // namespace

void AddInfoCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand(
      "info", "Summary of fogpipe files: recordings, results, campaign tables, sweeps, histories");
  auto paths = std::make_shared<std::vector<std::string>>();
  cmd->add_option("files", *paths, "Files written by fogpipe, or recordings")->required();
  cmd->callback([paths, exit_code]() {
    hdf5::SilenceHdf5ErrorPrinter();
    *exit_code = 0;
    for (const std::string& path : *paths) {
      try {
        if (const std::string problem = io::RegularFileProblem(path); !problem.empty()) {
          throw std::runtime_error(path + ": " + problem);
        }
        std::cout << io::SummarizeIsolated(path, [&path] { return Summarize(path); }) << "\n"
                  << std::flush;
      } catch (const std::exception& e) {
        std::cerr << "fogpipe info: " << e.what() << "\n";
        *exit_code = 1;
      }
    }
  });
}

}  // namespace fogpipe::cli
