// Tests of pipeline/graph/run_config.{h,cpp}: the configuration whose hash decides whether a rerun
// may skip a finished file.
#include "pipeline/graph/run_config.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

#include "pipeline/graph/memory_budget.h"
#include "pipeline/io/inputs.h"
#include "pipeline/io/sha256.h"

namespace fogpipe::graph {
namespace {

// The options outside the hash, and why they cannot change a number in a results file: which
// files and where to (inputs, manifest, shard, num-shards, shard-by, output, scratch-dir), how to
// schedule (threads: results are identical whatever the thread count, checked by the campaign
// test; memory-budget), whether to run at all (dry-run, force), and config (a file whose values
// set the other options, which are hashed themselves). An option added outside the hash must be
// added here, with its reason.
const std::set<std::string> kNotHashed = {"inputs",   "manifest",      "shard",       "num-shards",
                                          "shard-by", "output",        "scratch-dir", "config",
                                          "threads",  "memory-budget", "dry-run",     "force"};

// CLI11 takes its arguments reversed.
void Parse(CLI::App* app, std::vector<std::string> args) {
  std::reverse(args.begin(), args.end());
  app->parse(args);
}

// The command line that gives `option` its changed value.
std::vector<std::string> ChangedArgs(const RunOption& option) {
  std::vector<std::string> args = {"--" + option.key};
  if (!option.changed.empty()) args.push_back(option.changed);
  return args;
}

TEST(RunOptions, OnlyTheOptionsThatCannotChangeANumberAreLeftOutOfTheHash) {
  std::set<std::string> not_hashed;
  for (const RunOption& option : RunOptions()) {
    if (!option.hashed) not_hashed.insert(option.key);
  }
  EXPECT_EQ(not_hashed, kNotHashed);
}

// Every hashed option, set on a command line to a value other than its default, changes the
// hashed text, so a results file made with other numbers is never taken as "done". The table
// drives the test: an option added to it is covered without an edit here.
TEST(RunOptions, EveryHashedOptionChangesTheHashWhenItsValueChanges) {
  const std::string defaults = EffectiveConfigToml(RunConfig{});
  int checked = 0;
  for (const RunOption& option : RunOptions()) {
    if (!option.hashed) continue;
    const bool flag = std::holds_alternative<bool RunConfig::*>(option.member);
    EXPECT_EQ(option.changed.empty(), flag) << "--" << option.key << " needs a changed value";
    CLI::App app;
    RunConfig config;
    AddRunOptions(&app, &config);
    ASSERT_NO_THROW(Parse(&app, ChangedArgs(option))) << option.key;
    EXPECT_NE(EffectiveConfigToml(config), defaults) << "--" << option.key << " leaves the hash";
    EXPECT_NE(defaults.find("\n" + option.key + " = "), std::string::npos) << option.key;
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(RunOptions().size() - kNotHashed.size()));
}

// The campaign options that the rows of the table fill, as text. A row whose changed value leaves
// this text as it was does not reach the campaign; a row added with a new destination adds that
// destination here.
std::string CampaignFields(const CampaignOptions& o) {
  const method::MethodOptions& m = o.method;
  const allan::TauGridOptions& grid = m.allan.grid;
  std::ostringstream out;
  out.precision(17);
  out << "drop_start_s " << m.preprocess.drop_start_s << "\nmax_nan_gap_samples "
      << o.read.max_nan_gap_samples << "\nar max_order " << m.component.ar.max_order
      << " fixed_order " << m.component.ar.fixed_order << " estimator "
      << static_cast<int>(m.component.ar.estimator) << "\nemd fixed_sifts " << m.emd.fixed_sifts
      << " max_sifts " << m.emd.max_sifts << " stop_rule " << static_cast<int>(m.emd.stop_rule)
      << " max_imfs " << m.emd.max_imfs << "\nband_limit " << m.band_limit.cutoff_ratio
      << "\nkalman q " << m.component.kalman.q << " r " << m.component.kalman.r << " q_scale "
      << m.component.kalman.q_scale << " r_scale " << m.component.kalman.r_scale << " smooth "
      << m.component.kalman.smooth << " noise_rule " << static_cast<int>(m.component.noise_rule)
      << "\nimf_storage " << static_cast<int>(o.results.imf_storage) << " store_filtered "
      << o.results.store_filtered_imfs << "\ndirect_ar_order " << m.direct_ar_order << "\ntaus "
      << static_cast<int>(grid.kind) << " " << grid.per_decade << " " << grid.explicit_m.size()
      << "\nnoise_id " << static_cast<int>(m.allan.noise_id) << " sampled_phase_edf "
      << m.allan.sampled_phase_edf << "\nmodel " << (o.model ? o.model->path : "none") << "\n";
  return out.str();
}

// Every hashed option reaches the campaign options through its own row: its changed value gives
// other campaign options than its default, so no option can enter the hash and then be dropped
// on the way to the method. (The row is applied alone: --model's file is read by a later step.)
TEST(RunOptions, EveryHashedOptionReachesTheCampaignOptions) {
  const RunConfig defaults;
  int checked = 0;
  for (const RunOption& option : RunOptions()) {
    if (!option.hashed) continue;
    ASSERT_TRUE(option.apply) << "--" << option.key << " goes nowhere";
    CLI::App app;
    RunConfig config;
    AddRunOptions(&app, &config);
    ASSERT_NO_THROW(Parse(&app, ChangedArgs(option))) << option.key;
    CampaignOptions from_default, from_changed;
    EXPECT_EQ(option.apply(defaults, &from_default), "") << option.key;
    EXPECT_EQ(option.apply(config, &from_changed), "") << option.key;
    EXPECT_NE(CampaignFields(from_changed), CampaignFields(from_default))
        << "--" << option.key << " does not reach the campaign options";
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(RunOptions().size() - kNotHashed.size()));
}

// The rows without a destination in the campaign options are those `run` acts on itself: which
// recordings to read (inputs, manifest and the shards) and the config file that sets the others.
TEST(RunOptions, OnlyTheOptionsThatRunReadsItselfHaveNoPlaceInTheCampaignOptions) {
  std::set<std::string> without_apply;
  for (const RunOption& option : RunOptions()) {
    if (!option.apply) without_apply.insert(option.key);
  }
  EXPECT_EQ(without_apply, (std::set<std::string>{"inputs", "manifest", "shard", "num-shards",
                                                  "shard-by", "config"}));
}

// The hashed text is itself a --config file: read back onto fresh options it sets every hashed
// value as it was (here all of them changed at once).
TEST(RunOptions, TheHashedConfigurationReadsBackAsTheSameConfigFile) {
  CLI::App app;
  RunConfig config;
  AddRunOptions(&app, &config);
  std::vector<std::string> args;
  for (const RunOption& option : RunOptions()) {
    if (!option.hashed) continue;
    const std::vector<std::string> changed = ChangedArgs(option);
    args.insert(args.end(), changed.begin(), changed.end());
  }
  ASSERT_NO_THROW(Parse(&app, args));
  const std::string text = EffectiveConfigToml(config);
  ASSERT_NE(text, EffectiveConfigToml(RunConfig{}));
  const std::string path = "/tmp/fogpipe-run-options-test-" + std::to_string(getpid()) + ".toml";
  {
    std::ofstream file(path);
    file << text;
  }
  CLI::App reread_app;
  RunConfig reread;
  AddRunOptions(&reread_app, &reread);
  ASSERT_NO_THROW(Parse(&reread_app, {}));
  std::string error;
  EXPECT_TRUE(ApplyConfigFile(&reread_app, path, &error)) << error;
  EXPECT_EQ(EffectiveConfigToml(reread), text);
  unlink(path.c_str());
}

// The defaults' hashed text. Its first line names the results layout, so the configuration hash,
// the rerun key, changes with the layout: files of the previous layout (fogpipe-results-v1, whose
// default stored float64 IMFs) are rewritten by a rerun, never skipped (schemas/results-v2.md).
// Any other change of this text makes a rerun redo every finished file of a campaign.
TEST(RunOptions, TheDefaultConfigurationTextNamesTheResultsLayoutAndFloat32Imfs) {
  EXPECT_EQ(EffectiveConfigToml(RunConfig{}),
            "# fogpipe run: effective configuration (fogpipe-results-v2)\n"
            "drop-start-s = 0.0\n"
            "max-nan-gap = 10\n"
            "max-ar-order = 20\n"
            "ar-order = 0\n"
            "ar-estimator = \"burg\"\n"
            "emd-sifts = 10\n"
            "emd-stop-rule = \"fixed_sifts\"\n"
            "max-imfs = 0\n"
            "band-limit-ratio = 0.69999999999999996\n"
            "q = -1.0\n"
            "r = -1.0\n"
            "noise-rule = \"share\"\n"
            "q-scale = 1.0\n"
            "r-scale = 1.0\n"
            "smooth = false\n"
            "imf-storage = \"float32\"\n"
            "store-filtered-imfs = false\n"
            "direct-ar-order = 0\n"
            "taus = \"octave\"\n"
            "noise-id = \"calibrated\"\n"
            "model = \"\"\n");
}

// A quantity's --help line ends with its unit; a choice's lists its spellings.
TEST(RunOptions, TheHelpShowsEachQuantitysUnitAndEachChoicesSpellings) {
  CLI::App app;
  RunConfig config;
  AddRunOptions(&app, &config);
  int units = 0;
  for (const RunOption& option : RunOptions()) {
    const CLI::Option* cli =
        app.get_option(option.key == "inputs" ? option.key : "--" + option.key);
    if (!option.unit.empty()) {
      ++units;
      const std::string help = cli->get_description();
      EXPECT_EQ(help.substr(help.size() - option.unit.size() - 3), " [" + option.unit + "]")
          << option.key;
    }
    for (const std::string& choice : option.choices) {
      CLI::App one;
      RunConfig c;
      AddRunOptions(&one, &c);
      EXPECT_NO_THROW(Parse(&one, {"--" + option.key, choice})) << option.key << " " << choice;
    }
  }
  EXPECT_GE(units, 4);
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

// Defaults to the translation: the method options of `fogpipe run` with no options, the scratch
// folder the output folder, and the hash of the default text.
TEST(RunConfig, TheDefaultOptionsGiveTheDefaultMethodAndHash) {
  RunConfig config;
  config.output_dir = "out";
  CampaignOptions options;
  std::string error;
  ASSERT_TRUE(ToCampaignOptions(config, &options, &error)) << error;
  EXPECT_EQ(options.method.component.ar.max_order, 20);
  EXPECT_EQ(options.method.emd.fixed_sifts, 10);
  EXPECT_EQ(options.scratch_dir, "out");
  EXPECT_FALSE(options.model.has_value());
  EXPECT_EQ(options.config_toml, EffectiveConfigToml(config));
}

// BIC tries every order up to the largest of the three AR orders, so a fixed order (of the
// components or of method 2) above --max-ar-order is still among those tried.
TEST(RunConfig, TheLargestOfTheThreeArOrdersBoundsTheOrdersTried) {
  for (const auto& [max_ar_order, ar_order, direct_ar_order, expected] :
       {std::tuple{20, 0, 0, 20}, {20, 30, 0, 30}, {20, 0, 40, 40}, {20, 30, 25, 30}}) {
    RunConfig config;
    config.output_dir = "out";
    config.max_ar_order = max_ar_order;
    config.ar_order = ar_order;
    config.direct_ar_order = direct_ar_order;
    CampaignOptions options;
    std::string error;
    ASSERT_TRUE(ToCampaignOptions(config, &options, &error)) << error;
    EXPECT_EQ(options.method.component.ar.max_order, expected);
    EXPECT_EQ(options.method.component.ar.fixed_order, ar_order);
    EXPECT_EQ(options.method.direct_ar_order, direct_ar_order);
  }
}

// A RunConfig filled other than through CLI11 (which checks the spellings) still cannot carry a
// choice outside the list: the error names the option and its choices.
TEST(RunConfig, AChoiceOutsideItsListIsRefusedNamingTheChoices) {
  RunConfig config;
  config.output_dir = "out";
  config.noise_id = "allantools";
  CampaignOptions options;
  std::string error;
  EXPECT_FALSE(ToCampaignOptions(config, &options, &error));
  EXPECT_EQ(error, "--noise-id: expected calibrated or stable32, got 'allantools'");
  config = RunConfig{};
  config.ar_estimator = "lsq";
  EXPECT_FALSE(ToCampaignOptions(config, &options, &error));
  EXPECT_EQ(error,
            "--ar-estimator: expected burg, least_squares_qr, yule_walker or "
            "maximum_likelihood, got 'lsq'");
  config = RunConfig{};
  config.memory_budget = "lots";
  EXPECT_FALSE(ToCampaignOptions(config, &options, &error));
  EXPECT_EQ(error, "--memory-budget: expected auto or a size such as 512M or 2G, got 'lots'");
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

// ---- The --config file

// `fogpipe run`'s options on a command named run, beside a sweep command that also reads
// --config, as in the binary. Read() writes `text` to a file and applies it after the command
// line `args`.
class ConfigFile : public ::testing::Test {
 protected:
  ~ConfigFile() override { unlink(path.c_str()); }

  bool Read(const std::string& text, std::vector<std::string> args = {}) {
    {
      std::ofstream file(path);
      file << text;
    }
    config = RunConfig{};
    CLI::App top;
    CLI::App* run = top.add_subcommand("run");
    AddRunOptions(run, &config);
    CLI::App* sweep = top.add_subcommand("sweep");
    sweep->add_option("--config", sweep_config);
    args.insert(args.begin(), "run");
    Parse(&top, args);
    error.clear();
    return ApplyConfigFile(run, path, &error);
  }

  const std::string path = "/tmp/fogpipe-config-file-test-" + std::to_string(getpid()) + ".toml";
  RunConfig config;
  std::string sweep_config;
  std::string error;
};

TEST_F(ConfigFile, AFlatFileOfLongOptionNamesSetsTheOptions) {
  ASSERT_TRUE(
      Read("# campaign 7\nq-scale = 2.0 # doubled\n\nthreads = 3\nsmooth = true\n"
           "taus = \"decade\"\n"))
      << error;
  EXPECT_EQ(config.q_scale, 2.0);
  EXPECT_EQ(config.threads, 3);
  EXPECT_TRUE(config.smooth);
  EXPECT_EQ(config.taus, "decade");
}

// A flat config file of the form CLI11's reader accepted gives the configuration the same options
// give on the command line, so the file and the flags share one rerun key.
TEST_F(ConfigFile, AFlatFileGivesTheConfigurationHashOfTheSameCommandLine) {
  ASSERT_TRUE(
      Read("", {"--q-scale", "2.0", "--r-scale", "0.5", "--taus", "decade", "--emd-sifts", "12",
                "--smooth", "--threads", "1", "--memory-budget", "512M", "--noise-id", "stable32"}))
      << error;
  const std::string from_flags = io::Sha256Hex(EffectiveConfigToml(config));
  ASSERT_TRUE(
      Read("# a campaign config as users wrote it for CLI11\nq-scale = 2.0\n"
           "r-scale = 0.5 # halved\ntaus = \"decade\"\nemd-sifts = 12\nsmooth = true\n"
           "threads = 1\nmemory-budget = \"512M\"\nnoise-id = \"stable32\"\n"))
      << error;
  EXPECT_EQ(io::Sha256Hex(EffectiveConfigToml(config)), from_flags);
  EXPECT_NE(from_flags, io::Sha256Hex(EffectiveConfigToml(RunConfig{})));
}

// [run] holds the options as the top level does; in TOML a dotted key run.q or an inline table
// run = {...} is the same table.
TEST_F(ConfigFile, TheRunSectionHoldsTheOptionsAsTheTopLevelDoes) {
  ASSERT_TRUE(Read("threads = 2\n[run]\nq-scale = 2.0\nnoise-id = \"stable32\"\n")) << error;
  EXPECT_EQ(config.threads, 2);
  EXPECT_EQ(config.q_scale, 2.0);
  EXPECT_EQ(config.noise_id, "stable32");
  ASSERT_TRUE(Read("run.r-scale = 3.0\n")) << error;
  EXPECT_EQ(config.r_scale, 3.0);
  ASSERT_TRUE(Read("run = { max-imfs = 4, smooth = true }\n")) << error;
  EXPECT_EQ(config.max_imfs, 4);
  EXPECT_TRUE(config.smooth);
}

// One file can serve run and sweep: each reads its own section and skips the other's.
TEST_F(ConfigFile, TheSweepSectionIsLeftToSweep) {
  ASSERT_TRUE(Read("[run]\nq-scale = 2.0\n[sweep]\nar-order = [2, 4, 8]\n")) << error;
  EXPECT_EQ(config.q_scale, 2.0);
  EXPECT_EQ(config.ar_order, 0);
}

// Any other table would lose its keys silently: it is an error that names it and says where the
// options go.
TEST_F(ConfigFile, AnyOtherTableIsAnErrorNamingIt) {
  EXPECT_FALSE(Read("[kalman]\nq-scale = 2.0\n"));
  EXPECT_EQ(error, path +
                       ":1:2: [kalman] is not a section of fogpipe run: its options go at the top "
                       "of the file or under [run]");
  EXPECT_FALSE(Read("[run.kalman]\nq-scale = 2.0\n"));
  EXPECT_EQ(error, path +
                       ":1:6: [run.kalman] is not a section of fogpipe run: its options go at the "
                       "top of the file or under [run]");
}

TEST_F(ConfigFile, AKeyBothAtTheTopAndInTheSectionIsAnError) {
  EXPECT_FALSE(Read("q-scale = 2.0\n[run]\nq-scale = 3.0\n"));
  EXPECT_EQ(error, path + ":3:1: 'q-scale' is given twice: at the top of the file and in [run]");
}

TEST_F(ConfigFile, ListsAreTomlArraysAcrossLinesWithComments) {
  ASSERT_TRUE(Read("inputs = [\n  \"a.h5\",\n  # the second day\n  'b \"day 2\".h5',\n]\n"))
      << error;
  EXPECT_EQ(config.inputs, (std::vector<std::string>{"a.h5", "b \"day 2\".h5"}));
  ASSERT_TRUE(Read("inputs = \"one.h5\"\n")) << error;
  EXPECT_EQ(config.inputs, (std::vector<std::string>{"one.h5"}));
}

// TOML's other spellings of numbers and strings mean what TOML says (the TOML subset read before
// took 1_000 and 0o17 for text, and kept a literal string's quotes and a basic string's escapes).
TEST_F(ConfigFile, NumbersAndStringsInEveryTomlSpellingAreReadAsTomlDefinesThem) {
  ASSERT_TRUE(
      Read("max-nan-gap = 1_000\nemd-sifts = 0x10\nmax-imfs = 0o17\nar-order = 0b101\n"
           "q = 1e-9\nr = +2.5E-8\nq-scale = 1_000.5\nr-scale = 3\n"
           "model = 'C:\\models\\thermal.json'\ntaus = \"\"\"\ndecade\"\"\"\n"
           "noise-id = '''stable32'''\n"
           "manifest = \"a\\\"b\\tc\\u00e9\"\n"))
      << error;
  EXPECT_EQ(config.max_nan_gap, 1000);
  EXPECT_EQ(config.emd_sifts, 16);
  EXPECT_EQ(config.max_imfs, 15);
  EXPECT_EQ(config.ar_order, 5);
  EXPECT_EQ(config.q, 1e-9);
  EXPECT_EQ(config.r, 2.5e-8);
  EXPECT_EQ(config.q_scale, 1000.5);
  EXPECT_EQ(config.r_scale, 3.0);
  EXPECT_EQ(config.model, "C:\\models\\thermal.json");
  EXPECT_EQ(config.taus, "decade");
  EXPECT_EQ(config.noise_id, "stable32");
  EXPECT_EQ(config.manifest, "a\"b\tc\xc3\xa9");
}

// A syntax error, a key given twice included, is reported where it is, in the editors' form.
TEST_F(ConfigFile, ASyntaxErrorNamesFileLineAndColumn) {
  EXPECT_FALSE(Read("q-scale = = 2\n"));
  EXPECT_EQ(error, path + ":1:11: Error while parsing value: could not determine value type");
  EXPECT_FALSE(Read("q-scale = 2.0\nq-scale = 3.0\n"));
  EXPECT_EQ(error, path +
                       ":2:11: Error while parsing key-value pair: cannot redefine existing "
                       "floating-point 'q-scale'");
  EXPECT_FALSE(Read("\ntaus = \"decade\n"));
  EXPECT_EQ(error.rfind(path + ":2:15: Error while parsing string: ", 0), 0u) << error;
}

TEST_F(ConfigFile, AnUnknownKeyIsAnErrorNamingFileLineAndKey) {
  EXPECT_FALSE(Read("q-scale = 2.0\nqscale = 2.0\n"));
  EXPECT_EQ(error, path + ":2:1: unknown configuration key 'qscale'");
  EXPECT_FALSE(Read("config = \"other.toml\"\n"));
  EXPECT_EQ(error, path + ":1:1: unknown configuration key 'config'");
}

// Values are typed: a number is not read from a string, nor an integer from a float, nor a flag
// from a string. An integer is a valid number.
TEST_F(ConfigFile, AValueOfTheWrongTypeIsAnErrorNamingTheKeyAndTheExpectedType) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"q = \"abc\"", ":1:5: q: expected a number, got a string"},
      {"q = \"1e-9\"", ":1:5: q: expected a number, got a string"},
      {"threads = 1.5", ":1:11: threads: expected an integer, got a float"},
      {"smooth = \"yes\"", ":1:10: smooth: expected true or false, got a string"},
      {"taus = 3", ":1:8: taus: expected a string, got an integer"},
      {"q-scale = [2.0, 3.0]", ":1:11: q-scale: expected a number, got an array"},
      {"q = 1979-05-27", ":1:5: q: expected a number, got a date or time"},
      {"inputs = [\"a.h5\", 2]",
       ":1:10: inputs: expected a string or an array of strings, got an array holding an "
       "integer"},
  };
  for (const auto& [text, message] : cases) {
    EXPECT_FALSE(Read(text + "\n")) << text;
    EXPECT_EQ(error, path + message);
  }
}

// The options' own checks (ranges, choices) hold for the file as for the command line.
TEST_F(ConfigFile, AValueTheOptionRejectsIsAnErrorNamingTheOption) {
  EXPECT_FALSE(Read("threads = 99999\n"));
  EXPECT_EQ(error, path + ":1:11: --threads: Value 99999 not in range 0 to 4096");
  EXPECT_FALSE(Read("noise-id = \"allantools\"\n"));
  EXPECT_EQ(error, path + ":1:12: --noise-id: allantools not in {calibrated,stable32}");
}

TEST_F(ConfigFile, TheCommandLineWinsOverTheFile) {
  ASSERT_TRUE(Read("q-scale = 2.0\nr-scale = 3.0\n[run]\ninputs = [\"file.h5\"]\n",
                   {"--q-scale", "5", "cli.h5"}))
      << error;
  EXPECT_EQ(config.q_scale, 5.0);
  EXPECT_EQ(config.r_scale, 3.0);
  EXPECT_EQ(config.inputs, (std::vector<std::string>{"cli.h5"}));
}

// Sweep's grids are single texts ("2:12", "0.1,1,10"): a TOML array is joined with ','.
TEST(ConfigFileGrids, AGridGivenAsATomlArrayIsTheCommaListItSpellsOnTheCommandLine) {
  const std::string path = "/tmp/fogpipe-config-grid-test-" + std::to_string(getpid()) + ".toml";
  {
    std::ofstream file(path);
    file << "ar-order = [2, 4, 8]\nq-scale = [0.5, 1, 10]\nr-scale = \"0.1:10:5\"\n";
  }
  CLI::App app;
  std::string ar_order, q_scale, r_scale;
  app.add_option("--ar-order", ar_order);
  app.add_option("--q-scale", q_scale);
  app.add_option("--r-scale", r_scale);
  Parse(&app, {});
  std::string error;
  EXPECT_TRUE(ApplyConfigFile(&app, path, &error, {"ar-order", "q-scale", "r-scale"})) << error;
  EXPECT_EQ(ar_order, "2,4,8");
  EXPECT_EQ(q_scale, "0.5,1,10");
  EXPECT_EQ(r_scale, "0.1:10:5");
  unlink(path.c_str());
}

// ---- The configuration text, read by toml++

// Values that a writer of TOML gets wrong most easily, each within its option's range.
RunConfig AwkwardValues() {
  RunConfig c;
  c.inputs = {"a \"quoted\" name.h5", "C:\\data\\day 2.h5", "tab\there", "\xc3\xa9.h5"};
  c.manifest = "line\nbreak";
  c.output_dir = "\\\\server\\share";
  c.drop_start_s = 1e-300;
  c.band_limit_ratio = 0.1;
  c.q = -2.5e-9;
  c.r = 4.9406564584124654e-324;
  c.q_scale = 1.7976931348623157e308;
  c.r_scale = 0.1;
  c.smooth = true;
  c.taus = "";
  c.model = "\x7f\x01 control \"\\";
  return c;
}

// Whether TOML value `node` holds exactly the option's value in `config` (a double to the bit).
bool HoldsExactly(const toml::node& node, const RunConfig& config,
                  const RunOption::Member& member) {
  return std::visit(
      [&](auto pointer) {
        const auto& value = config.*pointer;
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, double>) {
          const std::optional<double> read = node.value_exact<double>();
          return read && std::memcmp(&*read, &value, sizeof(double)) == 0;
        } else if constexpr (std::is_same_v<T, int>) {
          return node.value_exact<std::int64_t>() == std::optional<std::int64_t>(value);
        } else if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::string>) {
          return node.value_exact<T>() == std::optional<T>(value);
        } else {
          const toml::array* array = node.as_array();
          if (array == nullptr || array->size() != value.size()) return false;
          for (std::size_t i = 0; i < value.size(); ++i) {
            if ((*array)[i].value_exact<std::string>() != std::optional<std::string>(value[i])) {
              return false;
            }
          }
          return true;
        }
      },
      member);
}

