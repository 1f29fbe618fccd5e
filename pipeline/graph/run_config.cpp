#include "pipeline/graph/run_config.h"

#include <toml++/toml.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <thread>
#include <tuple>
#include <type_traits>

#include "pipeline/graph/memory_budget.h"
#include "pipeline/io/inputs.h"
#include "pipeline/io/model_history.h"
#include "pipeline/io/results_layout.h"
#include "pipeline/io/results_writer.h"
#include "pipeline/io/sha256.h"

namespace fogpipe::graph {
namespace {

/// --threads' upper bound, also applied to SLURM_CPUS_PER_TASK.
constexpr long kMaxThreads = 4096;

std::string Number(double value) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", value);
  std::string out = text;
  // TOML floats need a '.' or an exponent.
  if (out.find_first_of(".eEn") == std::string::npos) out += ".0";
  return out;
}

// A TOML basic string. Control characters, which TOML allows only escaped, are written as \uXXXX;
// every other byte as it is, so the text of a string without them is what it always was.
std::string Quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
    } else if ((c >= 0 && c < 0x20) || c == 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\u%04x", static_cast<unsigned>(c));
      out += escaped;
      continue;
    }
    out += c;
  }
  return out + "\"";
}

// The choices of the enumerated options, each spelled by its own ToString.
constexpr ar::Estimator kEstimators[] = {ar::Estimator::kBurg, ar::Estimator::kLeastSquaresQr,
                                         ar::Estimator::kYuleWalker,
                                         ar::Estimator::kMaximumLikelihood};
constexpr emd::StopRule kStopRules[] = {emd::StopRule::kFixedSifts, emd::StopRule::kCauchy,
                                        emd::StopRule::kSNumber, emd::StopRule::kRilling};
constexpr method::ComponentNoiseRule kNoiseRules[] = {
    method::ComponentNoiseRule::kShareOfInnovation, method::ComponentNoiseRule::kInnovationMatch};
constexpr io::ImfStorage kImfStorages[] = {io::ImfStorage::kFloat32, io::ImfStorage::kFloat64,
                                           io::ImfStorage::kNone};
constexpr allan::NoiseIdRule kNoiseIdRules[] = {allan::NoiseIdRule::kCalibrated,
                                                allan::NoiseIdRule::kStable32};

template <typename Enum, std::size_t N>
std::vector<std::string> Names(const Enum (&values)[N]) {
  std::vector<std::string> names;
  for (Enum value : values) names.push_back(ToString(value));
  return names;
}

// The value whose ToString is `name`; false if none.
template <typename Enum, std::size_t N>
bool FromName(const std::string& name, const Enum (&values)[N], Enum* value) {
  for (Enum v : values) {
    if (name == ToString(v)) {
      *value = v;
      return true;
    }
  }
  return false;
}

// Sets *value to the choice spelled `name`; "" or "--key: expected a, b or c, got 'x'". CLI11
// checks the spelling on the command line and in a config file; this catches a RunConfig that was
// filled otherwise.
template <typename Enum, std::size_t N>
std::string Choose(const std::string& key, const std::string& name, const Enum (&values)[N],
                   Enum* value) {
  if (FromName(name, values, value)) return "";
  const std::vector<std::string> choices = Names(values);
  std::string list;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    list += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
  }
  return "--" + key + ": expected " + list + ", got '" + name + "'";
}

template <typename T, T kLo, T kHi>
void InRange(CLI::Option* option) {
  option->check(CLI::Range(kLo, kHi));
}
void NonNegative(CLI::Option* option) { option->check(CLI::NonNegativeNumber); }
void Positive(CLI::Option* option) { option->check(CLI::PositiveNumber); }
void ExistingFolder(CLI::Option* option) { option->check(CLI::ExistingDirectory); }
void Ratio(CLI::Option* option) { option->check(CLI::Range(0.0, 1.0)); }

