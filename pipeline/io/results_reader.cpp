#include "pipeline/io/results_reader.h"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "algorithms/allan/noise_fit.h"
#include "algorithms/method/preprocess.h"
#include "pipeline/hdf5/file.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/file_validation.h"
#include "pipeline/io/isolated_call.h"
#include "pipeline/io/results_layout.h"
#include "pipeline/io/sha256.h"

namespace fogpipe::io {
namespace {

using hdf5::Group;

double Scalar(const Group& g, const std::string& name) {
  const std::vector<double> v = g.OpenDataset(name).ReadDoubles();
  return v.empty() ? 0.0 : v[0];
}

method::NoiseRow ReadNoiseRow(const Group& allan, const std::string& signal,
                              const std::string& label) {
  const Group noise = allan.OpenGroup(signal + "/noise");
  const NoiseTable table = ReadNoiseTable(noise);
  method::NoiseRow row;
  row.signal = label;
  row.q_arcsec = table.value[0];
  row.n_deg_sqrt_h = table.value[1];
  row.b_deg_h = table.value[2];
  row.k_deg_h_sqrt_h = table.value[3];
  row.r_deg_h2 = table.value[4];
  row.p_value = table.p_value;
  if (table.dof > 0) row.chi2_per_dof = table.chi2 / static_cast<double>(table.dof);
  row.unreliable_reason = table.reason;
  row.readoff = table.readoff;
  return row;
}

/// Table 5 rows of the reference filters (signals/reference; absent in files written before).
void ReadReferenceRows(const Group& axis, const Group& allan, std::vector<method::NoiseRow>* rows) {
  if (!axis.Exists("signals/reference")) return;
  const Group g = axis.OpenGroup("signals/reference");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const std::string& name : g.ReadStringArrayAttribute("names")) {
    rows->push_back(allan.Exists(name) ? ReadNoiseRow(allan, name, name)
                                       : method::NoiseRow{name, nan, nan, nan, nan, nan});
  }
}

void ReadFitRows(const Group& models, const std::string& label_override,
                 std::vector<method::FitRow>* rows) {
  const std::vector<std::string> names = models.OpenDataset("component").ReadStrings();
  const std::vector<long long> order = models.OpenDataset("order").ReadInt64s();
  const std::vector<double> one = models.OpenDataset("fit_one_step_percent").ReadDoubles();
  const std::vector<double> sim = models.OpenDataset("fit_simulation_percent").ReadDoubles();
  for (std::size_t i = 0; i < names.size(); ++i) {
    method::FitRow row;
    row.component = label_override.empty() ? names[i] : label_override;
    row.order = static_cast<int>(order[i]);
    row.fit_one_step_percent = one[i];
    row.fit_simulation_percent = sim[i];
    rows->push_back(row);
  }
}

// FitRow::smoother_replaced from the Kalman tables (absent in files written before it was added):
// rows[0] is method 2's, then method 1's components in the kalman table's order.
void ReadSmootherReplaced(const Group& axis, std::vector<method::FitRow>* rows) {
  const auto read = [&](const std::string& path, std::size_t first_row) {
    if (!axis.Exists(path)) return;
    const std::vector<long long> replaced = axis.OpenDataset(path).ReadInt64s();
    for (std::size_t i = 0; i < replaced.size() && first_row + i < rows->size(); ++i)
      (*rows)[first_row + i].smoother_replaced = replaced[i] != 0;
  };
  read("signals/method2_kalman/smoother_replaced", 0);
  read("kalman/smoother_replaced", 1);
}

}  // namespace

NoiseTable ReadNoiseTable(const hdf5::Group& noise) {
  const hdf5::Dataset terms = noise.OpenDataset(results::kNoiseTable);
  const std::vector<std::string> names = terms.ReadFieldStrings("name");
  const std::vector<double> value = terms.ReadFieldDoubles("value");
  const std::vector<double> se = terms.ReadFieldDoubles("std_error");
  const std::vector<double> readoff = terms.ReadFieldDoubles("readoff");
  const std::vector<long long> reliable = terms.ReadFieldInt64s("reliable");
  const std::vector<std::string> reason = terms.ReadFieldStrings("reason");
  NoiseTable out;
  out.value.fill(std::numeric_limits<double>::quiet_NaN());
  out.std_error = out.value;
  out.readoff = out.value;
  out.reliable.fill(false);
  // Rows are found by name, so that the order of the rows is not part of the contract.
  for (int j = 0; j < allan::kNoiseTermCount; ++j) {
    const auto row = std::find(names.begin(), names.end(), allan::TermSymbol(j));
    if (row == names.end()) {
      throw std::runtime_error(terms.file_path() + ": " + terms.path() + " has no row " +
                               allan::TermSymbol(j));
    }
    const std::size_t i = static_cast<std::size_t>(row - names.begin());
    out.value[j] = value[i];
    out.std_error[j] = se[i];
    out.readoff[j] = readoff[i];
    out.reliable[j] = reliable[i] != 0;
    out.reason[j] = reason[i];
  }
  out.chi2 = noise.ReadDoubleAttribute("chi2");
  out.dof = noise.ReadInt64Attribute("dof");
  out.p_value = noise.ReadDoubleAttribute("p_value");
  out.misfit_tau_ranges = noise.ReadStringAttribute("misfit_tau_ranges");
  return out;
}

