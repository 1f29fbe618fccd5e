#include "pipeline/io/results_writer.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "algorithms/common/units.h"
#include "pipeline/hdf5/atomic_output_file.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/column_datasets.h"
#include "pipeline/io/noise_fit_report.h"
#include "pipeline/io/results_layout.h"

namespace fogpipe::io {
namespace {

using hdf5::Group;
using method::ComponentModel;
using method::MethodResult;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// How the large N-sample datasets are stored (column_datasets.h).
ColumnStorage Columns(ImfStorage storage, const ResultsOptions& options) {
  ColumnStorage columns;
  columns.type =
      storage == ImfStorage::kFloat32 ? hdf5::StorageType::kFloat32 : hdf5::StorageType::kFloat64;
  columns.deflate_level = options.deflate_level;
  return columns;
}

void WriteScalar(Group& group, const std::string& name, double value, const std::string& units) {
  group.WriteDataset(name, &value, {}, units);
}

void WriteCount(Group& group, const std::string& name, long long value, const std::string& units) {
  group.WriteDataset(name, std::vector<long long>{value}, units);
}

/// A [rows, width] matrix of per-component vectors, NaN-padded on the right.
void WritePadded(Group& group, const std::string& name, const std::vector<Eigen::VectorXd>& rows,
                 const std::string& units) {
  std::size_t width = 1;
  for (const auto& r : rows) width = std::max<std::size_t>(width, r.size());
  std::vector<double> data(rows.size() * width, kNaN);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (Eigen::Index j = 0; j < rows[i].size(); ++j) data[i * width + j] = rows[i][j];
  }
  group.WriteDataset(name, data.data(), {rows.size(), width}, units);
}

/// The models table (one row per component): what Table 3 is read from.
void WriteModelTable(Group group, const std::vector<std::string>& names,
                     const std::vector<const ComponentModel*>& components) {
  group.WriteStringDataset("component", names);
  std::vector<long long> order, stationary;
  std::vector<double> innovation, mean, one_step, simulation, q10, p10, q20, p20, residual;
  std::vector<Eigen::VectorXd> phi, phi_se, bic;
  for (const ComponentModel* c : components) {
    const auto& m = c->fit.model;
    const auto& d = c->fit.diagnostics;
    order.push_back(m.order);
    stationary.push_back(m.stationary ? 1 : 0);
    innovation.push_back(m.innovation_variance);
    mean.push_back(m.mean);
    one_step.push_back(d.fit_one_step_percent);
    simulation.push_back(d.fit_simulation_percent);
    residual.push_back(d.residual_variance);
    q10.push_back(d.ljung_box_q10);
    p10.push_back(d.ljung_box_p10);
    q20.push_back(d.ljung_box_q20);
    p20.push_back(d.ljung_box_p20);
    phi.push_back(m.phi);
    phi_se.push_back(m.phi_std_error);
    bic.push_back(c->fit.bic);
  }
  group.WriteDataset("order", order, "1");
  std::vector<std::string> order_note;
  for (const ComponentModel* c : components) order_note.push_back(c->order_note);
  group.WriteStringDataset("order_note", order_note);
  group.WriteDataset("stationary", stationary, "1");
  WritePadded(group, "coefficients", phi, "1");
  group.OpenDataset("coefficients")
      .WriteStringAttribute("sign_convention", results::kSignConvention);
  WritePadded(group, "coefficient_std_error", phi_se, "1");
  group.WriteDataset("innovation_variance", innovation, results::kRateVarianceUnits);
  group.WriteDataset("mean", mean, results::kRateUnits);
  WritePadded(group, "bic", bic, "1");
  group.OpenDataset("bic").WriteStringAttribute(
      "definition", "bic[i, p-1] = N ln(sigma_p^2) + p ln(N) for order p (Schwarz 1978)");
  group.WriteDataset("fit_one_step_percent", one_step, "%");
  group.WriteDataset("fit_simulation_percent", simulation, "%");
  group.WriteDataset("residual_variance", residual, results::kRateVarianceUnits);
  group.WriteDataset("ljung_box_q10", q10, "1");
  group.WriteDataset("ljung_box_p10", p10, "1");
  group.WriteDataset("ljung_box_q20", q20, "1");
  group.WriteDataset("ljung_box_p20", p20, "1");
}

/// The Kalman table (one row per component).
void WriteKalmanTable(Group group, const std::vector<std::string>& names,
                      const std::vector<const ComponentModel*>& components) {
  group.WriteStringDataset("component", names);
  std::vector<double> q, r, white, error_variance;
  std::vector<long long> switched, smoother_replaced;
  std::vector<std::string> smoother_note;
  std::vector<Eigen::VectorXd> gain;
  for (const ComponentModel* c : components) {
    smoother_replaced.push_back(c->kalman.summary.smoother_replaced ? 1 : 0);
    smoother_note.push_back(c->kalman.summary.smoother_note);
    q.push_back(c->kalman.q);
    r.push_back(c->kalman.r);
    white.push_back(c->white_noise_variance);
    error_variance.push_back(c->kalman.steady_state_error_variance);
    switched.push_back(c->kalman.summary.switched_at_sample);
    gain.push_back(c->kalman.steady_state_gain);
  }
  group.WriteDataset("q", q, results::kRateVarianceUnits);
  group.WriteDataset("r", r, results::kRateVarianceUnits);
  group.WriteDataset("white_noise_variance", white, results::kRateVarianceUnits);
  WritePadded(group, "steady_state_gain", gain, "1");
  group.WriteDataset("steady_state_error_variance", error_variance, results::kRateVarianceUnits);
  group.WriteDataset("switched_at_sample", switched, "samples");
  group.WriteDataset("smoother_replaced", smoother_replaced, "1");
  group.WriteStringDataset("smoother_note", smoother_note);
}

void WriteAllan(Group group, const method::AllanEvaluation& evaluation);

/// The reference filters (filters/reference_filters.h): signals/reference/<name> (the filtered
/// signal, stored as method 1's; attributes: the tuned parameter, termination, message, note)
/// and allan/<name> for those with an output.
void WriteReferenceFilters(Group signals, Group allan,
                           const std::vector<method::ReferenceEvaluation>& reference,
                           const ColumnStorage& storage) {
  if (reference.empty()) return;
  Group g = signals.CreateGroup("reference");
  std::vector<std::string> names;
  for (const method::ReferenceEvaluation& r : reference) names.push_back(r.output.name);
  g.WriteStringArrayAttribute("names", names);
  for (const method::ReferenceEvaluation& r : reference) {
    const filters::ReferenceOutput& o = r.output;
    Group f = g.CreateGroup(o.name);
    f.WriteStringAttribute("termination", ToString(o.termination));
    f.WriteStringAttribute("message", o.message);
    f.WriteStringAttribute("note", o.note);
    f.WriteStringAttribute("parameter_name", o.parameter_name);
    f.WriteStringAttribute("parameter_units", o.parameter_units);
    f.WriteDoubleAttribute("parameter", o.parameter);
    if (!HasResult(o.termination)) continue;
    WriteColumnDataset(f, "signal", {&o.signal}, false, results::kRateUnits, storage);
    if (HasResult(r.allan.allan.summary.termination))
      WriteAllan(allan.CreateGroup(o.name), r.allan);
  }
}

}  // namespace

