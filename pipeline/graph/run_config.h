// `fogpipe run` options: the command-line/TOML surface, its translation into the method's
// options, and the effective configuration text whose SHA-256 is the rerun key.
#pragma once

#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "pipeline/graph/campaign.h"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace fogpipe::graph {

/// Everything `fogpipe run` accepts, with its defaults; the options themselves are RunOptions().
struct RunConfig {
  std::vector<std::string> inputs;
  std::string manifest;
  int shard = 0;                    ///< This process's shard of the input list, in [0, num_shards).
  int num_shards = 1;               ///< Given explicitly (never from SLURM_ARRAY_TASK_COUNT).
  std::string shard_by = "stride";  ///< "stride" or "size" (io::ShardBy).
  std::string output_dir;
  /// Where the IMFs wait between the decomposition and the results file; "": the output folder.
  std::string scratch_dir;
  std::string config_file;
  int threads = 0;  ///< 0: SLURM_CPUS_PER_TASK if set, else the hardware's
  std::string memory_budget = "auto";
  bool dry_run = false;
  bool force = false;
  // Method (these enter the configuration hash).
  double drop_start_s = 0.0;
  int max_nan_gap = 10;
  int max_ar_order = 20;
  int ar_order = 0;
  std::string ar_estimator = "burg";
  int emd_sifts = 10;
  std::string emd_stop_rule = "fixed_sifts";
  /// method::BandLimitOptions::cutoff_ratio (0: EMD's IMFs as they are, the paper's method).
  double band_limit_ratio = method::BandLimitOptions().cutoff_ratio;
  int max_imfs = 0;
  double q = -1.0;
  double r = -1.0;
  /// How each component's Kalman q and R follow from its white-noise share (white_noise.h).
  std::string noise_rule = "share";
  double q_scale = 1.0;
  double r_scale = 1.0;
  bool smooth = false;
  std::string imf_storage = "float32";
  bool store_filtered_imfs = false;
  int direct_ar_order = 0;
  std::string taus = "octave";
  /// Noise identification behind the Allan intervals (algorithms/allan/noise_id.h).
  std::string noise_id = "calibrated";
  std::string model;
};

/// One option of `fogpipe run`, declared once: the command line, the TOML config file, the hashed
/// configuration text, RunConfig and the campaign options are all made from the table of these
/// (RunOptions()), so adding an option is adding one row.
struct RunOption {
  using Member = std::variant<std::vector<std::string> RunConfig::*, std::string RunConfig::*,
                              int RunConfig::*, double RunConfig::*, bool RunConfig::*>;
  /// Puts an option's value of type T into the campaign options; returns "" or, for a value
  /// outside its domain, the error. (common_type_t: T is deduced from the member alone, so a
  /// lambda converts.)
  template <typename T>
  using ApplyValue = std::string (*)(const std::common_type_t<T>& value, CampaignOptions* options);
  /// CLI11's names: "--q", "-o,--output", or "inputs" (the positional argument).
  std::string names;
  /// The long name without dashes: the TOML key and the name in the hashed configuration.
  std::string key;
  /// Where the value goes; its default is RunConfig's. A bool member is a flag.
  Member member;
  /// Where the value goes in the campaign options (ToCampaignOptions); empty for the options that
  /// only say which recordings to read (inputs, manifest, the shards) or where other values come
  /// from (config), which `run` itself acts on.
  std::function<std::string(const RunConfig&, CampaignOptions*)> apply;
  std::string help;
  /// The unit of a quantity, shown at the end of its --help line ("" for none).
  std::string unit;
  /// The accepted spellings of a choice (checked by CLI11); empty for any value.
  std::vector<std::string> choices;
  /// Any other check of the value (a range, an existing folder); null for none.
  void (*check)(CLI::Option*);
  /// The option can change a number in a results file: it enters the configuration hash
  /// (EffectiveConfigToml), so a rerun with another value redoes the file.
  bool hashed;
  /// A valid value other than the default ("" for a flag: giving it changes the value), for the
  /// test that every hashed option changes the hash.
  std::string changed;

  template <typename T>
  RunOption(std::string names_, std::string key_, T RunConfig::*member_, ApplyValue<T> apply_,
            std::string help_, std::string unit_ = "", std::vector<std::string> choices_ = {},
            void (*check_)(CLI::Option*) = nullptr, bool hashed_ = false, std::string changed_ = "")
      : names(std::move(names_)),
        key(std::move(key_)),
        member(member_),
        help(std::move(help_)),
        unit(std::move(unit_)),
        choices(std::move(choices_)),
        check(check_),
        hashed(hashed_),
        changed(std::move(changed_)) {
    if (apply_ != nullptr) {
      apply = [member_, apply_](const RunConfig& config, CampaignOptions* options) {
        return apply_(config.*member_, options);
      };
    }
  }
};

/// Every option of `fogpipe run`, in --help order; the hashed ones in the order of
/// EffectiveConfigToml.
const std::vector<RunOption>& RunOptions();

/// Registers the options of `run` on `cmd`, bound to `config`: every one, or those whose keys
/// are listed (another command sharing them, such as sweep's --threads).
void AddRunOptions(CLI::App* cmd, RunConfig* config, const std::vector<std::string>& keys = {});

/// Applies a TOML file to the options of `cmd` that were not given on the command line (the
/// command line wins). Its keys are the long option names (or a positional argument's name, such
/// as run's `inputs`), at the top of the file or in the table named after the command (`[run]`);
/// the tables of the other commands that read --config are skipped, any other table is an error.
/// Values are typed: a list option takes an array, and each key of `comma_lists` (a single text
/// such as sweep's "2:12" or "0.1,1,10") takes an array joined with ','. Returns false with
/// *error "FILE:LINE:COLUMN: ..." for a syntax error, an unknown key, a value of the wrong type or
/// one the option rejects.
bool ApplyConfigFile(CLI::App* cmd, const std::string& path, std::string* error,
                     const std::vector<std::string>& comma_lists = {});

/// One option's `key = value` line, as EffectiveConfigToml writes it (for any row, hashed or not):
/// floats as %.17g with a '.' or an exponent, strings as TOML basic strings.
std::string ConfigTomlLine(const RunConfig& config, const RunOption& option);

/// The options that change numbers, as TOML in a fixed order (itself a valid --config file). The
/// text is written here rather than by toml++, whose writer orders keys alphabetically and
/// formats floats otherwise: its SHA-256 is every results file's rerun key (docs/dependencies.md).
std::string EffectiveConfigToml(const RunConfig& config);

/// Translates the configuration into campaign options (method, storage, threads, budget, hash):
/// every option's `apply`, then the steps that join several options. Returns false with *error
/// for a value out of its domain.
bool ToCampaignOptions(const RunConfig& config, CampaignOptions* options, std::string* error);

/// --threads 0: SLURM_CPUS_PER_TASK when set and positive, else the hardware concurrency.
int ResolveThreads(int requested);

}  // namespace fogpipe::graph
