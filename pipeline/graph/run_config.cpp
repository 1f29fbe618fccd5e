#include "pipeline/graph/run_config.h"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <thread>

#include "pipeline/graph/memory_budget.h"
#include "pipeline/io/inputs.h"
#include "pipeline/io/model_history.h"
#include "pipeline/io/results_layout.h"
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

std::string Quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// --model FILE: read once per run; the file is named in every error.
bool ReadModelCompensation(const std::string& path, CampaignOptions* o, std::string* error) {
  ModelCompensationOptions m;
  m.path = path;
  if (const std::string problem = io::RegularFileProblem(path); !problem.empty()) {
    *error = "--model " + path + ": needs a model file, but " + problem;
    return false;
  }
  try {
    const io::ModelFile file = io::ReadModelFile(path);
    m.deterministic = file.deterministic;
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
  m.sha256 = *sha;
  for (const auto& comp : m.deterministic.components) {
    m.terms += (m.terms.empty() ? "" : ",") + std::string(model::ToString(comp.term));
    m.needs_temperature = m.needs_temperature || model::NeedsTemperature(comp.term);
  }
  o->model = std::move(m);
  return true;
}

}  // namespace

void AddRunOptions(CLI::App* cmd, RunConfig* c) {
  cmd->add_option("inputs", c->inputs,
                  "Recordings: files, folders (recursive *.h5) or quoted glob patterns");
  cmd->add_option("--manifest", c->manifest,
                  "File with one recording path per line ('#' comments; optional size column)");
  cmd->add_option("--shard", c->shard,
                  "Process only shard I of the sorted input list (Slurm arrays)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--num-shards", c->num_shards,
                  "Number of shards N; pass it explicitly (SLURM_ARRAY_TASK_COUNT changes when "
                  "only failed indices are resubmitted)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--shard-by", c->shard_by,
                  "stride (every N-th file) or size (balanced by bytes)");
  cmd->add_option("-o,--output", c->output_dir, "Output folder (one results file per recording)");
  cmd->add_option("--scratch-dir", c->scratch_dir,
                  "Folder for the IMFs between the decomposition and the results file, about "
                  "8 bytes per sample per IMF, removed as each recording ends (empty: the "
                  "output folder; on a cluster, node-local scratch such as $TMPDIR)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--config", c->config_file,
                  "TOML file of options (keys are the long option names; unknown keys are errors)");
  cmd->add_option("--threads", c->threads,
                  "Worker threads (0: SLURM_CPUS_PER_TASK if set, else all cores)")
      ->check(CLI::Range(0l, kMaxThreads));
  cmd->add_option("--memory-budget", c->memory_budget,
                  "Memory for recordings in flight, e.g. 512M, 8G, or auto (default: 80 % of "
                  "SLURM_MEM_PER_NODE, else half the physical memory)");
  cmd->add_flag("--dry-run", c->dry_run, "List what would be done; write nothing");
  cmd->add_flag("--force", c->force, "Redo files whose results exist with the same configuration");
  cmd->add_option("--drop-start-s", c->drop_start_s, "Seconds dropped at the start (transient)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--max-nan-gap", c->max_nan_gap,
                  "Longest run of NaN samples bridged by interpolation")
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--max-ar-order", c->max_ar_order, "Largest AR order tried by BIC")
      ->check(CLI::Range(1, 200));
  cmd->add_option("--ar-order", c->ar_order, "Fixed AR order of every component (0: by BIC)")
      ->check(CLI::Range(0, 200));
  cmd->add_option("--ar-estimator", c->ar_estimator, "AR estimator")
      ->check(CLI::IsMember({"burg", "least_squares_qr", "yule_walker", "maximum_likelihood"}));
  cmd->add_option("--emd-sifts", c->emd_sifts, "Sifts per IMF (fixed_sifts rule)")
      ->check(CLI::Range(1, 10000));
  cmd->add_option("--emd-stop-rule", c->emd_stop_rule, "EMD sifting stop rule")
      ->check(CLI::IsMember({"fixed_sifts", "cauchy", "s_number", "rilling"}));
  cmd->add_option("--max-imfs", c->max_imfs, "Maximum number of IMFs (0: until monotonic)")
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--band-limit-ratio", c->band_limit_ratio,
                  "Each IMF's content below this / its mean period (cycles per sample) moves to "
                  "the next component before modelling; 0: EMD's IMFs as they are (the paper's)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--q", c->q, "Kalman process-noise variance, (rad/s)^2 (<0: default rule)");
  cmd->add_option("--r", c->r,
                  "Kalman measurement-noise variance, (rad/s)^2 (<0: white-noise rule)");
  cmd->add_option("--noise-rule", c->noise_rule,
                  "How each IMF's Kalman q and R follow from its white-noise share: share "
                  "(default) or innovation (see schemas/results-v1.md)")
      ->check(CLI::IsMember({"share", "innovation"}));
  cmd->add_option("--q-scale", c->q_scale, "Multiplier of q")->check(CLI::PositiveNumber);
  cmd->add_option("--r-scale", c->r_scale, "Multiplier of R")->check(CLI::PositiveNumber);
  cmd->add_flag("--smooth", c->smooth, "Use the RTS smoother output instead of the filter's");
  cmd->add_option("--imf-storage", c->imf_storage, "How IMFs are stored")
      ->check(CLI::IsMember({"float64", "float32", "none"}));
  cmd->add_flag("--store-filtered-imfs", c->store_filtered_imfs,
                "Also store every filtered component");
  cmd->add_option("--direct-ar-order", c->direct_ar_order,
                  "Method 2's AR order (0: by BIC; the paper used 6)")
      ->check(CLI::Range(0, 200));
  cmd->add_option("--taus", c->taus,
                  "Allan tau grid: octave, decade (10 per decade), decade:K, all, or log10 "
                  "(allantools' taus='log10')");
  cmd->add_option("--noise-id", c->noise_id,
                  "Noise identification behind the Allan intervals: calibrated (chosen by measured "
                  "coverage) or stable32 (Stable32's Alpha column and EDF convention)")
      ->check(CLI::IsMember({"calibrated", "stable32"}));
  cmd->add_option(
      "--model", c->model,
      "Model file of `compare --save-model`: its deterministic effects are subtracted before the "
      "EMD (thermal terms use each recording's /aux/temperature)");
}