void WriteNoiseTable(Group& noise, const allan::NoiseFitResult& fit) {
  std::vector<std::string> names, units, reasons;
  std::vector<double> values, std_errors, z, upper_limits, readoffs;
  std::vector<long long> significant, reliable;
  for (int j = 0; j < allan::kNoiseTermCount; ++j) {
    const allan::TermAssessment& a = fit.assessment[j];
    names.push_back(allan::TermSymbol(j));
    values.push_back(allan::EngineeringValue(fit.terms, j));
    std_errors.push_back(allan::EngineeringStandardError(fit.terms, j));
    z.push_back(a.z);
    significant.push_back(a.significant ? 1 : 0);
    upper_limits.push_back(allan::EngineeringAmplitude(j, a.upper_limit));
    readoffs.push_back(allan::EngineeringValue(fit.slope_readoff, j));
    reliable.push_back(a.reliable ? 1 : 0);
    units.push_back(allan::EngineeringUnit(j));
    reasons.push_back(a.reason);
  }
  using hdf5::TableColumn;
  noise.WriteTable(
      results::kNoiseTable,
      {TableColumn::Strings("name", names), TableColumn::Doubles("value", values),
       TableColumn::Doubles("std_error", std_errors), TableColumn::Doubles("z", z),
       TableColumn::Int64s("significant", significant),
       TableColumn::Doubles("upper_limit", upper_limits), TableColumn::Doubles("readoff", readoffs),
       TableColumn::Int64s("reliable", reliable), TableColumn::Strings("units", units),
       TableColumn::Strings("reason", reasons)});
  // Goodness of fit of the whole fit (allan/noise_fit.h): dimensionless, beside the table.
  noise.WriteDoubleAttribute("chi2", fit.chi2);
  noise.WriteInt64Attribute("dof", fit.dof);
  noise.WriteDoubleAttribute("p_value", fit.p_value);
  noise.WriteStringAttribute("misfit_tau_ranges", allan::FormatTauRanges(fit.misfit_ranges));
}

