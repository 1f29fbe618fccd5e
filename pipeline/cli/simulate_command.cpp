// fogpipe simulate: writes contract-v1 gyro recordings with chosen error terms, rate-table
// profiles, durations and seeds, and the ground truth as a JSON sidecar "<file>.truth.json" that
// the analysis never reads.
//
// Order of construction for each file (seed_i = seed + i):
//   1. the profile: none (all terms off, 1 h at 10 Hz), "paper" (1 h at 1 Hz, navigation-grade
//      N, B, K, Q) or "nav" (6 h at 10 Hz, navigation-grade, aux temperature cycling);
//      levels are drawn from seed_i (algorithms/simulation/navigation_grade.h);
//   2. explicit levels (--n-deg-sqrt-h, --b-deg-h, ..., --duration-s, temperature settings);
//   3. --add TERM: a catalog term at a random navigation-grade size drawn from seed_i;
//   4. explicit effects (--gm, --sine, --bias-step, --warmup, --temperature-coef, ...).
// Every axis of a file has the same error model and independent random streams.
//
// Exit codes: 0 every file written; 1 a simulation or write failed; 2 invalid options.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "algorithms/common/units.h"
#include "algorithms/simulation/catalog.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/navigation_grade.h"
#include "pipeline/cli/commands.h"
#include "pipeline/graph/output_space.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/recording_writer.h"