// The value of `member` in `config` as TOML.
std::string TomlValue(const RunConfig& config, const RunOption::Member& member) {
  return std::visit(
      [&](auto pointer) -> std::string {
        const auto& value = config.*pointer;
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, double>) {
          return Number(value);
        } else if constexpr (std::is_same_v<T, int>) {
          return std::to_string(value);
        } else if constexpr (std::is_same_v<T, bool>) {
          return value ? "true" : "false";
        } else if constexpr (std::is_same_v<T, std::string>) {
          return Quoted(value);
        } else {
          std::string list = "[";
          for (std::size_t i = 0; i < value.size(); ++i)
            list += (i == 0 ? "" : ", ") + Quoted(value[i]);
          return list + "]";
        }
      },
      member);
}

// Puts a value where it goes; "" for no error: the ranges are checked by CLI11 (the check column)
// and, for the method, after every row by MethodOptions::IsValid.
template <typename Field, typename Value>
std::string Store(Field* field, const Value& value) {
  *field = value;
  return "";
}

// The option table, in groups of related options. The columns: names, key, member, apply (where
// the value goes in CampaignOptions), help, unit, choices, check, hashed, changed (a valid
// non-default value for the hash test). The groups follow each other in --help order, which is
// also the order of the hashed text that earlier results files hold.
using C = RunConfig;
using O = CampaignOptions;
using Rows = std::vector<RunOption>;

// Which recordings, and where the results and the other options come from. None of them can
// change a number: `run` itself reads the inputs and the config file.
Rows InputOutputOptions() {
  return {
      {"inputs", "inputs", &C::inputs, nullptr,
       "Recordings: files, folders (recursive *.h5) or quoted glob patterns"},
      {"--manifest", "manifest", &C::manifest, nullptr,
       "File with one recording path per line ('#' comments; optional size column)"},
      {"--shard",
       "shard",
       &C::shard,
       nullptr,
       "Process only shard I of the sorted input list (Slurm arrays)",
       "",
       {},
       NonNegative},
      {"--num-shards",
       "num-shards",
       &C::num_shards,
       nullptr,
       "Number of shards N; pass it explicitly (SLURM_ARRAY_TASK_COUNT changes when only failed "
       "indices are resubmitted)",
       "",
       {},
       Positive},
      {"--shard-by", "shard-by", &C::shard_by, nullptr,
       "stride (every N-th file) or size (balanced by bytes)"},
      {"-o,--output", "output", &C::output_dir,
       [](const std::string& v, O* o) { return Store(&o->output_dir, v); },
       "Output folder (one results file per recording)"},
      {"--scratch-dir",
       "scratch-dir",
       &C::scratch_dir,
       [](const std::string& v, O* o) { return Store(&o->scratch_dir, v); },
       "Folder for the IMFs between the decomposition and the results file, about 8 bytes per "
       "sample per IMF, removed as each recording ends (empty: the output folder; on a cluster, "
       "node-local scratch such as $TMPDIR)",
       "",
       {},
       ExistingFolder},
      {"--config", "config", &C::config_file, nullptr,
       "TOML file of options: keys are the long option names, at the top or under [run]; unknown "
       "keys are errors"},
  };
}

// How to schedule (results are identical whatever the thread count, checked by the campaign test)
// and whether to run at all: outside the hash.
Rows ScheduleOptions() {
  return {
      {"--threads",
       "threads",
       &C::threads,
       [](const int& v, O* o) { return Store(&o->threads, ResolveThreads(v)); },
       "Worker threads (0: SLURM_CPUS_PER_TASK if set, else all cores)",
       "",
       {},
       InRange<long, 0, kMaxThreads>},
      {"--memory-budget", "memory-budget", &C::memory_budget,
       [](const std::string& v, O* o) -> std::string {
         const auto budget =
             v == "auto" ? std::optional<std::uint64_t>(AutoMemoryBudgetBytes()) : ParseByteSize(v);
         if (!budget) {
           return "--memory-budget: expected auto or a size such as 512M or 2G, got '" + v + "'";
         }
         o->memory_budget_bytes = *budget;
         return "";
       },
       "Memory for recordings in flight, e.g. 512M, 8G, or auto (default: 80 % of "
       "SLURM_MEM_PER_NODE, else half the physical memory)"},
      {"--dry-run", "dry-run", &C::dry_run,
       [](const bool& v, O* o) { return Store(&o->dry_run, v); },
       "List what would be done; write nothing"},
      {"--force", "force", &C::force, [](const bool& v, O* o) { return Store(&o->force, v); },
       "Redo files whose results exist with the same configuration"},
  };
}

