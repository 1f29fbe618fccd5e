#include "pipeline/io/model_history.h"

#include <H5Cpp.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "algorithms/common/units.h"
#include "pipeline/hdf5/atomic_output_file.h"
#include "pipeline/hdf5/file.h"
#include "pipeline/hdf5/group.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/inputs.h"
#include "pipeline/io/noise_fit_report.h"
#include "pipeline/io/results_writer.h"
#include "pipeline/io/text_output_file.h"

namespace fogpipe::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json Number(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

json ParametersJson(const std::vector<model::Parameter>& ps) {
  json o = json::object();
  for (const auto& p : ps) {
    o[p.name] = {{"value", Number(p.value)},
                 {"standard_error", Number(p.standard_error)},
                 {"units", p.units}};
    if (std::isfinite(p.low) && std::isfinite(p.high))
      o[p.name]["interval_95"] = {Number(p.low), Number(p.high)};
  }
  return o;
}

std::string NowUtc() {
  std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

// A scalar of a view as a one-element dataset, so that it carries its `units` attribute like
// every numeric dataset (attributes cannot).
void WriteScalar(hdf5::Group& g, const std::string& name, double value, const std::string& units) {
  g.WriteDataset(name, std::vector<double>{value}, units);
}

void WriteAllanView(hdf5::Group& g, const model::Views& v) {
  hdf5::Group a = g.CreateGroup("allan");
  a.WriteDataset("tau_s", v.allan.tau_s, "s");
  a.WriteDataset("avar_meas", v.allan.avar_meas, "(rad/s)^2");
  a.WriteDataset("avar_model", v.allan.avar_model, "(rad/s)^2");
  a.WriteDataset("ci_low", v.allan.ci_low, "rad/s");
  a.WriteDataset("ci_high", v.allan.ci_high, "rad/s");
  a.WriteDataset("edf", v.allan.edf, "1");
  a.WriteDataset("alpha", std::vector<long long>(v.allan.alpha.begin(), v.allan.alpha.end()), "1");
  a.WriteStringDataset("alpha_method", v.allan.alpha_method);
  a.WriteDataset("z", v.allan.z, "1");
  a.WriteDoubleAttribute("statistic", v.allan.statistic);
  a.WriteDoubleAttribute("critical", v.allan.critical);
  // The targeted Gauss-Markov bump test (algorithms/model/targeted_tests.h).
  WriteScalar(a, "gm_z", v.allan.gm_z, "1");
  WriteScalar(a, "gm_critical", v.allan.gm_critical, "1");
  WriteScalar(a, "gm_correlation_time_s", v.allan.gm_correlation_time_s, "s");
  WriteScalar(a, "gm_sigma_rad_s", v.allan.gm_sigma_rad_s, "rad/s");
  hdf5::Group terms = a.CreateGroup("terms");
  for (size_t i = 0; i < v.allan.term_names.size(); ++i)
    terms.WriteDataset(v.allan.term_names[i], v.allan.term_avar[i], "(rad/s)^2");
}

void WriteFrequencyView(hdf5::Group& g, const model::Views& v) {
  hdf5::Group f = g.CreateGroup("frequency");
  f.WriteDataset("frequency_hz", v.frequency.frequency_hz, "Hz");
  f.WriteDataset("psd", v.frequency.psd, "(rad/s)^2/Hz");
  f.WriteDataset("model_psd", v.frequency.model_psd, "(rad/s)^2/Hz");
  f.WriteDataset("line_frequency_hz", v.frequency.line_frequency_hz, "Hz");
  f.WriteDataset("line_z", v.frequency.line_z, "1");
  // The failing bands (one per frequency failure, views.h).
  std::vector<double> from, to, center, peak, ratio, excess;
  std::vector<long long> bins;
  for (const auto& fl : v.failures) {
    if (fl.domain != model::ViewDomain::kFrequency) continue;
    from.push_back(fl.from);
    to.push_back(fl.to);
    center.push_back(fl.center_hz);
    peak.push_back(fl.peak_hz);
    ratio.push_back(fl.peak_ratio);
    excess.push_back(fl.excess_power);
    bins.push_back(fl.failing_bins);
  }
  hdf5::Group bands = f.CreateGroup("bands");
  bands.WriteDataset("from_hz", from, "Hz");
  bands.WriteDataset("to_hz", to, "Hz");
  bands.WriteDataset("center_hz", center, "Hz");
  bands.WriteDataset("peak_hz", peak, "Hz");
  bands.WriteDataset("peak_ratio", ratio, "1");
  bands.WriteDataset("excess_power", excess, "(rad/s)^2");
  bands.WriteDataset("failing_bins", bins, "1");
  f.WriteDoubleAttribute("statistic", v.frequency.statistic);
  f.WriteDoubleAttribute("critical", v.frequency.critical);
  f.WriteDoubleAttribute("dof", v.frequency.dof);
  f.WriteDoubleAttribute("scale", v.frequency.scale);
}

void WriteTimeView(hdf5::Group& g, const model::Views& v) {
  hdf5::Group t = g.CreateGroup("time");
  t.WriteDataset("center_s", v.time.center_s, "s");
  t.WriteDataset("mean", v.time.mean, "rad/s");
  t.WriteDataset("variance", v.time.variance, "(rad/s)^2");
  t.WriteDataset("z_variance", v.time.z_variance, "1");
  t.WriteDataset("boundary_s", v.time.boundary_s, "s");
  t.WriteDataset("boundary_window_s", v.time.boundary_window_s, "s");
  t.WriteDataset("z_mean", v.time.z_mean, "1");
  t.WriteDataset("change_point_s", v.time.change_point_s, "s");
  t.WriteDoubleAttribute("window_s", v.time.window_s);
  t.WriteDoubleAttribute("statistic", v.time.statistic);
  t.WriteDoubleAttribute("critical", v.time.critical);
  // The targeted bias-step and warm-up scans (not scored; they rank bias_step against warmup).
  WriteScalar(t, "step_z", v.time.step_z, "1");
  WriteScalar(t, "step_critical", v.time.step_critical, "1");
  WriteScalar(t, "step_time_s", v.time.step_time_s, "s");
  WriteScalar(t, "step_size_rad_s", v.time.step_size_rad_s, "rad/s");
  WriteScalar(t, "warmup_z", v.time.warmup_z, "1");
  WriteScalar(t, "warmup_critical", v.time.warmup_critical, "1");
  WriteScalar(t, "warmup_time_constant_s", v.time.warmup_time_constant_s, "s");
  WriteScalar(t, "warmup_amplitude_rad_s", v.time.warmup_amplitude_rad_s, "rad/s");
  // The levels test (algorithms/model/bias_levels.h; scored).
  t.WriteDataset("levels_step_s", v.time.levels_step_s, "s");
  WriteScalar(t, "levels_ratio", v.time.levels_ratio, "1");
  WriteScalar(t, "levels_penalty", v.time.levels_penalty, "1");
}

void WriteAuxView(hdf5::Group& g, const model::Views& v) {
  hdf5::Group x = g.CreateGroup("aux");
  x.WriteDataset("block_center_s", v.aux.block_center_s, "s");
  x.WriteDataset("residual_lowpass", v.aux.residual_lowpass, "rad/s");
  x.WriteDoubleAttribute("statistic", v.aux.statistic);
  x.WriteDoubleAttribute("critical", v.aux.critical);
  for (const auto& c : v.aux.channels) {
    hdf5::Group cg = x.CreateGroup(c.name);
    cg.WriteDataset("lowpass", c.lowpass, c.units.empty() ? "1" : c.units);
    cg.WriteDoubleAttribute("r", c.r);
    cg.WriteDoubleAttribute("z", c.z);
    cg.WriteDoubleAttribute("r_derivative", c.r_derivative);
    cg.WriteDoubleAttribute("z_derivative", c.z_derivative);
  }
}

// The four views of an evaluation (views.h), one group each.
void WriteViews(hdf5::Group& g, const model::Evaluation& e) {
  WriteAllanView(g, e.views);
  WriteFrequencyView(g, e.views);
  WriteTimeView(g, e.views);
  WriteAuxView(g, e.views);
}

std::vector<long long> Int64(const std::vector<int>& v) { return {v.begin(), v.end()}; }

void WriteImfView(hdf5::Group& g, const model::ImfView& v) {
  hdf5::Group m = g.CreateGroup("imf");
  m.WriteStringAttribute("termination", fogpipe::ToString(v.summary.termination));
  m.WriteStringAttribute("message", v.summary.message);
  m.WriteInt64Attribute("decimation", v.decimation);
  m.WriteDoubleAttribute("sample_rate_hz", v.sample_rate_hz);
  m.WriteDoubleAttribute("critical", v.critical);
  m.WriteDoubleAttribute("aux_critical", v.aux_critical);
  m.WriteDataset("mean_period_s", v.mean_period_s, "s");
  m.WriteDataset("energy", v.energy, "(rad/s)^2");
  m.WriteDataset("expected_energy", v.expected_energy, "(rad/s)^2");
  m.WriteDataset("ratio", v.ratio, "1");
  m.WriteDataset("edf", v.edf, "1");
  m.WriteDataset("log_sd", v.log_sd, "1");
  m.WriteDataset("z", v.z, "1");
  m.WriteDataset("scored", Int64(v.scored), "1");
  m.WriteDataset("flagged", Int64(v.flagged), "1");
  m.WriteDataset("ar_order", Int64(v.ar_order), "1");
  m.WriteDataset("ar_fit_percent", v.ar_fit_percent, "%");
  hdf5::Group aux = m.CreateGroup("aux");
  for (size_t c = 0; c < v.aux_names.size(); ++c) {
    hdf5::Group cg = aux.CreateGroup(v.aux_names[c]);
    cg.WriteDataset("r", v.aux_r[c], "1");
    cg.WriteDataset("r_derivative", v.aux_r_derivative[c], "1");
    cg.WriteDataset("z", v.aux_z[c], "1");
    cg.WriteDataset("z_derivative", v.aux_z_derivative[c], "1");
  }
}

}  // namespace

json ImfJson(const model::ImfView& v) {
  json imfs = json::array();
  for (size_t k = 0; k < v.energy.size(); ++k) {
    json aux = json::object();
    for (size_t c = 0; c < v.aux_names.size(); ++c)
      aux[v.aux_names[c]] = {{"r", Number(v.aux_r[c][k])},
                             {"r_derivative", Number(v.aux_r_derivative[c][k])},
                             {"z", Number(v.aux_z[c][k])},
                             {"z_derivative", Number(v.aux_z_derivative[c][k])}};
    imfs.push_back({{"imf", k + 1},
                    {"mean_period_s", Number(v.mean_period_s[k])},
                    {"energy_rad2_per_s2", Number(v.energy[k])},
                    {"expected_energy_rad2_per_s2", Number(v.expected_energy[k])},
                    {"ratio", Number(v.ratio[k])},
                    {"log_sd", Number(v.log_sd[k])},
                    {"z", Number(v.z[k])},
                    {"flagged", v.flagged[k] != 0},
                    {"ar_order", v.ar_order[k]},
                    {"ar_fit_percent", Number(v.ar_fit_percent[k])},
                    {"aux", aux}});
  }
  return {{"decimation", v.decimation},       {"sample_rate_hz", Number(v.sample_rate_hz)},
          {"critical_z", Number(v.critical)}, {"aux_critical_z", Number(v.aux_critical)},
          {"message", v.summary.message},     {"imfs", imfs}};
}

// The angle-counter test of the rate (algorithms/model/angle_lattice.h), the step in arcsec.
json AngleLatticeJson(const model::AngleLattice& a) {
  return {{"evaluated", a.evaluated},
          {"on_lattice", a.on_lattice},
          {"step_arcsec", Number(units::QuantizationToArcsec(a.step_rad))},
          {"step_se_arcsec", Number(units::QuantizationToArcsec(a.step_se_rad))},
          {"offset_arcsec", Number(units::QuantizationToArcsec(a.offset_rad))},
          {"on_lattice_fraction", Number(a.on_lattice_fraction)},
          {"levels", a.levels},
          {"spread_steps", Number(a.spread_steps)},
          {"lag1_correlation", Number(a.lag1_correlation)},
          {"whiteness_statistic", Number(a.whiteness_statistic)},
          {"whiteness_critical", Number(a.whiteness_critical)},
          {"whiteness_dof", a.whiteness_dof},
          {"coarse", a.coarse},
          {"message", a.message}};
}

json LongTauJson(const model::LongTauCheck& c) {
  json points = json::array();
  for (const auto& p : c.points)
    points.push_back(
        {{"tau_s", Number(p.tau_s)},
         {"blocks", p.blocks},
         {"dominant_term", p.dominant_term},
         {"share", Number(p.share)},
         {"kurtosis_z", Number(p.kurtosis_z)},
         {"kurtosis_critical", Number(p.kurtosis_critical)},
         {"largest_jump", Number(p.jump)},
         {"largest_jump_time_s", Number(p.jump_time_s)},
         {"ljung_box", Number(p.portmanteau)},
         {"ljung_box_lags", p.lags},
         {"ljung_box_critical", Number(p.portmanteau_critical)},
         {"low_frequency_ratio", Number(p.low_frequency)},
         {"low_frequency_bins", p.low_bins},
         {"low_frequency_band", {Number(p.low_frequency_low), Number(p.low_frequency_high)}},
         {"flagged", p.flagged}});
  return {{"evaluated", c.evaluated},
          {"flagged", c.flagged},
          {"message", c.message},
          {"points", points}};
}

json ModelJson(const model::Evaluation& e) {
  json terms = json::array();
  for (const model::ModelTerm& t : e.terms) terms.push_back(model::ToString(t));
  json fitted = json::array();
  for (const auto& ft : e.fitted)
    fitted.push_back({{"term", ft.term}, {"parameters", ParametersJson(ft.parameters)}});
  const allan::NoiseFitResult& check = e.noise_check;
  const json noise_fit = {{"message", check.summary.message},
                          {"points", check.summary.points},
                          {"misfit_tau_ranges", allan::FormatTauRanges(check.misfit_ranges)},
                          {"terms", NoiseFitAssessmentJson(check)}};
  return {{"terms", terms}, {"fitted", fitted}, {"noise_fit", noise_fit}};
}

namespace {

// The domains as `compare --json` spells them (views.h).
json DomainNames(const std::vector<model::ViewDomain>& domains) {
  json names = json::array();
  for (model::ViewDomain domain : domains) names.push_back(model::ToString(domain));
  return names;
}

}  // namespace

json ViewErrorsJson(const std::vector<model::ViewError>& errors) {
  json o = json::object();
  for (const auto& e : errors) o[model::ToString(e.domain)] = Number(e.error);
  return o;
}

json FailuresJson(const std::vector<model::Failure>& list) {
  json failures = json::array();
  for (const auto& f : list) {
    json o = {{"domain", model::ToString(f.domain)}, {"severity", Number(f.severity)}};
    if (f.domain == model::ViewDomain::kAux) {
      o["channel"] = f.channel;
    } else {
      o["from"] = Number(f.from);
      o["to"] = Number(f.to);
    }
    if (f.domain == model::ViewDomain::kFrequency) {
      o["center_hz"] = Number(f.center_hz);
      o["peak_hz"] = Number(f.peak_hz);
      o["peak_ratio"] = Number(f.peak_ratio);
      o["excess_power_rad2_per_s2"] = Number(f.excess_power);
      o["failing_bins"] = f.failing_bins;
    }
    failures.push_back(o);
  }
  return failures;
}

json CompareJson(const model::CompareResult& r) {
  json model = ModelJson(r.base);
  // The IMF view lives inside "model": the top level keeps exactly the seven documented keys of
  // `compare --json` (error, consistent, view_errors, verdict, failures, suggestions, model), which
  // scripts rely on.
  model["imf"] = ImfJson(r.base.imf);
  model["long_tau_check"] = LongTauJson(r.base.long_tau);
  model["angle_lattice"] = AngleLatticeJson(r.angle_lattice);
  json suggestions = json::array();
  for (const auto& s : r.suggestions)
    suggestions.push_back({{"term", model::ToString(s.term)},
                           {"error_after", Number(s.error_after)},
                           {"delta_bic", Number(s.delta_bic)},
                           {"parameters", ParametersJson(s.parameters)},
                           {"evidence", s.evidence},
                           {"view_errors_after", ViewErrorsJson(s.view_errors_after)},
                           {"fixes", DomainNames(s.fixes)},
                           {"bic_rejects", s.bic_rejects},
                           {"clears_long_tau", s.clears_long_tau}});
  const model::Verdict& v = r.verdict;
  const json verdict = {
      {"status", v.status},
      {"suggestion", v.suggestion ? json(model::ToString(*v.suggestion)) : json(nullptr)},
      {"fixes", DomainNames(v.fixes)},
      {"consistent_with_suggestion", v.consistent_with_suggestion},
      {"absorbing_slow_effect", v.absorbing_slow_effect},
      {"coarse_angle_quantization", v.coarse_angle_quantization},
      {"still_failing", FailuresJson(v.still_failing)},
      {"unexplained", FailuresJson(v.unexplained)},
      {"text", v.text}};
  return {{"error", Number(r.base.views.error)},
          {"consistent", r.base.views.consistent},
          {"view_errors", ViewErrorsJson(r.base.views.view_errors)},
          {"verdict", verdict},
          {"failures", FailuresJson(r.base.views.failures)},
          {"suggestions", suggestions},
          {"model", model}};
}

void WriteModelFile(const std::string& path, const model::Evaluation& e) {
  const auto& d = e.deterministic.model;
  json comps = json::array();
  for (const auto& c : d.components) {
    json comp = {{"term", model::ToString(c.term)},
                 {"nonlinear", c.nonlinear},
                 {"coefficients", c.coefficients}};
    // Aux terms: the channel's reference x_ref and its units (schemas/model-file.md).
    if (c.term.IsAux()) {
      comp["reference"] = c.reference;
      comp["units"] = c.units;
    }
    // bias_levels: its step times, s (coefficients are the step sizes, in the same order).
    if (c.term == model::Term::kBiasLevels) comp["step_times_s"] = c.step_times_s;
    comps.push_back(comp);
  }
  json out = {{"format", "fogpipe-model-1"},
              {"terms", ModelJson(e)["terms"]},
              {"deterministic",
               {{"bias_rad_s", d.bias_rad_s},
                {"temperature_ref_degC", d.temperature_ref_degc},
                {"temperature_smoothing_s", d.temperature_smoothing_s},
                {"components", comps}}},
              {"model", ModelJson(e)}};
  WriteTextFileAtomically(fs::path(path).string(), out.dump(2) + "\n");
}

ModelFile ReadModelFile(const std::string& path) {
  if (const std::string problem = RegularFileProblem(path); !problem.empty()) {
    throw std::runtime_error(path + ": needs a model file, but " + problem);
  }
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot open model file");
  json j;
  try {
    f >> j;
  } catch (const std::exception& ex) {
    throw std::runtime_error(path + ": not JSON: " + ex.what());
  }
  if (j.value("format", "") != "fogpipe-model-1")
    throw std::runtime_error(path + ": not a fogpipe-model-1 file");
  ModelFile m;
  try {
    for (const auto& t : j.at("terms")) {
      auto term = model::ParseModelTerm(t.get<std::string>());
      if (!term) throw std::runtime_error("unknown term '" + t.get<std::string>() + "'");
      m.terms.push_back(*term);
    }
    const json& d = j.at("deterministic");
    m.deterministic.bias_rad_s = d.at("bias_rad_s").get<double>();
    m.deterministic.temperature_ref_degc = d.at("temperature_ref_degC").get<double>();
    m.deterministic.temperature_smoothing_s = d.at("temperature_smoothing_s").get<double>();
    for (const auto& c : d.at("components")) {
      model::DeterministicComponent comp;
      auto term = model::ParseModelTerm(c.at("term").get<std::string>());
      if (!term || !model::IsFittedOnRate(*term))
        throw std::runtime_error("bad deterministic term");
      comp.term = *term;
      comp.nonlinear = c.at("nonlinear").get<double>();
      comp.coefficients = c.at("coefficients").get<std::vector<double>>();
      if (comp.term.IsAux()) {
        comp.reference = c.at("reference").get<double>();
        comp.units = c.value("units", "");
      }
      if (comp.term == model::Term::kBiasLevels) {
        comp.step_times_s = c.at("step_times_s").get<std::vector<double>>();
        if (comp.step_times_s.size() != comp.coefficients.size())
          throw std::runtime_error("bias_levels: step_times_s and coefficients differ in length");
        comp.step_times_se_s.assign(comp.step_times_s.size(), 0.0);
      } else if (comp.coefficients.empty()) {
        throw std::runtime_error("a component without coefficients");
      }
      comp.coefficients_se.assign(comp.coefficients.size(), 0.0);
      m.deterministic.components.push_back(comp);
    }
  } catch (const std::exception& ex) {
    throw std::runtime_error(path + ": " + ex.what());
  }
  return m;
}

namespace {

// The model's narrow bands (narrow_band.h), one row each, SI; zero rows without any.
void WriteNarrowBands(hdf5::Group& step, const std::vector<model::NarrowBand>& bands) {
  std::vector<double> f0, f0_se, zeta, zeta_se, bandwidth, bandwidth_se, rms, rms_se;
  for (const model::NarrowBand& b : bands) {
    f0.push_back(b.f0_hz);
    f0_se.push_back(b.f0_se_hz);
    zeta.push_back(b.zeta);
    zeta_se.push_back(b.zeta_se);
    bandwidth.push_back(model::HalfPowerBandwidthHz(b));
    bandwidth_se.push_back(b.bandwidth_se_hz);
    rms.push_back(b.sigma_rad_s);
    rms_se.push_back(b.sigma_se_rad_s);
  }
  hdf5::Group g = step.CreateGroup("narrow_bands");
  g.WriteDataset("frequency_hz", f0, "Hz");
  g.WriteDataset("frequency_se_hz", f0_se, "Hz");
  g.WriteDataset("damping_ratio", zeta, "1");
  g.WriteDataset("damping_ratio_se", zeta_se, "1");
  g.WriteDataset("bandwidth_hz", bandwidth, "Hz");
  g.WriteDataset("bandwidth_se_hz", bandwidth_se, "Hz");
  g.WriteDataset("rms_rad_s", rms, "rad/s");
  g.WriteDataset("rms_se_rad_s", rms_se, "rad/s");
}

}  // namespace

int AppendHistory(const std::string& results, const std::string& recording, const std::string& axis,
                  const model::CompareResult& r) {
  auto lock = hdf5::LockHdf5();
  const fs::path final_path = fs::absolute(results);
  const fs::path tmp = hdf5::MakeAtomicTempPath(final_path);
  int index = 0;
  try {
    std::unique_ptr<H5::H5File> file;
    const bool appending = fs::exists(final_path);
    if (appending) {
      fs::copy_file(final_path, tmp, fs::copy_options::overwrite_existing);
      file = std::make_unique<H5::H5File>(tmp.string(), H5F_ACC_RDWR);
    } else {
      file = std::make_unique<H5::H5File>(tmp.string(), H5F_ACC_EXCL);
    }
    hdf5::Group root(tmp.string(), "/", file->openGroup("/"));
    // A file of its own is tagged so that `validate` and `info` know it; a results file the
    // history is appended to keeps its own tag.
    if (!appending) root.WriteStringAttribute("fogpipe_format", kCompareFormat);
    hdf5::Group compare = root.RequireGroup("compare");
    index =
        compare.HasAttribute("steps") ? static_cast<int>(compare.ReadInt64Attribute("steps")) : 0;
    char name[32];
    std::snprintf(name, sizeof(name), "step_%03d", index);
    hdf5::Group step = compare.CreateGroup(name);
    std::vector<std::string> terms;
    for (const model::ModelTerm& t : r.base.terms) terms.push_back(model::ToString(t));
    step.WriteStringArrayAttribute("terms", terms);
    step.WriteDoubleAttribute("error", r.base.views.error);
    step.WriteInt64Attribute("consistent", r.base.views.consistent ? 1 : 0);
    for (const auto& e : r.base.views.view_errors)
      step.WriteDoubleAttribute(std::string("error_") + model::ToString(e.domain), e.error);
    step.WriteStringAttribute("verdict", r.verdict.status);
    step.WriteStringAttribute("verdict_text", r.verdict.text);
    step.WriteStringAttribute("first_suggestion",
                              r.suggestions.empty() ? "" : model::ToString(r.suggestions[0].term));
    step.WriteStringAttribute("recording", recording);
    step.WriteStringAttribute("axis", axis);
    step.WriteStringAttribute("created_utc", NowUtc());
    const json cj = CompareJson(r);
    step.WriteTextDataset("compare_json", cj.dump());
    step.WriteTextDataset("model_json", cj["model"].dump());
    WriteViews(step, r.base);
    WriteNarrowBands(step, r.base.stochastic.model.bands);
    hdf5::Group noise = step.OpenGroup("allan").CreateGroup("noise");
    noise.WriteStringAttribute("termination", ToString(r.base.noise_check.summary.termination));
    noise.WriteStringAttribute("message", r.base.noise_check.summary.message);
    WriteNoiseTermDatasets(noise, r.base.noise_check);
    WriteImfView(step, r.base.imf);
    compare.WriteInt64Attribute("steps", index + 1);
    file->flush(H5F_SCOPE_GLOBAL);
    file->close();
    fs::rename(tmp, final_path);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  return index;
}

std::vector<HistoryStep> ReadHistory(const std::string& results) {
  if (const std::string problem = RegularFileProblem(results); !problem.empty()) {
    throw std::runtime_error(results + ": needs a results file, but " + problem);
  }
  auto lock = hdf5::LockHdf5();
  hdf5::File f = hdf5::File::OpenReadOnly(results);
  hdf5::Group root = f.Root();
  if (root.KindOf("compare") != hdf5::ObjectKind::kGroup)
    throw std::runtime_error(results + ": no /compare history");
  hdf5::Group compare = root.OpenGroup("compare");
  const int steps = static_cast<int>(compare.ReadInt64Attribute("steps"));
  std::vector<HistoryStep> out;
  for (int i = 0; i < steps; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "step_%03d", i);
    hdf5::Group s = compare.OpenGroup(name);
    HistoryStep h;
    h.index = i;
    h.terms = s.ReadStringArrayAttribute("terms");
    h.error = s.ReadDoubleAttribute("error");
    h.consistent = s.ReadInt64Attribute("consistent") != 0;
    h.first_suggestion = s.ReadStringAttribute("first_suggestion");
    // Steps written before the verdict existed have none.
    if (s.HasAttribute("verdict")) h.verdict = s.ReadStringAttribute("verdict");
    h.recording = s.ReadStringAttribute("recording");
    h.axis = s.ReadStringAttribute("axis");
    const auto text = s.OpenDataset("model_json").ReadStrings();
    h.model_json = text.empty() ? "" : text[0];
    out.push_back(h);
  }
  return out;
}

std::string FormatHistory(const std::vector<HistoryStep>& steps) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof(line), "%-5s %-8s %-10s %-11s %-12s %-18s %s\n", "step", "axis",
                "error", "consistent", "verdict", "next suggestion", "terms");
  out += line;
  std::map<std::string, double> previous;  // the last error of each axis
  for (const auto& s : steps) {
    std::string terms;
    for (const auto& t : s.terms) terms += (terms.empty() ? "" : ",") + t;
    std::snprintf(line, sizeof(line), "%-5d %-8s %-10.4g %-11s %-12s %-18s ", s.index,
                  s.axis.c_str(), s.error, s.consistent ? "yes" : "no",
                  s.verdict.empty() ? "-" : s.verdict.c_str(),
                  s.first_suggestion.empty() ? "-" : s.first_suggestion.c_str());
    out += line + terms;
    const auto before = previous.find(s.axis);
    if (before != previous.end() && before->second > 0) {
      std::snprintf(line, sizeof(line), "   (error x%.2g)", s.error / before->second);
      out += line;
    }
    out += "\n";
    previous[s.axis] = s.error;
  }
  return out;
}

}  // namespace fogpipe::io