void WriteNoiseTermDatasets(Group& noise, const allan::NoiseFitResult& fit) {
  const allan::NoiseTermsEngineering e = allan::ToEngineeringUnits(fit.terms);
  const struct {
    const char* name;
    double value, se;
    const char* units;
  } terms[] = {{"Q", e.q_arcsec, e.q_se, units::kQuantizationUnit},
               {"N", e.n_deg_sqrt_h, e.n_se, units::kArwUnit},
               {"B", e.b_deg_h, e.b_se, units::kBiasUnit},
               {"K", e.k_deg_h_sqrt_h, e.k_se, units::kRrwUnit},
               {"R", e.r_deg_h2, e.r_se, units::kRampUnit}};
  for (const auto& term : terms) {
    WriteScalar(noise, term.name, term.value, term.units);
    WriteScalar(noise, std::string(term.name) + "_std_error", term.se, term.units);
  }
  // Goodness of fit and per-term flags of the noise fit (allan/noise_fit.h), next to the terms.
  WriteScalar(noise, "chi2", fit.chi2, "1");
  WriteCount(noise, "dof", fit.dof, "1");
  WriteScalar(noise, "p_value", fit.p_value, "1");
  noise.WriteStringAttribute("misfit_tau_ranges", allan::FormatTauRanges(fit.misfit_ranges));
  for (int j = 0; j < allan::kNoiseTermCount; ++j) {
    const allan::TermAssessment& a = fit.assessment[j];
    const std::string t = allan::TermSymbol(j);
    const char* unit = allan::EngineeringUnit(j);
    WriteScalar(noise, t + "_z", a.z, "1");
    WriteCount(noise, t + "_significant", a.significant ? 1 : 0, "1");
    WriteScalar(noise, t + "_upper_limit", allan::EngineeringAmplitude(j, a.upper_limit), unit);
    WriteScalar(noise, t + "_readoff", allan::EngineeringValue(fit.slope_readoff, j), unit);
    WriteCount(noise, t + "_reliable", a.reliable ? 1 : 0, "1");
    noise.WriteStringAttribute(t + "_reason", a.reason);
  }
}