// Reading the recording and the AR models of its components.
Rows PreprocessingAndArOptions() {
  return {
      {"--drop-start-s",
       "drop-start-s",
       &C::drop_start_s,
       [](const double& v, O* o) { return Store(&o->method.preprocess.drop_start_s, v); },
       "Time dropped at the start (transient)",
       "s",
       {},
       NonNegative,
       true,
       "12.5"},
      {"--max-nan-gap",
       "max-nan-gap",
       &C::max_nan_gap,
       [](const int& v, O* o) { return Store(&o->read.max_nan_gap_samples, v); },
       "Longest run of NaN samples bridged by interpolation",
       "samples",
       {},
       InRange<int, 0, 1000000>,
       true,
       "7"},
      // Joined with --ar-order and --direct-ar-order by TryEveryFixedArOrder.
      {"--max-ar-order",
       "max-ar-order",
       &C::max_ar_order,
       [](const int& v, O* o) { return Store(&o->method.component.ar.max_order, v); },
       "Largest AR order tried by BIC",
       "",
       {},
       InRange<int, 1, 200>,
       true,
       "13"},
      {"--ar-order",
       "ar-order",
       &C::ar_order,
       [](const int& v, O* o) { return Store(&o->method.component.ar.fixed_order, v); },
       "Fixed AR order of every component (0: by BIC)",
       "",
       {},
       InRange<int, 0, 200>,
       true,
       "3"},
      {"--ar-estimator", "ar-estimator", &C::ar_estimator,
       [](const std::string& v, O* o) {
         return Choose("ar-estimator", v, kEstimators, &o->method.component.ar.estimator);
       },
       "AR estimator", "", Names(kEstimators), nullptr, true, "yule_walker"},
  };
}

// The empirical mode decomposition.
Rows DecompositionOptions() {
  return {
      {"--emd-sifts",
       "emd-sifts",
       &C::emd_sifts,
       [](const int& v, O* o) {
         o->method.emd.fixed_sifts = v;
         o->method.emd.max_sifts = std::max(o->method.emd.max_sifts, v);
         return std::string();
       },
       "Sifts per IMF (fixed_sifts rule)",
       "",
       {},
       InRange<int, 1, 10000>,
       true,
       "17"},
      {"--emd-stop-rule", "emd-stop-rule", &C::emd_stop_rule,
       [](const std::string& v, O* o) {
         return Choose("emd-stop-rule", v, kStopRules, &o->method.emd.stop_rule);
       },
       "EMD sifting stop rule", "", Names(kStopRules), nullptr, true, "rilling"},
      {"--max-imfs",
       "max-imfs",
       &C::max_imfs,
       [](const int& v, O* o) { return Store(&o->method.emd.max_imfs, v); },
       "Maximum number of IMFs (0: until monotonic)",
       "",
       {},
       InRange<int, 0, 1000>,
       true,
       "5"},
      {"--band-limit-ratio",
       "band-limit-ratio",
       &C::band_limit_ratio,
       [](const double& v, O* o) { return Store(&o->method.band_limit.cutoff_ratio, v); },
       "Each IMF's content below this / its mean period (cycles per sample) moves to the next "
       "component before modelling; 0: EMD's IMFs as they are (the paper's)",
       "cycles per mean period",
       {},
       Ratio,
       true,
       "0.35"},
  };
}

