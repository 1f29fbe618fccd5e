// Tests of pipeline/graph/run_config.{h,cpp}: the configuration whose hash decides whether a rerun
// may skip a finished file.
#include "pipeline/graph/run_config.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

#include "pipeline/graph/memory_budget.h"
#include "pipeline/io/inputs.h"

namespace fogpipe::graph {
namespace {

// Options that cannot change a number in a results file, and why: which files and where to
// (inputs, manifest, shard, num-shards, shard-by, o, scratch-dir), how to schedule (threads:
// results are identical whatever the thread count, checked by the campaign test; memory-budget),
// whether to run at all (dry-run, force), and config (a file whose values set the other options,
// which are hashed themselves). Every other option must appear in the hashed configuration text.
const std::set<std::string> kExempt = {
    "help",   "inputs", "manifest", "shard",         "num-shards", "shard-by", "o",
    "output", "config", "threads",  "memory-budget", "dry-run",    "force",    "scratch-dir"};

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

// A value other than the default for every hashed option, given on a command line: each must
// change the hashed text, so a results file made with other numbers is never taken as "done".
// An option added without an entry here fails the test.
TEST(RunConfig, EveryHashedOptionChangesTheHashWhenItsValueChanges) {
  const std::vector<std::vector<std::string>> kChanged = {{"--drop-start-s", "12.5"},
                                                          {"--max-nan-gap", "7"},
                                                          {"--max-ar-order", "13"},
                                                          {"--ar-order", "3"},
                                                          {"--ar-estimator", "yule_walker"},
                                                          {"--emd-sifts", "17"},
                                                          {"--emd-stop-rule", "rilling"},
                                                          {"--max-imfs", "5"},
                                                          {"--band-limit-ratio", "0.35"},
                                                          {"--q", "1e-9"},
                                                          {"--r", "2e-8"},
                                                          {"--noise-rule", "innovation"},
                                                          {"--q-scale", "2"},
                                                          {"--r-scale", "3"},
                                                          {"--smooth"},
                                                          {"--imf-storage", "none"},
                                                          {"--store-filtered-imfs"},
                                                          {"--direct-ar-order", "6"},
                                                          {"--taus", "decade"},
                                                          {"--noise-id", "stable32"},
                                                          {"--model", "thermal.model.json"}};
  const std::string defaults = EffectiveConfigToml(RunConfig{});
  std::set<std::string> covered;
  for (const std::vector<std::string>& args : kChanged) {
    CLI::App app;
    RunConfig config;
    AddRunOptions(&app, &config);
    std::vector<std::string> argv = args;
    std::reverse(argv.begin(), argv.end());  // CLI11 takes a reversed vector
    ASSERT_NO_THROW(app.parse(argv)) << args[0];
    EXPECT_NE(EffectiveConfigToml(config), defaults) << args[0] << " does not change the hash";
    covered.insert(args[0].substr(2));
  }
  CLI::App app;
  RunConfig config;
  AddRunOptions(&app, &config);
  for (const CLI::Option* option : app.get_options()) {
    std::string name = option->get_lnames().empty() ? option->get_name() : option->get_lnames()[0];
    while (!name.empty() && name[0] == '-') name.erase(0, 1);
    if (kExempt.count(name) == 0) {
      EXPECT_EQ(covered.count(name), 1u) << "--" << name << " has no changed value in this test";
    }
  }
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

// Restores an environment variable when the test ends.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) saved_ = old;
    had_ = std::getenv(name) != nullptr;
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (had_) {
      setenv(name_, saved_.c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::string saved_;
  bool had_ = false;
};

// The Slurm environment cannot grant what the options refuse: threads stay within --threads'
// range and the memory budget within 80 % of the machine, whatever the job asked for.
TEST(RunConfig, SlurmVariablesAreHeldToTheOptionsLimits) {
  {
    ScopedEnv cpus("SLURM_CPUS_PER_TASK", "100000000");
    const int threads = ResolveThreads(0);
    EXPECT_GE(threads, 1);
    EXPECT_LE(threads, 4096);
  }
  {
    ScopedEnv cpus("SLURM_CPUS_PER_TASK", "3");
    EXPECT_EQ(ResolveThreads(0), 3);
    EXPECT_EQ(ResolveThreads(2), 2);  // the option wins
  }
  const std::uint64_t physical = PhysicalMemoryBytes();
  ASSERT_GT(physical, 0u);
  {
    // 1 PiB in MiB, far above any machine.
    ScopedEnv mem("SLURM_MEM_PER_NODE", "1073741824");
    EXPECT_LE(AutoMemoryBudgetBytes(), physical / 5 * 4);
    EXPECT_GT(AutoMemoryBudgetBytes(), 0u);
  }
  {
    ScopedEnv mem("SLURM_MEM_PER_NODE", "not-a-number");
    EXPECT_EQ(AutoMemoryBudgetBytes(), physical / 2);
  }
}

// `--config` names a TOML file: a folder (or a missing file) is a usage error that says so, never
// silently ignored.
TEST(RunConfig, AConfigFileThatIsAFolderIsRefused) {
  CLI::App app;
  RunConfig config;
  AddRunOptions(&app, &config);
  std::string error;
  EXPECT_FALSE(ApplyConfigFile(&app, "/tmp", &error));
  EXPECT_NE(error.find("it is a folder"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(ApplyConfigFile(&app, "/nonexistent/fogpipe.toml", &error));
  EXPECT_NE(error.find("no such file"), std::string::npos) << error;
}

// --manifest and --model name files too: a folder, a FIFO (whose open blocks until a writer
// comes) or /dev/null is refused by name before it is opened, never read as an empty list.
TEST(RunConfig, ManifestAndModelFilesMustBeRegularFiles) {
  const std::string fifo = "/tmp/fogpipe-run-config-test-" + std::to_string(getpid()) + ".fifo";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {std::string("/tmp"), fifo, std::string("/dev/null")}) {
    std::vector<std::string> errors;
    const auto inputs = io::ListInputs({}, path, &errors);
    EXPECT_TRUE(inputs.empty());
    ASSERT_EQ(errors.size(), 1u) << path;
    EXPECT_NE(errors[0].find("--manifest needs a manifest file"), std::string::npos) << errors[0];
    RunConfig config;
    config.output_dir = "out";
    config.model = path;
    CampaignOptions options;
    std::string error;
    EXPECT_FALSE(ToCampaignOptions(config, &options, &error)) << path;
    EXPECT_NE(error.find("needs a model file"), std::string::npos) << error;
  }
  unlink(fifo.c_str());
}

}  // namespace
}  // namespace fogpipe::graph