namespace {

void WriteAllan(Group group, const method::AllanEvaluation& evaluation) {
  const allan::AllanTable& t = evaluation.allan.table;
  group.WriteStringAttribute("deviation", allan::ToString(t.deviation));
  group.WriteStringAttribute("noise_id_rule", allan::ToString(t.noise_id_rule));
  // One table, a row per tau: one object instead of eleven datasets (schemas/results-v2.md).
  // model_alpha, the noise fit's dominant term at each tau, sits beside the identified alpha.
  const std::vector<int> model_alpha = allan::ModelDominantAlpha(evaluation.noise.terms, t.tau_s);
  using hdf5::TableColumn;
  hdf5::Dataset table = group.WriteTable(
      results::kAllanTable,
      {TableColumn::Doubles("tau_s", t.tau_s), TableColumn::Int64s("m", t.m),
       TableColumn::Doubles("sigma", t.sigma), TableColumn::Doubles("ci_low", t.ci_low),
       TableColumn::Doubles("ci_high", t.ci_high), TableColumn::Doubles("edf", t.edf),
       TableColumn::Strings("edf_source", allan::EdfSourceNames(t.edf_source)),
       TableColumn::Int64s("alpha", std::vector<long long>(t.alpha.begin(), t.alpha.end())),
       TableColumn::Strings("alpha_method", allan::MethodNames(t.alpha_method)),
       TableColumn::Int64s("count", t.count),
       TableColumn::Int64s("model_alpha",
                           std::vector<long long>(model_alpha.begin(), model_alpha.end()))});
  table.WriteStringArrayAttribute(results::kFieldUnitsAttribute,
                                  {"s", "1", results::kRateUnits, results::kRateUnits,
                                   results::kRateUnits, "1", "", "1", "", "1", "1"});

  Group noise = group.CreateGroup("noise");
  noise.WriteStringAttribute("termination", ToString(evaluation.noise.summary.termination));
  noise.WriteStringAttribute("message", evaluation.noise.summary.message);
  noise.WriteStringAttribute("noise_type_check", io::NoiseTypeCrossCheckLine(t, evaluation.noise));
  noise.WriteStringAttribute(
      "model",
      std::string("sigma^2 = 3Q^2/tau^2 + N^2/tau + (2 ln2/pi) B^2 + K^2 tau/3 + R^2 tau^2/2, ") +
          std::string(evaluation.noise.generalized ? "generalised" : "weighted") +
          " NNLS (IEEE Std 952-1997 Annex C)");
  WriteNoiseTable(noise, evaluation.noise);
}

/// preprocessing/: what was dropped, replaced and removed before the EMD, and what the reader
/// bridged and flagged in the recorded column.
void WritePreprocessing(Group g, const AxisResults& axis) {
  const method::Preprocessed& pre = axis.result->preprocessed;
  Group p = g.CreateGroup("preprocessing");
  WriteCount(p, "dropped_samples", pre.summary.dropped_samples, "samples");
  WriteScalar(p, "mean_removed", pre.mean_removed, results::kRateUnits);
  p.WriteDataset("outlier_indices", pre.outlier_indices, "samples");
  p.OpenDataset("outlier_indices").WriteStringAttribute("rule", pre.outlier_rule);
  WriteCount(p, "window_samples", pre.window_samples, "samples");
  p.WriteDataset("window_mean", pre.window_mean, results::kRateUnits);
  p.WriteDataset("window_variance", pre.window_variance, results::kRateVarianceUnits);
  WriteCount(p, "nan_bridged_samples", axis.read.nan.bridged_samples, "samples");
  WriteCount(p, "longest_repeat_start", axis.read.repeats.start, "samples");
  WriteCount(p, "longest_repeat_samples", axis.read.repeats.samples, "samples");
  const std::optional<units::RateUnit> input_unit = units::ParseRateUnit(axis.input_units);
  WriteScalar(p, "longest_repeat_value",
              input_unit ? axis.read.repeats.value * units::ToRadPerSecond(*input_unit) : kNaN,
              results::kRateUnits);
  p.WriteStringAttribute(
      "repeat_warning",
      DescribeRepeatedRun(axis.read.repeats, axis.sample_rate_hz, axis.input_units));
}

/// Component k (IMFs, then the residue) of `kind`, from the store when the method streamed them
/// there, else from the result; read back one column at a time into one buffer. Each column is
/// read once, so the store releases it as soon as it is read.
class ComponentColumns {
 public:
  ComponentColumns(const AxisResults& axis, method::ComponentStore::Kind kind)
      : axis_(axis), kind_(kind) {}
  const double* operator()(int k) {
    const MethodResult& r = *axis_.result;
    if (axis_.store != nullptr) {
      axis_.store->Get(kind_, k, &buffer_);
      axis_.store->Release(kind_, k);
      if (buffer_.size() != r.preprocessed.signal.size())
        throw std::runtime_error("scratch file: component " + std::to_string(k) + " has " +
                                 std::to_string(buffer_.size()) + " samples, the signal " +
                                 std::to_string(r.preprocessed.signal.size()));
      return buffer_.data();
    }
    if (kind_ == method::ComponentStore::Kind::kFiltered) return r.components[k].Output().data();
    return k < static_cast<int>(r.decomposition.imfs.size()) ? r.decomposition.imfs[k].data()
                                                             : r.decomposition.residue.data();
  }