// Each component's Kalman filter.
Rows KalmanOptions() {
  return {
      {"--q",
       "q",
       &C::q,
       [](const double& v, O* o) { return Store(&o->method.component.kalman.q, v); },
       "Kalman process-noise variance (<0: default rule)",
       "(rad/s)^2",
       {},
       nullptr,
       true,
       "1e-9"},
      {"--r",
       "r",
       &C::r,
       [](const double& v, O* o) { return Store(&o->method.component.kalman.r, v); },
       "Kalman measurement-noise variance (<0: white-noise rule)",
       "(rad/s)^2",
       {},
       nullptr,
       true,
       "2e-8"},
      {"--noise-rule", "noise-rule", &C::noise_rule,
       [](const std::string& v, O* o) {
         return Choose("noise-rule", v, kNoiseRules, &o->method.component.noise_rule);
       },
       "How each IMF's Kalman q and R follow from its white-noise share: share (default) or "
       "innovation (see schemas/results-v2.md)",
       "", Names(kNoiseRules), nullptr, true, "innovation"},
      {"--q-scale",
       "q-scale",
       &C::q_scale,
       [](const double& v, O* o) { return Store(&o->method.component.kalman.q_scale, v); },
       "Multiplier of q",
       "",
       {},
       Positive,
       true,
       "2"},
      {"--r-scale",
       "r-scale",
       &C::r_scale,
       [](const double& v, O* o) { return Store(&o->method.component.kalman.r_scale, v); },
       "Multiplier of R",
       "",
       {},
       Positive,
       true,
       "3"},
      {"--smooth",
       "smooth",
       &C::smooth,
       [](const bool& v, O* o) { return Store(&o->method.component.kalman.smooth, v); },
       "Use the RTS smoother output instead of the filter's (method 1 components whose record "
       "contradicts their model in the smoother's direction keep the filter's; Table 3 names them)",
       "",
       {},
       nullptr,
       true},
  };
}

// What the results file holds besides the tables, and method 2.
Rows StorageAndDirectArOptions() {
  return {
      {"--imf-storage", "imf-storage", &C::imf_storage,
       [](const std::string& v, O* o) {
         return Choose("imf-storage", v, kImfStorages, &o->results.imf_storage);
       },
       "How the stored IMFs, residue and filtered components are kept: float32 (default; "
       "rounding 6e-8 relative), float64 (exact) or none. Only the stored copy: the models, "
       "filters and Allan tables are computed from doubles before storage",
       "", Names(kImfStorages), nullptr, true, "none"},
      {"--store-filtered-imfs",
       "store-filtered-imfs",
       &C::store_filtered_imfs,
       [](const bool& v, O* o) { return Store(&o->results.store_filtered_imfs, v); },
       "Also store every filtered component",
       "",
       {},
       nullptr,
       true},
      {"--direct-ar-order",
       "direct-ar-order",
       &C::direct_ar_order,
       [](const int& v, O* o) { return Store(&o->method.direct_ar_order, v); },
       "Method 2's AR order (0: by BIC; the paper used 6)",
       "",
       {},
       InRange<int, 0, 200>,
       true,
       "6"},
  };
}

// The Allan tables and the deterministic model subtracted before everything else.
Rows AllanAndModelOptions() {
  return {
      {"--taus",
       "taus",
       &C::taus,
       [](const std::string& v, O* o) {
         std::string error;
         return allan::ParseTauGrid(v, &o->method.allan.grid, &error) ? "" : error;
       },
       "Allan tau grid: octave, decade (10 per decade), decade:K, all, or log10 (allantools' "
       "taus='log10')",
       "",
       {},
       nullptr,
       true,
       "decade"},
      {"--noise-id", "noise-id", &C::noise_id,
       [](const std::string& v, O* o) {
         allan::AllanOptions& allan = o->method.allan;
         const std::string error = Choose("noise-id", v, kNoiseIdRules, &allan.noise_id);
         // Stable32's bounds come from its noise types and the EDF as Greenhall & Riley printed.
         allan.sampled_phase_edf = allan.noise_id != allan::NoiseIdRule::kStable32;
         return error;
       },
       "Noise identification behind the Allan intervals: calibrated (chosen by measured coverage) "
       "or stable32 (Stable32's Alpha column and EDF convention)",
       "", Names(kNoiseIdRules), nullptr, true, "stable32"},
      // The file itself is read by ReadModelCompensation, once the method options are valid.
      {"--model",
       "model",
       &C::model,
       [](const std::string& v, O* o) {
         o->model.reset();
         if (!v.empty()) o->model.emplace().path = v;
         return std::string();
       },
       "Model file of `compare --save-model`: its deterministic effects are subtracted before the "
       "EMD (thermal terms use each recording's /aux/temperature, aux terms its /aux/<name>)",
       "",
       {},
       nullptr,
       true,
       "thermal.model.json"},
  };
}