// Every line the canonical writer produces, for every row (hashed or not), is TOML that toml++
// reads back to exactly the value of the RunConfig: floats to the bit (1e-300, 0.1, -0.0, the
// smallest subnormal, the largest double, negative ones), strings with quotes, backslashes,
// control characters and UTF-8, negative integers, empty and non-empty lists.
TEST(ConfigurationText, EveryLineParsesWithTomlPlusPlusToExactlyTheValueWritten) {
  RunConfig negative = AwkwardValues();
  negative.inputs = {};
  negative.r_scale = -0.0;
  negative.q_scale = -1e-300;
  negative.max_ar_order = -2147483647 - 1;
  negative.shard = -3;
  for (const RunConfig& config : {RunConfig{}, AwkwardValues(), negative}) {
    std::string text;
    for (const RunOption& option : RunOptions()) text += ConfigTomlLine(config, option);
    toml::table table;
    ASSERT_NO_THROW(table = toml::parse(text)) << text;
    for (const RunOption& option : RunOptions()) {
      const toml::node* node = table.get(option.key);
      ASSERT_NE(node, nullptr) << option.key;
      EXPECT_TRUE(HoldsExactly(*node, config, option.member)) << ConfigTomlLine(config, option);
    }
    EXPECT_EQ(table.size(), RunOptions().size());
  }
  EXPECT_EQ(ConfigTomlLine(AwkwardValues(), RunOptions()[0]),
            "inputs = [\"a \\\"quoted\\\" name.h5\", \"C:\\\\data\\\\day 2.h5\", "
            "\"tab\\u0009here\", \"\xc3\xa9.h5\"]\n");
}

// Through fogpipe's own reader too: the hashed text of awkward floats and strings is a --config
// file that gives the same text back.
TEST(ConfigurationText, ReadAsAConfigFileItGivesTheSameTextBack) {
  const std::string text = EffectiveConfigToml(AwkwardValues());
  const std::string path = "/tmp/fogpipe-config-text-test-" + std::to_string(getpid()) + ".toml";
  {
    std::ofstream file(path);
    file << text;
  }
  CLI::App app;
  RunConfig reread;
  AddRunOptions(&app, &reread);
  Parse(&app, {});
  std::string error;
  EXPECT_TRUE(ApplyConfigFile(&app, path, &error)) << error;
  EXPECT_EQ(EffectiveConfigToml(reread), text);
  unlink(path.c_str());
}

}  // namespace
}  // namespace fogpipe::graph