 private:
  const AxisResults& axis_;
  method::ComponentStore::Kind kind_;
  Eigen::VectorXd buffer_;
};

/// decomposition/: the IMFs and residue (as options.imf_storage says) and each IMF's sifting.
void WriteDecomposition(Group g, const AxisResults& axis, const ResultsOptions& options) {
  const MethodResult& r = *axis.result;
  const emd::EmdResult& e = r.decomposition;
  const int num_imfs = r.summary.num_imfs;
  Group d = g.CreateGroup("decomposition");
  d.WriteStringAttribute("storage", ToString(options.imf_storage));
  d.WriteInt64Attribute("num_imfs", num_imfs);
  d.WriteStringAttribute("termination", ToString(e.summary.termination));
  d.WriteDoubleAttribute("band_limit_ratio", r.band_limit_ratio);
  if (options.imf_storage != ImfStorage::kNone) {
    const ColumnStorage big = Columns(options.imf_storage, options);
    const unsigned long long n = static_cast<unsigned long long>(r.preprocessed.signal.size());
    ComponentColumns columns(axis, method::ComponentStore::Kind::kComponent);
    const ColumnLoader load = [&columns](int k) { return columns(k); };
    WriteColumnDataset(d, "imfs", num_imfs, n, load, true, results::kRateUnits, big);
    WriteColumnDataset(
        d, "residue", 1, n, [&](int) { return columns(num_imfs); }, false, results::kRateUnits,
        big);
  }
  std::vector<long long> sifts;
  std::vector<std::string> stop_reason;
  std::vector<double> period, energy;
  for (const emd::ImfInfo& info : e.imf_info) {
    sifts.push_back(info.sifts);
    stop_reason.push_back(emd::ToString(info.stop_reason));
    period.push_back(info.mean_period_samples);
    energy.push_back(info.energy);
  }
  d.WriteDataset("sifts", sifts, "1");
  d.WriteStringDataset("stop_reason", stop_reason);
  d.WriteDataset("mean_period_samples", period, "samples");
  d.WriteDataset("energy", energy, results::kRateVarianceUnits);
}

/// models/ and kalman/: one row per component (IMFs, then the residue), and the filtered
/// components when options.store_filtered_imfs.
void WriteComponents(Group g, const AxisResults& axis, const ResultsOptions& options) {
  const MethodResult& r = *axis.result;
  const int num_imfs = r.summary.num_imfs;
  std::vector<std::string> names;
  std::vector<const ComponentModel*> components;
  for (int k = 0; k <= num_imfs; ++k) {
    names.push_back(method::ComponentName(k, num_imfs));
    components.push_back(&r.components[k]);
  }
  WriteModelTable(g.CreateGroup("models"), names, components);
  Group kalman = g.CreateGroup("kalman");
  WriteKalmanTable(kalman, names, components);
  if (options.store_filtered_imfs && options.imf_storage != ImfStorage::kNone) {
    ComponentColumns columns(axis, method::ComponentStore::Kind::kFiltered);
    WriteColumnDataset(
        kalman, "filtered", num_imfs + 1,
        static_cast<unsigned long long>(r.preprocessed.signal.size()),
        [&columns](int k) { return columns(k); }, true, results::kRateUnits,
        Columns(options.imf_storage, options));
  }
}

/// signals/ and allan/: methods 1 and 2 and the reference filters, each with its Allan table and
/// noise terms, beside the raw signal's.
void WriteSignalsAndAllan(Group g, const MethodResult& r, const ResultsOptions& options) {
  Group s = g.CreateGroup("signals");
  const ColumnStorage exact = Columns(ImfStorage::kFloat64, options);
  WriteColumnDataset(s, "method1", {&r.method1}, false, results::kRateUnits, exact);
  WriteColumnDataset(s, "method2", {&r.direct.Output()}, false, results::kRateUnits, exact);
  WriteModelTable(s.CreateGroup("method2_model"), {"raw"}, {&r.direct});
  WriteKalmanTable(s.CreateGroup("method2_kalman"), {"raw"}, {&r.direct});

  const method::Preprocessed& pre = r.preprocessed;
  Group a = g.CreateGroup("allan");
  Group raw = a.CreateGroup("raw");
  WriteAllan(raw, r.raw_allan);
  raw.WriteInt64Attribute("dropped_samples", pre.summary.dropped_samples);
  raw.WriteInt64Attribute("outliers_replaced", pre.summary.outliers);
  raw.WriteStringAttribute("preprocessing", method::PreprocessingNote(pre.summary.dropped_samples,
                                                                      pre.summary.outliers));
  WriteAllan(a.CreateGroup("method1"), r.method1_allan);
  WriteAllan(a.CreateGroup("method2"), r.method2_allan);
  WriteReferenceFilters(s, a, r.reference, exact);
}

void WriteAxis(Group axes, const AxisResults& axis, const ResultsOptions& options) {
  const MethodResult& r = *axis.result;
  Group g = axes.CreateGroup(axis.name);
  g.WriteInt64Attribute("column", axis.index);
  g.WriteDoubleAttribute("sample_rate_hz", axis.sample_rate_hz);
  g.WriteStringAttribute("input_units", axis.input_units);
  g.WriteInt64Attribute("samples", static_cast<long long>(r.preprocessed.signal.size()));
  WritePreprocessing(g, axis);
  WriteDecomposition(g, axis, options);
  WriteComponents(g, axis, options);
  WriteSignalsAndAllan(g, r, options);
}

}  // namespace