// The steps of ToCampaignOptions that join several options.

// Every option's apply, in table order; false with the first error.
bool ApplyEveryOption(const RunConfig& c, CampaignOptions* o, std::string* error) {
  for (const RunOption& option : RunOptions()) {
    if (!option.apply) continue;
    if (std::string problem = option.apply(c, o); !problem.empty()) {
      *error = std::move(problem);
      return false;
    }
  }
  return true;
}

// BIC tries every order up to the largest of --max-ar-order, --ar-order and --direct-ar-order, so
// that a fixed order is always among those tried.
void TryEveryFixedArOrder(method::MethodOptions* m) {
  ar::ArOptions& ar = m->component.ar;
  ar.max_order = std::max(ar.max_order, std::max(ar.fixed_order, m->direct_ar_order));
}

// --model FILE: read once per run; the file is named in every error.
bool ReadModelCompensation(ModelCompensationOptions* m, std::string* error) {
  const std::string& path = m->path;
  if (const std::string problem = io::RegularFileProblem(path); !problem.empty()) {
    *error = "--model " + path + ": needs a model file, but " + problem;
    return false;
  }
  try {
    const io::ModelFile file = io::ReadModelFile(path);
    m->deterministic = file.deterministic;
  } catch (const std::exception& e) {
    *error = std::string("--model: ") + e.what();
    return false;
  }
  std::string sha_error;
  const auto sha = io::Sha256FileHex(path, &sha_error);
  if (!sha) {
    *error = "--model: " + sha_error;
    return false;
  }
  m->sha256 = *sha;
  for (const auto& comp : m->deterministic.components) {
    const std::string channel = model::AuxChannelOf(comp.term);
    m->terms += (m->terms.empty() ? "" : ",") + model::ToString(comp.term);
    if (!channel.empty() &&
        std::find(m->aux_channels.begin(), m->aux_channels.end(), channel) == m->aux_channels.end())
      m->aux_channels.push_back(channel);
  }
  return true;
}

// A budget the machine cannot hold would admit recordings that then swap or are killed.
bool BudgetFitsThisMachine(const std::string& spelled, std::uint64_t budget, std::string* error) {
  const std::uint64_t physical = PhysicalMemoryBytes();
  if (physical > 0 && budget > physical) {
    *error = "--memory-budget " + spelled + " is more than this machine's " +
             std::to_string(physical >> 20) + " MiB of physical memory; give at most that";
    return false;
  }
  return true;
}

// The hashed text and its SHA-256, the rerun key. The model file's content is part of the
// configuration: a changed model redoes every file. A TOML comment keeps config_toml a valid
// --config file.
void HashConfiguration(const RunConfig& c, CampaignOptions* o) {
  o->config_toml = EffectiveConfigToml(c);
  if (o->model) o->config_toml += "# model-sha256 = " + o->model->sha256 + "\n";
  o->config_sha256 = io::Sha256Hex(o->config_toml);
}

// The --config file, read by toml++: where each key is, what it may hold, and the option it sets.

// "FILE:LINE:COLUMN: ", where something in a config file is.
std::string At(const std::string& path, const toml::source_position& where) {
  if (where.line == 0) return path + ": ";
  return path + ":" + std::to_string(where.line) + ":" + std::to_string(where.column) + ": ";
}