namespace fogpipe::cli {
namespace {

namespace sim = fogpipe::simulation;
namespace fs = std::filesystem;

struct SimulateArguments {
  std::string output;
  std::string profile = "none";
  std::uint64_t seed = 1;
  int files = 0;  // 0: -o names one file
  std::string prefix = "sim";
  int axes = 1;
  std::string units = "deg/h";
  std::string dtype = "float64";
  std::string instrument = "fogpipe-sim";
  std::string serial;  // default SIM-<seed_i>
  std::string start_time_utc = "2026-01-01T00:00:00Z";
  std::optional<double> latitude_deg;
  std::optional<double> duration_s;
  std::optional<double> sample_rate_hz;
  // Levels in engineer's units.
  std::optional<double> n_deg_sqrt_h, b_deg_h, k_deg_h_sqrt_h, q_arcsec, r_deg_h2, bias_deg_h;
  bool angle_quantizer = false;
  std::vector<std::string> add;
  std::vector<std::string> gm, sine, bias_step;
  std::string warmup;
  std::optional<double> temperature_coef, temperature_rate_coef, temperature_ref_degC;
  std::optional<double> temperature_pp_degC, temperature_period_s, temperature_mean_degC,
      temperature_noise_degC;
  bool no_temperature = false;
  std::string rate_profile;
};

// "A:B[:C]" -> numbers; throws std::invalid_argument naming the option.
std::vector<double> ParseFields(const std::string& option, const std::string& text,
                                size_t min_fields, size_t max_fields) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string field;
  while (std::getline(stream, field, ':')) {
    size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(field, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != field.size() || field.empty() || !std::isfinite(v)) {
      throw std::invalid_argument(option + " '" + text + "': '" + field + "' is not a number");
    }
    values.push_back(v);
  }
  if (values.size() < min_fields || values.size() > max_fields || text.back() == ':') {
    throw std::invalid_argument(
        option + " '" + text + "': expected " + std::to_string(min_fields) +
        (max_fields > min_fields ? "-" + std::to_string(max_fields) : std::string()) +
        " colon-separated numbers");
  }
  return values;
}

sim::TemperatureProfile DefaultTemperature() { return sim::TemperatureProfile{}; }

bool WantsTemperature(const SimulateArguments& a) {
  return a.temperature_pp_degC || a.temperature_period_s || a.temperature_mean_degC ||
         a.temperature_noise_degC || a.temperature_coef || a.temperature_rate_coef;
}

// The profile, with an explicit record length, sample rate and latitude over it.
sim::GyroSimulatorOptions ProfileOptions(const SimulateArguments& a, std::uint64_t seed) {
  sim::GyroSimulatorOptions o;
  if (a.profile == "paper") {
    o = sim::PaperOptions(seed);
  } else if (a.profile == "nav") {
    o = sim::NavigationGradeOptions(seed);
  } else {
    o.sample_rate_hz = 10.0;
    o.duration_s = 3600.0;
  }
  o.seed = seed;
  if (a.duration_s) o.duration_s = *a.duration_s;
  if (a.sample_rate_hz) o.sample_rate_hz = *a.sample_rate_hz;
  if (a.latitude_deg) o.latitude_deg = *a.latitude_deg;
  return o;
}

// Explicit levels and temperature settings.
void ApplyLevels(const SimulateArguments& a, sim::GyroSimulatorOptions* o) {
  using namespace fogpipe::units;
  sim::GyroErrorModel& e = o->errors;
  if (a.n_deg_sqrt_h) e.n_rad_sqrt_s = DegPerSqrtHourToArw(*a.n_deg_sqrt_h);
  if (a.b_deg_h) e.b_rad_s = DegPerHourToBias(*a.b_deg_h);
  if (a.k_deg_h_sqrt_h) e.k_rad_s_sqrt_s = DegPerHourSqrtHourToRrw(*a.k_deg_h_sqrt_h);
  if (a.q_arcsec) e.q_rad = ArcsecToQuantization(*a.q_arcsec);
  if (a.r_deg_h2) e.r_rad_s2 = DegPerHour2ToRamp(*a.r_deg_h2);
  if (a.bias_deg_h) e.bias_rad_s = DegPerHourToRadPerSecond(*a.bias_deg_h);
  if (a.angle_quantizer) e.quantization_model = sim::QuantizationModel::kAngleQuantizer;

  if (a.no_temperature) {
    o->temperature.reset();
  } else if (WantsTemperature(a) || o->temperature) {
    sim::TemperatureProfile t = o->temperature ? *o->temperature : DefaultTemperature();
    if (a.temperature_pp_degC) t.peak_to_peak_degC = *a.temperature_pp_degC;
    if (a.temperature_period_s) t.period_s = *a.temperature_period_s;
    if (a.temperature_mean_degC) t.mean_degC = *a.temperature_mean_degC;
    if (a.temperature_noise_degC) t.noise_std_degC = *a.temperature_noise_degC;
    o->temperature = t;
  }
}

// --add TERM: each at a navigation-grade size drawn from the seed.
void AddCatalogTerms(const SimulateArguments& a, std::uint64_t seed, sim::GyroSimulatorOptions* o) {
  for (const std::string& name : a.add) {
    const std::optional<sim::Term> term = sim::ParseTerm(name);
    if (!term) throw std::invalid_argument("--add '" + name + "' is not a catalog term");
    if (*term == sim::Term::kNarrowBand || *term == sim::Term::kBiasLevels)
      throw std::invalid_argument("--add " + name + ": the simulator does not make this term");
    if (*term == sim::Term::kAngleQuantizer)
      throw std::invalid_argument("--add " + name +
                                  ": the simulator makes it with --angle-quantizer");
    if (a.no_temperature && sim::NeedsTemperature(*term)) {
      throw std::invalid_argument("--add " + name +
                                  " needs the aux temperature (--no-temperature)");
    }
    sim::AddNavigationGradeTerm(*term, seed, o);
  }
}

// Explicit effects (those on the temperature need it), then the rate-table input.
void ApplyEffects(const SimulateArguments& a, sim::GyroSimulatorOptions* o) {
  using namespace fogpipe::units;
  sim::GyroErrorModel& e = o->errors;
  for (const std::string& text : a.gm) {
    const std::vector<double> v = ParseFields("--gm", text, 2, 2);
    e.gauss_markov.push_back({DegPerHourToRadPerSecond(v[0]), v[1]});
  }
  for (const std::string& text : a.sine) {
    const std::vector<double> v = ParseFields("--sine", text, 2, 3);
    e.sinusoids.push_back(
        {v[0], DegPerHourToRadPerSecond(v[1]), v.size() > 2 ? v[2] * kRadPerDeg : 0.0});
  }
  for (const std::string& text : a.bias_step) {
    const std::vector<double> v = ParseFields("--bias-step", text, 2, 2);
    e.bias_steps.push_back({v[0], DegPerHourToRadPerSecond(v[1])});
  }
  if (!a.warmup.empty()) {
    const std::vector<double> v = ParseFields("--warmup", a.warmup, 2, 2);
    e.warmup = sim::Warmup{DegPerHourToRadPerSecond(v[0]), v[1]};
  }
  if (a.temperature_coef || a.temperature_rate_coef) {
    if (!o->temperature) {
      throw std::invalid_argument("thermal effects need the aux temperature (--no-temperature)");
    }
  }
  if (a.temperature_coef) {
    e.temperature = sim::TemperatureEffect{
        DegPerHourToRadPerSecond(*a.temperature_coef),
        a.temperature_ref_degC ? *a.temperature_ref_degC : o->temperature->mean_degC};
  }
  if (a.temperature_rate_coef) {
    e.temperature_rate =
        sim::TemperatureRateEffect{DegPerHourToRadPerSecond(*a.temperature_rate_coef)};
  }
  if (!a.rate_profile.empty()) {
    std::string error;
    if (!sim::ParseRateProfile(a.rate_profile, &o->input_rate, &error)) {
      throw std::invalid_argument("--rate-profile: " + error);
    }
  }
}

// Builds the options of file i, in the order of construction above. Throws
// std::invalid_argument on a malformed option.
sim::GyroSimulatorOptions BuildOptions(const SimulateArguments& a, std::uint64_t seed) {
  sim::GyroSimulatorOptions o = ProfileOptions(a, seed);
  ApplyLevels(a, &o);
  AddCatalogTerms(a, seed, &o);
  ApplyEffects(a, &o);
  std::string error;
  if (!o.IsValid(&error)) throw std::invalid_argument(error);
  return o;
}

std::string FileName(const SimulateArguments& a, int index) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "_%03d.h5", index);
  return a.prefix + buffer;
}