ResultsSummary ReadResultsSummary(const std::string& path) {
  auto lock = hdf5::LockHdf5();
  hdf5::File file = hdf5::File::OpenReadOnly(path);
  const Group root = file.Root();
  RequireFormatTag(root, path, results::kFormat);
  ResultsSummary out;
  out.path = path;
  const Group p = root.OpenGroup("provenance");
  Provenance& prov = out.provenance;
  prov.fogpipe_version = p.ReadStringAttribute("fogpipe_version");
  prov.git_commit = p.ReadStringAttribute("git_commit");
  prov.config_sha256 = p.ReadStringAttribute(results::kConfigHashAttribute);
  prov.input_path = p.ReadStringAttribute("input_path");
  prov.input_size_bytes = p.ReadInt64Attribute("input_size_bytes");
  prov.input_sha256 = p.ReadStringAttribute("input_sha256");
  prov.start_time_utc = p.ReadStringAttribute("start_time_utc");
  prov.end_time_utc = p.ReadStringAttribute("end_time_utc");
  prov.threads = static_cast<int>(p.ReadInt64Attribute("threads"));
  prov.config_toml = p.OpenDataset("config_toml").ReadStrings().at(0);
  prov.stage_names = p.OpenDataset("stage_names").ReadStrings();
  prov.stage_seconds = p.OpenDataset("stage_seconds").ReadDoubles();

  const Group axes = root.OpenGroup("axes");
  for (const std::string& name : axes.ChildNames()) {
    const Group g = axes.OpenGroup(name);
    AxisSummary axis;
    axis.name = name;
    axis.samples = g.ReadInt64Attribute("samples");
    axis.sample_rate_hz = g.ReadDoubleAttribute("sample_rate_hz");
    axis.input_units = g.ReadStringAttribute("input_units");
    axis.num_imfs = static_cast<int>(g.OpenGroup("decomposition").ReadInt64Attribute("num_imfs"));
    const Group pre = g.OpenGroup("preprocessing");
    axis.dropped_samples = static_cast<long long>(Scalar(pre, "dropped_samples"));
    axis.outliers = static_cast<long long>(pre.OpenDataset("outlier_indices").size());
    axis.mean_removed_rad_s = Scalar(pre, "mean_removed");
    if (pre.HasAttribute("repeat_warning"))
      axis.data_warning = pre.ReadStringAttribute("repeat_warning");
    ReadFitRows(g.OpenGroup("signals/method2_model"), "raw (method 2)", &axis.table3);
    ReadFitRows(g.OpenGroup("models"), "", &axis.table3);
    ReadSmootherReplaced(g, &axis.table3);
    const Group allan = g.OpenGroup("allan");
    axis.table5 = {ReadNoiseRow(allan, "raw", "raw"), ReadNoiseRow(allan, "method1", "method 1"),
                   ReadNoiseRow(allan, "method2", "method 2")};
    ReadReferenceRows(g, allan, &axis.table5);
    out.axes.push_back(std::move(axis));
  }
  return out;
}