bool ParseConfigFile(const std::string& path, toml::table* file, std::string* error) {
  if (const std::string problem = io::RegularFileProblem(path); !problem.empty()) {
    *error = path + ": --config needs a TOML file, but " + problem;
    return false;
  }
  try {
    *file = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    *error = At(path, e.source().begin) + std::string(e.description());
    return false;
  }
  return true;
}

// One `key = value` of a config file.
struct ConfigEntry {
  std::string key;
  const toml::node* value;
  toml::source_position where;  ///< of the key
};

// The sections of the other commands that read --config (sweep's for run, run's for sweep): one
// file may hold both, each command reading its own.
std::vector<std::string> OtherCommandsSections(const CLI::App& cmd) {
  std::vector<std::string> names;
  if (const CLI::App* parent = cmd.get_parent()) {
    for (const CLI::App* other : parent->get_subcommands([](const CLI::App*) { return true; })) {
      if (other != &cmd && other->get_option_no_throw("--config") != nullptr) {
        names.push_back(other->get_name());
      }
    }
  }
  return names;
}

// The table that holds the command's options besides the top level ([run] for `fogpipe run`), and
// the other commands' tables, which are skipped.
struct ConfigSections {
  std::string own;
  std::vector<std::string> skipped;
};

// A table that is neither the command's section nor another command's: named in the error, since
// its keys would otherwise be lost.
std::string NotASection(const std::string& table, const std::string& section) {
  if (section.empty()) return "[" + table + "] holds no options: they go at the top of the file";
  return "[" + table + "] is not a section of fogpipe " + section +
         ": its options go at the top of the file or under [" + section + "]";
}

// The entries of `table` and of the command's own table within it ([run]; a dotted key run.q or an
// inline table run = {...} is the same table in TOML). A key both at the top and in the section is
// an error, as a key given twice is in TOML.
bool CollectTable(const toml::table& table, const std::string& prefix, const std::string& path,
                  const ConfigSections& sections, std::vector<ConfigEntry>* entries,
                  std::string* error) {
  for (auto&& [key, value] : table) {
    const std::string name(key.str());
    if (const toml::table* inner = value.as_table()) {
      const bool top = prefix.empty();
      if (top && !sections.own.empty() && name == sections.own) {
        if (!CollectTable(*inner, name, path, sections, entries, error)) return false;
      } else if (!top || std::find(sections.skipped.begin(), sections.skipped.end(), name) ==
                             sections.skipped.end()) {
        *error = At(path, key.source().begin) +
                 NotASection(top ? name : prefix + "." + name, sections.own);
        return false;
      }
      continue;
    }
    for (const ConfigEntry& seen : *entries) {
      if (seen.key != name) continue;
      *error = At(path, key.source().begin) + "'" + name +
               "' is given twice: at the top of the file and in [" + sections.own + "]";
      return false;
    }
    entries->push_back({name, &value, key.source().begin});
  }
  return true;
}

// The entries in the order of the file, so that the first error reported is the first in it.
bool CollectEntries(const toml::table& file, const std::string& path,
                    const ConfigSections& sections, std::vector<ConfigEntry>* entries,
                    std::string* error) {
  if (!CollectTable(file, "", path, sections, entries, error)) return false;
  std::stable_sort(
      entries->begin(), entries->end(), [](const ConfigEntry& a, const ConfigEntry& b) {
        return std::tie(a.where.line, a.where.column) < std::tie(b.where.line, b.where.column);
      });
  return true;
}

// The option a key sets: --KEY, or the positional argument named KEY (run's inputs, sweep's
// recordings). Not --config itself, nor --help, nor a short name spelled with its dash.
CLI::Option* OptionOfKey(CLI::App* cmd, const std::string& key) {
  if (key.empty() || key[0] == '-' || key == "config" || key == "help") return nullptr;
  if (CLI::Option* option = cmd->get_option_no_throw("--" + key)) return option;
  CLI::Option* positional = cmd->get_option_no_throw(key);
  return positional != nullptr && positional->get_positional() ? positional : nullptr;
}