// Simulates and writes one file; returns false (after printing why) on failure.
/// Writes one recording and its truth sidecar, both or neither; *write_error is set when a
/// write failed (not for a simulation that could not run).
bool WriteOne(const SimulateArguments& a, const sim::GyroSimulatorOptions& base,
              const std::string& path, std::string* write_error) {
  static const char* kAxisNames[] = {"x", "y", "z"};
  io::RecordingData data;
  data.sample_rate_hz = base.sample_rate_hz;
  data.start_time_utc = a.start_time_utc;
  data.instrument = a.instrument;
  data.serial = a.serial.empty() ? "SIM-" + std::to_string(base.seed) : a.serial;
  data.latitude_deg = base.latitude_deg;
  std::vector<sim::SimulationTruth> truths;
  std::vector<std::string> names;
  for (int axis = 0; axis < a.axes; ++axis) {
    sim::GyroSimulatorOptions options = base;
    options.axis = axis;
    sim::SimulatedRecording r = sim::SimulateGyro(options);
    if (r.summary.termination != Termination::kSuccess) {
      std::cerr << "fogpipe simulate: " << path << ": " << r.summary.message << "\n";
      return false;
    }
    if (axis == 0) {
      data.rate_rad_s.resize(r.rate_rad_s.size(), a.axes);
      if (r.temperature_degC.size() > 0) {
        data.aux["temperature"] = io::AuxChannel{r.temperature_degC, "degC"};
      }
    }
    data.rate_rad_s.col(axis) = r.rate_rad_s;
    truths.push_back(std::move(r.truth));
    names.push_back(kAxisNames[axis]);
  }
  if (a.axes > 1) data.axes = names;
  io::RecordingWriterOptions writer;
  writer.rate_unit = *units::ParseRateUnit(a.units);
  writer.sample_type = a.dtype == "float32" ? io::SampleType::kFloat32 : io::SampleType::kFloat64;
  // The truth first, the recording last: a recording never appears without its truth, and a
  // truth whose recording could not be written is removed.
  const std::string truth_path = io::TruthSidecarPath(path);
  bool truth_written = false;
  try {
    nlohmann::json truth = io::SimulationTruthToJson(truths, names);
    truth["recording"] = fs::path(path).filename().string();
    truth["profile"] = a.profile;
    truth["rate_units"] = a.units;
    truth["dtype"] = a.dtype;
    io::WriteJsonFile(truth_path, truth);
    truth_written = true;
    io::WriteRecording(path, data, writer);
  } catch (const std::exception& e) {
    if (truth_written) {
      std::error_code ec;
      fs::remove(truth_path, ec);
    }
    std::cerr << "fogpipe simulate: " << e.what() << "\n";
    *write_error = e.what();
    return false;
  }
  return true;
}

