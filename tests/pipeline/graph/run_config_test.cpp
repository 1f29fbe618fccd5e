// Tests of pipeline/graph/run_config.{h,cpp}: the configuration whose hash decides whether a rerun
// may skip a finished file.
#include "pipeline/graph/run_config.h"

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <set>
#include <string>

#include "pipeline/graph/memory_budget.h"

namespace fogpipe::graph {
namespace {

// Options that cannot change a number in a results file, and why: which files and where to
// (inputs, manifest, shard, num-shards, shard-by, o), how to schedule (threads: results are
// identical whatever the thread count, checked by the campaign test; memory-budget), whether to
// run at all (dry-run, force), and config (a file whose values set the other options, which are
// hashed themselves). Every other option must appear in the hashed configuration text.
const std::set<std::string> kExempt = {
    "help",   "inputs", "manifest", "shard",         "num-shards", "shard-by", "o",
    "output", "config", "threads",  "memory-budget", "dry-run",    "force"};

TEST(RunConfig, EveryOptionThatCanChangeANumberIsInTheHashedConfiguration) {
  CLI::App app;
  RunConfig config;
  AddRunOptions(&app, &config);
  const std::string text = EffectiveConfigToml(config);
  int checked = 0;
  for (const CLI::Option* option : app.get_options()) {
    std::string name = option->get_lnames().empty() ? option->get_name() : option->get_lnames()[0];
    while (!name.empty() && name[0] == '-') name.erase(0, 1);
    if (kExempt.count(name) != 0) continue;
    ++checked;
    EXPECT_NE(text.find("\n" + name + " = "), std::string::npos)
        << "--" << name << " is not in the hashed configuration:\n"
        << text;
  }
  std::printf("%d options checked against the hashed configuration\n", checked);
  EXPECT_GE(checked, 18);
}

TEST(RunConfig, ChangingAnOptionChangesTheConfigurationText) {
  RunConfig a, b;
  b.noise_id = "stable32";
  EXPECT_NE(EffectiveConfigToml(a), EffectiveConfigToml(b));
  b = a;
  b.taus = "decade:5";
  EXPECT_NE(EffectiveConfigToml(a), EffectiveConfigToml(b));
  b = a;
  b.q_scale = 2.0;
  EXPECT_NE(EffectiveConfigToml(a), EffectiveConfigToml(b));
}

// A budget the machine cannot hold is refused with the physical memory in the message; one
// within it is taken as given.
TEST(RunConfig, AMemoryBudgetAboveThePhysicalMemoryIsRefused) {
  const std::uint64_t physical = PhysicalMemoryBytes();
  ASSERT_GT(physical, 0u);
  RunConfig config;
  config.output_dir = "out";
  config.memory_budget = std::to_string(2 * (physical >> 20)) + "M";
  CampaignOptions options;
  std::string error;
  EXPECT_FALSE(ToCampaignOptions(config, &options, &error));
  EXPECT_NE(error.find("physical memory"), std::string::npos) << error;
  EXPECT_NE(error.find(std::to_string(physical >> 20) + " MiB"), std::string::npos) << error;
  config.memory_budget = "256M";
  error.clear();
  EXPECT_TRUE(ToCampaignOptions(config, &options, &error)) << error;
  EXPECT_EQ(options.memory_budget_bytes, 256u << 20);
}

}  // namespace
}  // namespace fogpipe::graph