// What an option takes, as TOML: CLI11's own type of the option (INT, UINT, FLOAT, TEXT; a flag
// takes none), one value or a list.
enum class ValueKind { kBool, kInteger, kNumber, kText };
struct Expected {
  ValueKind kind;
  bool many;        ///< a list option: an array (or one value)
  bool comma_list;  ///< one text spelled FROM:TO or a,b,c: an array joined with ','
};

Expected ExpectedOf(const CLI::Option& option, bool comma_list) {
  if (option.get_expected_min() == 0) return {ValueKind::kBool, false, false};
  const std::string type = option.get_type_name();
  const std::string base = type.substr(0, type.find(':'));
  const ValueKind kind = base == "INT" || base == "UINT" ? ValueKind::kInteger
                         : base == "FLOAT"               ? ValueKind::kNumber
                                                         : ValueKind::kText;
  return {kind, option.get_items_expected_max() > 1, comma_list && kind == ValueKind::kText};
}

std::string KindName(ValueKind kind, bool plural) {
  switch (kind) {
    case ValueKind::kBool:
      return plural ? "booleans" : "true or false";
    case ValueKind::kInteger:
      return plural ? "integers" : "an integer";
    case ValueKind::kNumber:
      return plural ? "numbers" : "a number";
    default:
      return plural ? "strings" : "a string";
  }
}

std::string ExpectedName(const Expected& expected) {
  if (expected.comma_list) return "a string or an array of numbers or strings";
  if (expected.many) {
    return KindName(expected.kind, false) + " or an array of " + KindName(expected.kind, true);
  }
  return KindName(expected.kind, false);
}

std::string TomlTypeName(const toml::node& value) {
  switch (value.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "a date or time";
  }
}

// One TOML value as the option's command-line text: strictly typed (a number is not read from a
// string, nor an integer option from a float); an integer is a valid number. Floats go through
// %.17g, which CLI11 reads back to the same double.
std::optional<std::string> ScalarText(const toml::node& value, ValueKind kind) {
  if (kind == ValueKind::kBool && value.is_boolean()) {
    return value.as_boolean()->get() ? "true" : "false";
  }
  if ((kind == ValueKind::kInteger || kind == ValueKind::kNumber) && value.is_integer()) {
    return std::to_string(value.as_integer()->get());
  }
  if (kind == ValueKind::kNumber && value.is_floating_point()) {
    return Number(value.as_floating_point()->get());
  }
  if (kind == ValueKind::kText && value.is_string()) return value.as_string()->get();
  return std::nullopt;
}

// The texts CLI11 gets for one key; false with "expected ..., got ..." in *error.
bool OptionTexts(const toml::node& value, const Expected& expected, std::vector<std::string>* texts,
                 std::string* error) {
  const toml::array* array = value.as_array();
  if (array != nullptr && (expected.many || expected.comma_list)) {
    std::string joined;
    for (const toml::node& element : *array) {
      std::optional<std::string> text = ScalarText(element, expected.kind);
      if (expected.comma_list && !text) text = ScalarText(element, ValueKind::kNumber);
      if (!text) {
        *error = "expected " + ExpectedName(expected) + ", got an array holding " +
                 TomlTypeName(element);
        return false;
      }
      if (expected.many) texts->push_back(*text);
      joined += (joined.empty() ? "" : ",") + *text;
    }
    if (expected.comma_list) texts->push_back(joined);
    return true;
  }
  std::optional<std::string> text = ScalarText(value, expected.kind);
  if (!text) {
    *error = "expected " + ExpectedName(expected) + ", got " + TomlTypeName(value);
    return false;
  }
  texts->push_back(*text);
  return true;
}

}  // namespace

const std::vector<RunOption>& RunOptions() {
  static const std::vector<RunOption> options = [] {
    Rows all;
    for (Rows group : {InputOutputOptions(), ScheduleOptions(), PreprocessingAndArOptions(),
                       DecompositionOptions(), KalmanOptions(), StorageAndDirectArOptions(),
                       AllanAndModelOptions()}) {
      all.insert(all.end(), group.begin(), group.end());
    }
    return all;
  }();
  return options;
}