int Run(const SimulateArguments& a) {
  const bool directory_mode = a.files > 0 || fs::is_directory(a.output);
  const int count = std::max(a.files, 1);
  std::vector<sim::GyroSimulatorOptions> options;
  try {
    for (int i = 0; i < count; ++i) options.push_back(BuildOptions(a, a.seed + i));
  } catch (const std::invalid_argument& e) {
    std::cerr << "fogpipe simulate: " << e.what() << "\n";
    return 2;
  }
  if (directory_mode) {
    std::error_code ec;
    fs::create_directories(a.output, ec);
    if (ec) {
      std::cerr << "fogpipe simulate: cannot create " << a.output << ": " << ec.message() << "\n";
      return 1;
    }
  }
  hdf5::SilenceHdf5ErrorPrinter();
  int failures = 0;
  for (int i = 0; i < count; ++i) {
    const std::string path =
        directory_mode ? (fs::path(a.output) / FileName(a, i)).string() : a.output;
    std::string write_error;
    if (WriteOne(a, options[i], path, &write_error)) {
      std::cerr << "fogpipe simulate: wrote " << path << " (" << options[i].NumSamples()
                << " samples x " << a.axes << " axes, seed " << options[i].seed << ")\n";
      continue;
    }
    ++failures;
    // A full or read-only device fails every later file too: stop, and name them.
    const std::string folder = fs::absolute(path).parent_path().string();
    const std::string exhausted =
        write_error.empty() ? "" : graph::OutputExhaustedReason(folder, write_error);
    if (!exhausted.empty() && i + 1 < count) {
      std::cerr << "fogpipe simulate: " << exhausted << "; " << count - i - 1
                << " more file(s) not written, from "
                << (fs::path(a.output) / FileName(a, i + 1)).string() << "\n";
      failures += count - i - 1;
      break;
    }
  }
  return failures == 0 ? 0 : 1;
}

}  // namespace

void AddSimulateCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<SimulateArguments>();
  auto* cmd = app.add_subcommand(
      "simulate",
      "Write simulated contract-v1 gyro recordings with known truth (<file>.truth.json)");
  cmd->add_option("-o,--output", args->output,
                  "Output file, or folder (with --files K, or an existing folder)")
      ->required();
  cmd->add_option("--profile", args->profile,
                  "none (terms off), paper (1 h at 1 Hz, navigation grade) or nav (6 h at 10 Hz, "
                  "navigation grade, aux temperature cycling)")
      ->check(CLI::IsMember({"none", "paper", "nav"}));
  cmd->add_option("--seed", args->seed, "Seed; file i of --files uses seed + i");
  cmd->add_option("--files", args->files, "Write K recordings <prefix>_000.h5 ... into -o DIR")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--prefix", args->prefix, "File name prefix in folder mode");
  cmd->add_option("--axes", args->axes, "Number of axes (1-3)")->check(CLI::Range(1, 3));
  cmd->add_option("--units", args->units, "Rate units in the file")
      ->check(CLI::IsMember({"deg/h", "deg/s", "rad/s"}));
  cmd->add_option("--dtype", args->dtype, "Sample type of /rate")
      ->check(CLI::IsMember({"float64", "float32"}));
  cmd->add_option("--instrument", args->instrument, "Root attribute `instrument`");
  cmd->add_option("--serial", args->serial, "Root attribute `serial` (default SIM-<seed>)");
  cmd->add_option("--start-time-utc", args->start_time_utc, "Root attribute `start_time_utc`");
  cmd->add_option("--latitude-deg", args->latitude_deg,
                  "Site latitude; adds the Earth-rate projection Omega_e sin(lat) (vertical axis)")
      ->check(CLI::Range(-90.0, 90.0));
  cmd->add_option("--duration-s", args->duration_s, "Record length in s");
  cmd->add_option("--sample-rate-hz", args->sample_rate_hz, "Sampling rate in Hz");

  cmd->add_option("--n-deg-sqrt-h", args->n_deg_sqrt_h, "white: angle random walk N, deg/sqrt(h)");
  cmd->add_option("--b-deg-h", args->b_deg_h, "bias_instability: B, deg/h (Allan floor 0.664 B)");
  cmd->add_option("--k-deg-h-sqrt-h", args->k_deg_h_sqrt_h, "rate_random_walk: K, deg/h/sqrt(h)");
  cmd->add_option("--q-arcsec", args->q_arcsec, "quantization: Q, arcsec");
  cmd->add_option("--r-deg-h2", args->r_deg_h2, "rate_ramp: R, deg/h^2");
  cmd->add_flag("--angle-quantizer", args->angle_quantizer,
                "Quantize the output angle with step Q sqrt(12) instead of white angle noise");
  cmd->add_option("--bias-deg-h", args->bias_deg_h, "Constant bias, deg/h");
  cmd->add_option("--gm", args->gm, "gauss_markov SIGMA_DEG_H:TC_S (repeatable)");
  cmd->add_option("--sine", args->sine, "sinusoid F_HZ:AMP_DEG_H[:PHASE_DEG] (repeatable)");
  cmd->add_option("--bias-step", args->bias_step, "bias_step T_S:DEG_H (repeatable)");
  cmd->add_option("--warmup", args->warmup, "warmup AMP_DEG_H:TAU_S (A exp(-t/tau))");
  cmd->add_option("--temperature-coef", args->temperature_coef,
                  "temperature: deg/h per degC of T - T_ref");
  cmd->add_option("--temperature-ref-degc", args->temperature_ref_degC,
                  "T_ref of --temperature-coef (default: the cycle's mean)");
  cmd->add_option("--temperature-rate-coef", args->temperature_rate_coef,
                  "temperature_rate (Shupe): deg/h per degC/s of dT/dt");
  cmd->add_option("--temperature-pp-degc", args->temperature_pp_degC,
                  "Aux temperature peak-to-peak, degC (default 8; nav: drawn 6-12)");
  cmd->add_option("--temperature-period-s", args->temperature_period_s,
                  "Aux temperature cycle period, s (default 5400; nav: drawn 3600-7200)");
  cmd->add_option("--temperature-mean-degc", args->temperature_mean_degC,
                  "Aux temperature mean, degC (default 25)");
  cmd->add_option("--temperature-noise-degc", args->temperature_noise_degC,
                  "Aux temperature sensor noise std, degC (default 0.005)");
  cmd->add_flag("--no-temperature", args->no_temperature, "Write no aux temperature channel");
  std::string catalog;
  for (sim::Term term : sim::AllTerms())
    if (term != sim::Term::kNarrowBand && term != sim::Term::kAngleQuantizer &&
        term != sim::Term::kBiasLevels)
      catalog += std::string(" ") + sim::ToString(term);
  cmd->add_option("--add", args->add,
                  "Add a catalog term at a random navigation-grade size drawn from the seed "
                  "(repeatable):" +
                      catalog);
  cmd->add_option("--rate-profile", args->rate_profile,
                  "Rate-table input, deg/h, summed components: constant:W, step:T_S:S, "
                  "ramp:T0_S:T1_S:SLOPE_PER_S, sine:F_HZ:A[:PHASE_DEG]; e.g. "
                  "step:600:10,ramp:1200:1800:0.01,sine:0.01:5");
  cmd->footer(
      "An option shown without a default keeps the --profile's value: none: 1 h at 10 Hz, no\n"
      "error terms; paper: 1 h at 1 Hz, navigation-grade N, B, K, Q and bias drawn from the seed;\n"
      "nav: 6 h at 10 Hz, navigation grade drawn from the seed, aux temperature cycling. No\n"
      "--latitude-deg: no Earth rate. Exit codes: 0 every file written, 1 a simulation or write\n"
      "failed, 2 invalid options.");
  cmd->callback([args, exit_code]() { *exit_code = Run(*args); });
}

}  // namespace fogpipe::cli