std::optional<std::string> ReadConfigHash(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  try {
    auto lock = hdf5::LockHdf5();
    hdf5::File file = hdf5::File::OpenReadOnly(path);
    const Group root = file.Root();
    RequireFormatTag(root, path, results::kFormat);
    return root.OpenGroup("provenance").ReadStringAttribute(results::kConfigHashAttribute);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

namespace {

bool SamePath(const std::string& a, const std::string& b) {
  if (a == b) return true;
  std::error_code ec1, ec2;
  const auto ca = std::filesystem::weakly_canonical(a, ec1);
  const auto cb = std::filesystem::weakly_canonical(b, ec2);
  return !ec1 && !ec2 && ca == cb;
}

}  // namespace

namespace {

/// What an existing results file records of its input and configuration; `problem` says why it
/// cannot be used (layout invalid, checked in a child process, or unreadable).
struct RecordedInput {
  std::string problem;
  std::string config_sha256, path, sha256;
  long long size_bytes = -1;
};

RecordedInput ReadRecordedInput(const std::string& output_path) {
  RecordedInput r;
  FileValidationOptions options;
  options.check_data = false;
  const FileValidation v = ValidateFileIsolated(output_path, options, IsolationLimits());
  // Without the schemas (a usage problem, not the file's) the provenance is still read.
  if (v.usage_error.empty() && !v.problems.empty()) {
    r.problem = "existing results invalid (" + v.problems.front().object + ": " +
                v.problems.front().message + ")";
    return r;
  }
  try {
    auto lock = hdf5::LockHdf5();
    hdf5::File file = hdf5::File::OpenReadOnly(output_path);
    const Group root = file.Root();
    RequireFormatTag(root, output_path, results::kFormat);
    const Group p = root.OpenGroup("provenance");
    r.config_sha256 = p.ReadStringAttribute(results::kConfigHashAttribute);
    r.path = p.ReadStringAttribute("input_path");
    r.size_bytes = p.ReadInt64Attribute("input_size_bytes");
    r.sha256 = p.ReadStringAttribute("input_sha256");
  } catch (const std::exception& e) {
    r.problem = std::string("existing results unreadable (") + e.what() + ")";
  }
  return r;
}

/// The results at `output_path` were recorded from another input than `input_path`: identity is
/// the path (then size and content). Another input with the same output name, even a
/// byte-identical copy and whatever its configuration, is a collision: its results would be lost
/// under this input's. "" when the recorded input is this one.
std::string CollisionReason(const std::string& output_path, const RecordedInput& recorded,
                            const std::string& input_path) {
  if (SamePath(recorded.path, input_path)) return "";
  return output_path + " already holds the results of another input, " + recorded.path +
         " (same output name; give the inputs distinct names or another output folder)";
}

}  // namespace

CompletedResults CheckCompletedResults(const std::string& output_path,
                                       const std::string& input_path,
                                       const std::string& config_sha256) {
  using Verdict = CompletedResults::Verdict;
  CompletedResults out;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(output_path, ec)) return out;
  const RecordedInput recorded = ReadRecordedInput(output_path);
  if (!recorded.problem.empty()) {
    out.verdict = Verdict::kRerun;
    out.reason = recorded.problem;
    return out;
  }
  out.reason = CollisionReason(output_path, recorded, input_path);
  if (!out.reason.empty()) {
    out.verdict = Verdict::kCollision;
    return out;
  }
  if (recorded.config_sha256 != config_sha256) {
    out.verdict = Verdict::kRerun;
    return out;
  }
  std::string error;
  const auto size = std::filesystem::file_size(input_path, ec);
  const auto sha = ec ? std::nullopt : Sha256FileHex(input_path, &error);
  if (sha && static_cast<long long>(size) == recorded.size_bytes && *sha == recorded.sha256) {
    out.verdict = Verdict::kDone;
    return out;
  }
  out.verdict = Verdict::kRerun;
  out.reason = "input changed since its results were written";
  return out;
}

std::string ResultsOfAnotherInput(const std::string& output_path, const std::string& input_path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(output_path, ec)) return "";
  const RecordedInput recorded = ReadRecordedInput(output_path);
  return recorded.problem.empty() ? CollisionReason(output_path, recorded, input_path) : "";
}

std::string FormatSummary(const ResultsSummary& summary) {
  std::ostringstream out;
  const Provenance& p = summary.provenance;
  out << summary.path << "\n"
      << "  input      " << p.input_path << " (" << p.input_size_bytes << " bytes, sha256 "
      << p.input_sha256.substr(0, 16) << "...)\n"
      << "  fogpipe    " << p.fogpipe_version << " (" << p.git_commit.substr(0, 12) << "), "
      << p.threads << " threads, " << p.start_time_utc << " .. " << p.end_time_utc << "\n"
      << "  config     sha256 " << p.config_sha256.substr(0, 16) << "...\n"
      << "  stages    ";
  for (std::size_t i = 0; i < p.stage_names.size(); ++i) {
    char text[64];
    std::snprintf(text, sizeof(text), " %s %.2f s", p.stage_names[i].c_str(), p.stage_seconds[i]);
    out << text << (i + 1 < p.stage_names.size() ? "," : "\n");
  }
  for (const AxisSummary& axis : summary.axes) {
    out << "\naxis " << axis.name << ": " << axis.samples << " samples at " << axis.sample_rate_hz
        << " Hz (input " << axis.input_units << "), " << axis.dropped_samples
        << " dropped at the start, " << axis.outliers << " outliers replaced, " << axis.num_imfs
        << " IMFs + residue\n"
        << "Table 3: AR order and fit per component\n"
        << method::FormatTable3(axis.table3) << "Table 5: Allan noise terms\n"
        << method::FormatTable5(axis.table5)
        << method::PreprocessingNote(axis.dropped_samples, axis.outliers) << "\n";
    if (!axis.data_warning.empty()) out << "warning: " << axis.data_warning << "\n";
  }
  return out.str();
}

}  // namespace fogpipe::io