void AddRunOptions(CLI::App* cmd, RunConfig* c, const std::vector<std::string>& keys) {
  for (const RunOption& o : RunOptions()) {
    if (!keys.empty() && std::find(keys.begin(), keys.end(), o.key) == keys.end()) continue;
    const std::string help = o.unit.empty() ? o.help : o.help + " [" + o.unit + "]";
    CLI::Option* option = std::visit(
        [&](auto pointer) -> CLI::Option* {
          auto& value = c->*pointer;
          if constexpr (std::is_same_v<std::decay_t<decltype(value)>, bool>) {
            return cmd->add_flag(o.names, value, help);
          } else {
            return cmd->add_option(o.names, value, help);
          }
        },
        o.member);
    if (!o.choices.empty()) option->check(CLI::IsMember(o.choices));
    if (o.check != nullptr) o.check(option);
  }
}

bool ApplyConfigFile(CLI::App* cmd, const std::string& path, std::string* error,
                     const std::vector<std::string>& comma_lists) {
  toml::table file;
  std::vector<ConfigEntry> entries;
  if (!ParseConfigFile(path, &file, error) ||
      !CollectEntries(file, path, {cmd->get_name(), OtherCommandsSections(*cmd)}, &entries,
                      error)) {
    return false;
  }
  for (const ConfigEntry& entry : entries) {
    CLI::Option* option = OptionOfKey(cmd, entry.key);
    if (option == nullptr) {
      *error = At(path, entry.where) + "unknown configuration key '" + entry.key + "'";
      return false;
    }
    if (option->count() > 0) continue;  // the command line wins
    const bool comma_list =
        std::find(comma_lists.begin(), comma_lists.end(), entry.key) != comma_lists.end();
    std::vector<std::string> texts;
    if (!OptionTexts(*entry.value, ExpectedOf(*option, comma_list), &texts, error)) {
      *error = At(path, entry.value->source().begin) + entry.key + ": " + *error;
      return false;
    }
    if (texts.empty()) continue;  // an empty list: the lists' default
    try {
      option->add_result(texts);
      option->run_callback();
    } catch (const CLI::Error& e) {
      *error = At(path, entry.value->source().begin) + e.what();
      return false;
    }
  }
  return true;
}

std::string ConfigTomlLine(const RunConfig& c, const RunOption& option) {
  return option.key + " = " + TomlValue(c, option.member) + "\n";
}

std::string EffectiveConfigToml(const RunConfig& c) {
  std::string out =
      "# fogpipe run: effective configuration (" + std::string(io::results::kFormat) + ")\n";
  for (const RunOption& option : RunOptions()) {
    if (option.hashed) out += ConfigTomlLine(c, option);
  }
  return out;
}

int ResolveThreads(int requested) {
  if (requested > 0) return requested;
  if (const char* slurm = std::getenv("SLURM_CPUS_PER_TASK")) {
    // Held to --threads' own range: the environment may not grant what the option refuses.
    char* end = nullptr;
    const long n = std::strtol(slurm, &end, 10);
    if (end != slurm && *end == '\0' && n > 0) return static_cast<int>(std::min(n, kMaxThreads));
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

bool ToCampaignOptions(const RunConfig& c, CampaignOptions* o, std::string* error) {
  if (!ApplyEveryOption(c, o, error)) return false;
  TryEveryFixedArOrder(&o->method);
  if (!o->method.IsValid(error)) return false;
  if (o->model && !ReadModelCompensation(&*o->model, error)) return false;
  if (!BudgetFitsThisMachine(c.memory_budget, o->memory_budget_bytes, error)) return false;
  if (o->scratch_dir.empty()) o->scratch_dir = o->output_dir;
  HashConfiguration(c, o);
  return true;
}

}  // namespace fogpipe::graph