const char* ToString(ImfStorage storage) {
  switch (storage) {
    case ImfStorage::kFloat64:
      return "float64";
    case ImfStorage::kFloat32:
      return "float32";
    case ImfStorage::kNone:
      return "none";
  }
  return "float64";
}

bool ParseImfStorage(const std::string& text, ImfStorage* storage) {
  for (ImfStorage s : {ImfStorage::kFloat64, ImfStorage::kFloat32, ImfStorage::kNone}) {
    if (text == ToString(s)) {
      *storage = s;
      return true;
    }
  }
  return false;
}

std::string UtcNowIso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

void WriteResultsFile(const std::filesystem::path& final_path, const Provenance& provenance,
                      const std::vector<AxisResults>& axes, const ResultsOptions& options) {
  std::optional<hdf5::AtomicOutputFile> out;
  {
    auto lock = hdf5::LockHdf5();
    try {
      out.emplace(final_path);
      {
        Group root = out->Root();
        root.WriteStringAttribute(results::kFormatAttribute, results::kFormat);
        Group p = root.CreateGroup("provenance");
        p.WriteStringAttribute("fogpipe_version", provenance.fogpipe_version);
        p.WriteStringAttribute("git_commit", provenance.git_commit);
        p.WriteStringAttribute(results::kConfigHashAttribute, provenance.config_sha256);
        p.WriteStringAttribute("input_path", provenance.input_path);
        p.WriteInt64Attribute("input_size_bytes", provenance.input_size_bytes);
        p.WriteStringAttribute("input_sha256", provenance.input_sha256);
        p.WriteStringAttribute("start_time_utc", provenance.start_time_utc);
        p.WriteStringAttribute("end_time_utc", provenance.end_time_utc);
        p.WriteInt64Attribute("threads", provenance.threads);
        if (!provenance.model_path.empty()) {
          p.WriteStringAttribute("model_path", provenance.model_path);
          p.WriteStringAttribute("model_sha256", provenance.model_sha256);
          p.WriteStringAttribute("model_compensated_terms", provenance.model_compensated_terms);
        }
        p.WriteTextDataset("config_toml", provenance.config_toml);
        p.WriteStringDataset("stage_names", provenance.stage_names);
        p.WriteDataset("stage_seconds", provenance.stage_seconds, "s");
        Group axes_group = root.CreateGroup("axes");
        for (const AxisResults& axis : axes) WriteAxis(axes_group, axis, options);
      }
      out->CloseFile();
    } catch (...) {
      out.reset();  // its HDF5 handles are released under the lock
      throw;
    }
  }
  // The fsyncs and the rename of a large file take seconds; other recordings' HDF5 reads and
  // writes need not wait for them.
  out->Commit();
}

}  // namespace fogpipe::io