bool ApplyConfigFile(CLI::App* cmd, const std::string& path, std::string* error) {
  if (const std::string problem = io::RegularFileProblem(path); !problem.empty()) {
    *error = path + ": --config needs a TOML file, but " + problem;
    return false;
  }
  try {
    for (const CLI::ConfigItem& item : CLI::ConfigTOML().from_file(path)) {
      const std::string key =
          (item.parents.empty() ? "" : CLI::detail::join(item.parents, ".") + ".") + item.name;
      CLI::Option* option =
          item.parents.empty() ? cmd->get_option_no_throw("--" + item.name) : nullptr;
      if (option == nullptr || key == "config") {
        *error = path + ": unknown configuration key '" + key + "'";
        return false;
      }
      if (option->count() > 0) continue;  // the command line wins
      option->add_result(item.inputs);
      option->run_callback();
    }
  } catch (const CLI::Error& e) {
    *error = path + ": " + e.what();
    return false;
  }
  return true;
}

std::string EffectiveConfigToml(const RunConfig& c) {
  std::ostringstream out;
  out << "# fogpipe run: effective configuration (" << io::results::kFormat << ")\n"
      << "drop-start-s = " << Number(c.drop_start_s) << "\n"
      << "max-nan-gap = " << c.max_nan_gap << "\n"
      << "max-ar-order = " << c.max_ar_order << "\n"
      << "ar-order = " << c.ar_order << "\n"
      << "ar-estimator = " << Quoted(c.ar_estimator) << "\n"
      << "emd-sifts = " << c.emd_sifts << "\n"
      << "emd-stop-rule = " << Quoted(c.emd_stop_rule) << "\n"
      << "max-imfs = " << c.max_imfs << "\n"
      << "band-limit-ratio = " << Number(c.band_limit_ratio) << "\n"
      << "q = " << Number(c.q) << "\n"
      << "r = " << Number(c.r) << "\n"
      << "noise-rule = " << Quoted(c.noise_rule) << "\n"
      << "q-scale = " << Number(c.q_scale) << "\n"
      << "r-scale = " << Number(c.r_scale) << "\n"
      << "smooth = " << (c.smooth ? "true" : "false") << "\n"
      << "imf-storage = " << Quoted(c.imf_storage) << "\n"
      << "store-filtered-imfs = " << (c.store_filtered_imfs ? "true" : "false") << "\n"
      << "direct-ar-order = " << c.direct_ar_order << "\n"
      << "taus = " << Quoted(c.taus) << "\n"
      << "noise-id = " << Quoted(c.noise_id) << "\n"
      << "model = " << Quoted(c.model) << "\n";
  return out.str();
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
  method::MethodOptions& m = o->method;
  m.preprocess.drop_start_s = c.drop_start_s;
  m.emd.fixed_sifts = c.emd_sifts;
  m.emd.max_sifts = std::max(m.emd.max_sifts, c.emd_sifts);
  m.emd.max_imfs = c.max_imfs;
  m.band_limit.cutoff_ratio = c.band_limit_ratio;
  for (emd::StopRule rule : {emd::StopRule::kFixedSifts, emd::StopRule::kCauchy,
                             emd::StopRule::kSNumber, emd::StopRule::kRilling}) {
    if (c.emd_stop_rule == emd::ToString(rule)) m.emd.stop_rule = rule;
  }
  m.component.ar.max_order = std::max(c.max_ar_order, std::max(c.ar_order, c.direct_ar_order));
  m.component.ar.fixed_order = c.ar_order;
  for (ar::Estimator e : {ar::Estimator::kBurg, ar::Estimator::kLeastSquaresQr,
                          ar::Estimator::kYuleWalker, ar::Estimator::kMaximumLikelihood}) {
    if (c.ar_estimator == ar::ToString(e)) m.component.ar.estimator = e;
  }
  m.component.kalman.q = c.q;
  m.component.kalman.r = c.r;
  if (!method::ParseComponentNoiseRule(c.noise_rule, &m.component.noise_rule)) {
    *error = "--noise-rule: expected share or innovation, got '" + c.noise_rule + "'";
    return false;
  }
  m.component.kalman.q_scale = c.q_scale;
  m.component.kalman.r_scale = c.r_scale;
  m.component.kalman.smooth = c.smooth;
  m.direct_ar_order = c.direct_ar_order;
  if (!allan::ParseTauGrid(c.taus, &m.allan.grid, error)) return false;
  if (!allan::ParseNoiseIdRule(c.noise_id, &m.allan.noise_id)) {
    *error = "--noise-id: expected calibrated or stable32, got '" + c.noise_id + "'";
    return false;
  }
  // Stable32's bounds come from its noise types and the EDF as Greenhall & Riley printed it.
  m.allan.sampled_phase_edf = m.allan.noise_id != allan::NoiseIdRule::kStable32;
  if (!m.IsValid(error)) return false;
  if (!c.model.empty() && !ReadModelCompensation(c.model, o, error)) return false;
  if (!io::ParseImfStorage(c.imf_storage, &o->results.imf_storage)) {
    *error = "--imf-storage: expected float64, float32 or none";
    return false;
  }
  o->results.store_filtered_imfs = c.store_filtered_imfs;
  o->read.max_nan_gap_samples = c.max_nan_gap;
  const auto budget = c.memory_budget == "auto"
                          ? std::optional<std::uint64_t>(AutoMemoryBudgetBytes())
                          : ParseByteSize(c.memory_budget);
  if (!budget) {
    *error = "--memory-budget: expected auto or a size such as 512M or 2G, got '" +
             c.memory_budget + "'";
    return false;
  }
  // A budget the machine cannot hold would admit recordings that then swap or are killed.
  const std::uint64_t physical = PhysicalMemoryBytes();
  if (physical > 0 && *budget > physical) {
    *error = "--memory-budget " + c.memory_budget + " is more than this machine's " +
             std::to_string(physical >> 20) + " MiB of physical memory; give at most that";
    return false;
  }
  o->memory_budget_bytes = *budget;
  o->threads = ResolveThreads(c.threads);
  o->output_dir = c.output_dir;
  o->scratch_dir = c.scratch_dir.empty() ? c.output_dir : c.scratch_dir;
  o->force = c.force;
  o->dry_run = c.dry_run;
  o->config_toml = EffectiveConfigToml(c);
  // The model file's content is part of the configuration: a changed model redoes every file.
  // A TOML comment keeps config_toml a valid --config file.
  if (o->model) o->config_toml += "# model-sha256 = " + o->model->sha256 + "\n";
  o->config_sha256 = io::Sha256Hex(o->config_toml);
  return true;
}

}  // namespace fogpipe::graph
