#include "pipeline/io/campaign_table.h"

#include <H5Lpublic.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "algorithms/allan/noise_fit.h"
#include "pipeline/hdf5/atomic_output_file.h"
#include "pipeline/hdf5/file.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/csv_writer.h"
#include "pipeline/io/file_validation.h"
#include "pipeline/io/inputs.h"
#include "pipeline/io/isolated_reader.h"
#include "pipeline/io/results_layout.h"
#include "pipeline/io/results_reader.h"

namespace fogpipe::io {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kResultsSuffix = ".fogpipe.h5";

std::string Normal(const std::string& path) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec);
  return (ec ? fs::path(path) : absolute).lexically_normal().string();
}

CampaignRow EmptyRow(const std::string& input_path) {
  CampaignRow row;
  row.input_path = input_path;
  row.duration_s = kNaN;
  row.model_loop_error = kNaN;
  for (auto& signal : row.term) signal.fill(kNaN);
  for (auto& signal : row.term_std_error) signal.fill(kNaN);
  for (auto& signal : row.term_readoff) signal.fill(kNaN);
  row.noise_fit_chi2_per_dof.fill(kNaN);
  row.noise_fit_p_value.fill(kNaN);
  return row;
}

double Scalar(const hdf5::Group& group, const std::string& name) {
  if (!group.Exists(name)) return kNaN;
  const std::vector<double> values = group.OpenDataset(name).ReadDoubles();
  return values.empty() ? kNaN : values[0];
}

/// One results file: its input path, end time and per-axis rows (status "ok").
struct ResultsRows {
  std::string input_path;
  std::string end_time_utc;
  std::vector<CampaignRow> rows;
};

ResultsRows ReadResultsRows(const fs::path& path) {
  auto lock = hdf5::LockHdf5();
  hdf5::File file = hdf5::File::OpenReadOnly(path.string());
  const hdf5::Group root = file.Root();
  // A results file of the previous layout is named as such (file_validation.h).
  RequireFormatTag(root, path.string(), results::kFormat);
  const hdf5::Group provenance = root.OpenGroup("provenance");
  ResultsRows out;
  out.input_path = Normal(provenance.ReadStringAttribute("input_path"));
  out.end_time_utc = provenance.ReadStringAttribute("end_time_utc");
  const hdf5::Group axes = root.OpenGroup("axes");
  for (const std::string& name : axes.ChildNames()) {
    const hdf5::Group g = axes.OpenGroup(name);
    CampaignRow row = EmptyRow(out.input_path);
    row.results_file = path.filename().string();
    row.axis = name;
    row.duration_s = static_cast<double>(g.ReadInt64Attribute("samples")) /
                     g.ReadDoubleAttribute("sample_rate_hz");
    for (std::size_t s = 0; s < kCampaignSignals.size(); ++s) {
      const std::string noise = std::string("allan/") + kCampaignSignals[s] + "/noise";
      if (!g.Exists(noise)) continue;
      const NoiseTable n = ReadNoiseTable(g.OpenGroup(noise));
      // kCampaignTerms is Q, N, B, K, R: the order of allan::TermSymbol and of NoiseTable.
      for (std::size_t t = 0; t < kCampaignTerms.size(); ++t) {
        const std::string symbol = kCampaignTerms[t];
        row.term[s][t] = n.value[t];
        row.term_std_error[s][t] = n.std_error[t];
        row.term_readoff[s][t] = n.readoff[t];
        const std::string& reason = n.reason[t];
        if (reason.empty()) continue;
        const bool first = row.unreliable_terms[s].empty();
        row.unreliable_terms[s] += (first ? "" : ",") + symbol;
        row.unreliable_reasons[s] += (first ? "" : " | ") + symbol + ": " + reason;
      }
      row.noise_fit_chi2_per_dof[s] = n.dof > 0 ? n.chi2 / static_cast<double>(n.dof) : kNaN;
      row.noise_fit_p_value[s] = n.p_value;
      row.misfit_tau_ranges[s] = n.misfit_tau_ranges;
    }
    const hdf5::Group pre = g.OpenGroup("preprocessing");
    if (pre.HasAttribute("repeat_warning"))
      row.data_warning = pre.ReadStringAttribute("repeat_warning");
    // A model history (fogpipe compare) is not part of fogpipe-results-v2 yet.
    if (g.Exists("model_history/loop_rms_error")) {
      row.model_loop_error = Scalar(g, "model_history/loop_rms_error");
    }
    row.status = "ok";
    out.rows.push_back(std::move(row));
  }
  return out;
}

struct StatusLine {
  std::string status, message;
};

std::map<std::string, StatusLine> ReadStatusLog(const fs::path& path,
                                                std::vector<std::string>* problems) {
  std::map<std::string, StatusLine> last;
  std::error_code ec;
  if (fs::exists(fs::symlink_status(path, ec))) {
    if (const std::string problem = RegularFileProblem(path.string()); !problem.empty()) {
      problems->push_back(path.string() + ": not read: " + problem);
      return last;
    }
  }
  std::ifstream in(path);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    try {
      const auto json = nlohmann::json::parse(line);
      last[Normal(json.at("file").get<std::string>())] = {json.at("status").get<std::string>(),
                                                          json.value("message", "")};
    } catch (const std::exception& e) {
      problems->push_back(path.string() + ":" + std::to_string(number) + ": " + e.what());
    }
  }
  return last;
}

/// A column of the table: HDF5 dataset and CSV field.
struct Column {
  std::string name;
  std::string units;  ///< empty for text columns
  // The row's field itself, so that one list of columns both writes and reads the table.
  std::function<std::string&(CampaignRow&)> text;
  std::function<double&(CampaignRow&)> number;
};

std::vector<Column> Columns() {
  std::vector<Column> columns = {
      {"input_path", "", [](CampaignRow& r) -> std::string& { return r.input_path; }, nullptr},
      {"results_file", "", [](CampaignRow& r) -> std::string& { return r.results_file; }, nullptr},
      {"axis", "", [](CampaignRow& r) -> std::string& { return r.axis; }, nullptr},
      {"serial", "", [](CampaignRow& r) -> std::string& { return r.serial; }, nullptr},
      {"instrument", "", [](CampaignRow& r) -> std::string& { return r.instrument; }, nullptr},
      {"duration_s", "s", nullptr, [](CampaignRow& r) -> double& { return r.duration_s; }}};
  for (std::size_t s = 0; s < kCampaignSignals.size(); ++s) {
    for (std::size_t t = 0; t < kCampaignTerms.size(); ++t) {
      const std::string name = std::string(kCampaignSignals[s]) + "_" + kCampaignTerms[t];
      columns.push_back({name, allan::EngineeringUnit(static_cast<int>(t)), nullptr,
                         [s, t](CampaignRow& r) -> double& { return r.term[s][t]; }});
      columns.push_back({name + "_std_error", allan::EngineeringUnit(static_cast<int>(t)), nullptr,
                         [s, t](CampaignRow& r) -> double& { return r.term_std_error[s][t]; }});
      columns.push_back({name + "_readoff", allan::EngineeringUnit(static_cast<int>(t)), nullptr,
                         [s, t](CampaignRow& r) -> double& { return r.term_readoff[s][t]; }});
    }
    const std::string signal = kCampaignSignals[s];
    columns.push_back({signal + "_unreliable_terms", "",
                       [s](CampaignRow& r) -> std::string& { return r.unreliable_terms[s]; },
                       nullptr});
    columns.push_back({signal + "_unreliable_reasons", "",
                       [s](CampaignRow& r) -> std::string& { return r.unreliable_reasons[s]; },
                       nullptr});
    columns.push_back({signal + "_noise_fit_chi2_per_dof", "1", nullptr,
                       [s](CampaignRow& r) -> double& { return r.noise_fit_chi2_per_dof[s]; }});
    columns.push_back({signal + "_noise_fit_p_value", "1", nullptr,
                       [s](CampaignRow& r) -> double& { return r.noise_fit_p_value[s]; }});
    columns.push_back({signal + "_noise_fit_misfit_tau_ranges", "",
                       [s](CampaignRow& r) -> std::string& { return r.misfit_tau_ranges[s]; },
                       nullptr});
  }
  columns.push_back({"model_loop_error", "deg/h", nullptr,
                     [](CampaignRow& r) -> double& { return r.model_loop_error; }});
  columns.push_back(
      {"data_warning", "", [](CampaignRow& r) -> std::string& { return r.data_warning; }, nullptr});
  columns.push_back(
      {"status", "", [](CampaignRow& r) -> std::string& { return r.status; }, nullptr});
  columns.push_back(
      {"message", "", [](CampaignRow& r) -> std::string& { return r.message; }, nullptr});
  return columns;
}

// A table cell: 4 significant digits, "-" where there is no value (NaN).
std::string FormatNumber(double value) {
  if (std::isnan(value)) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), "%.4g", value);
  return text;
}

// A column's value in a row that is only read.
double NumberOf(const Column& column, const CampaignRow& row) {
  return column.number(const_cast<CampaignRow&>(row));
}
const std::string& TextOf(const Column& column, const CampaignRow& row) {
  return column.text(const_cast<CampaignRow&>(row));
}

bool IsResultsFile(const fs::directory_entry& entry) {
  const std::string name = entry.path().filename().string();
  const std::size_t suffix = std::string(kResultsSuffix).size();
  return entry.is_regular_file() && name.size() > suffix &&
         name.compare(name.size() - suffix, std::string::npos, kResultsSuffix) == 0;
}

std::vector<fs::path> ListResultsFiles(const std::string& outdir) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(outdir)) {
    if (IsResultsFile(entry)) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The rows of one results file, or nothing after adding to `problems` why it cannot count.
std::optional<ResultsRows> ReadCheckedResults(const fs::path& file,
                                              std::vector<std::string>* problems) {
  // A results file that misses part of its layout (say an axis without /allan) would otherwise
  // give rows without terms marked ok. Checked in a child process: a damaged file cannot take
  // the merge down.
  FileValidationOptions validation;
  validation.check_data = false;
  const FileValidation v = ValidateFileIsolated(file.string(), validation, IsolationLimits());
  if (v.usage_error.empty() && !v.problems.empty()) {
    problems->push_back(file.string() + ": invalid results (" + v.problems.front().object + ": " +
                        v.problems.front().message + ")");
    return std::nullopt;
  }
  try {
    return ReadResultsRows(file);
  } catch (const std::exception& e) {
    problems->push_back(file.string() + ": " + e.what());
    return std::nullopt;
  }
}

// The newest results file per input path (a re-named duplicate must not count twice).
std::map<std::string, ResultsRows> NewestResultsByInput(const std::string& outdir,
                                                        CampaignTable* table) {
  std::map<std::string, ResultsRows> by_input;
  for (const fs::path& file : ListResultsFiles(outdir)) {
    std::optional<ResultsRows> rows = ReadCheckedResults(file, &table->problems);
    if (!rows) continue;
    auto found = by_input.find(rows->input_path);
    if (found == by_input.end()) {
      by_input.emplace(rows->input_path, std::move(*rows));
    } else {
      ++table->duplicate_results;
      if (rows->end_time_utc > found->second.end_time_utc) found->second = std::move(*rows);
    }
  }
  return by_input;
}

using RowsByInput = std::map<std::string, std::vector<CampaignRow>>;

// The analysed rows, with the serial and instrument of their recordings.
RowsByInput AnalysedRows(std::map<std::string, ResultsRows> by_input, CampaignTable* table) {
  RowsByInput rows;
  for (auto& [input, results] : by_input) {
    // Serial and instrument live in the recording, not in the results file.
    std::string serial, instrument;
    try {
      const RecordingInfo info = InspectRecordingIsolated(input);
      serial = info.serial.value_or("");
      instrument = info.instrument.value_or("");
    } catch (const std::exception&) {
      // The recording may have moved since; the noise terms are still valid.
    }
    for (CampaignRow& row : results.rows) {
      row.serial = serial;
      row.instrument = instrument;
    }
    rows[input] = std::move(results.rows);
    ++table->results_files;
  }
  return rows;
}

// A row for every input the status log names that has no results file.
void AddStatusOnlyRows(const std::map<std::string, StatusLine>& status, RowsByInput* rows) {
  for (const auto& [input, line] : status) {
    if (rows->count(input) != 0) continue;
    CampaignRow row = EmptyRow(input);
    // "ok"/"skipped" without a results file: it was removed or renamed since.
    row.status = line.status == "failed" ? "failed" : "missing";
    row.message = line.message;
    (*rows)[input] = {row};
  }
}

// A "missing" row for every input of the manifest that has neither results nor a status.
void AddManifestOnlyRows(const std::string& manifest, RowsByInput* rows,
                         std::vector<std::string>* problems) {
  std::vector<std::string> errors;
  for (const InputFile& input : ListInputs({}, manifest, &errors)) {
    const std::string key = Normal(input.path);
    if (rows->count(key) != 0) continue;
    CampaignRow row = EmptyRow(key);
    row.status = "missing";
    row.message = "listed in " + manifest + " but neither analysed nor reported";
    (*rows)[key] = {row};
  }
  for (const std::string& e : errors) problems->push_back(e);
}

}  // namespace

CampaignTable CollectCampaign(const std::string& outdir, const std::string& manifest) {
  CampaignTable table;
  table.source_folder = outdir;
  std::map<std::string, ResultsRows> by_input = NewestResultsByInput(outdir, &table);
  const auto status = ReadStatusLog(fs::path(outdir) / "status.jsonl", &table.problems);
  RowsByInput rows = AnalysedRows(std::move(by_input), &table);
  AddStatusOnlyRows(status, &rows);
  if (!manifest.empty()) AddManifestOnlyRows(manifest, &rows, &table.problems);
  for (auto& [input, file_rows] : rows) {
    ++table.recordings;
    for (CampaignRow& row : file_rows) table.rows.push_back(std::move(row));
  }
  return table;
}

void WriteCampaignTable(const std::string& path, const CampaignTable& table) {
  const fs::path final_path = fs::absolute(path);
  auto lock = hdf5::LockHdf5();
  hdf5::AtomicOutputFile out(final_path);
  hdf5::Group root = out.Root();
  root.WriteStringAttribute("fogpipe_format", kCampaignFormat);
  root.WriteInt64Attribute("rows", static_cast<long long>(table.rows.size()));
  root.WriteStringAttribute("source_folder", table.source_folder);
  hdf5::Group campaign = root.CreateGroup("campaign");
  for (const Column& column : Columns()) {
    if (column.number) {
      std::vector<double> values;
      for (const CampaignRow& row : table.rows) values.push_back(NumberOf(column, row));
      campaign.WriteDataset(column.name, values, column.units);
    } else {
      std::vector<std::string> values;
      for (const CampaignRow& row : table.rows) values.push_back(TextOf(column, row));
      campaign.WriteStringDataset(column.name, values);
    }
  }
  hdf5::Group links = root.CreateGroup("results");
  const fs::path campaign_folder = final_path.parent_path();
  std::string previous;
  for (const CampaignRow& row : table.rows) {
    if (row.results_file.empty() || row.results_file == previous) continue;
    previous = row.results_file;
    const fs::path target = fs::absolute(fs::path(table.source_folder) / row.results_file);
    const std::string relative = target.lexically_relative(campaign_folder).string();
    const std::string link_name =
        row.results_file.substr(0, row.results_file.size() - std::string(kResultsSuffix).size());
    if (H5Lcreate_external(relative.c_str(), "/", links.id(), link_name.c_str(), H5P_DEFAULT,
                           H5P_DEFAULT) < 0) {
      throw std::runtime_error(path + ": cannot create the external link to " + relative);
    }
  }
  out.Commit();
}

std::string FormatCampaignCsv(const CampaignTable& table) {
  const std::vector<Column> columns = Columns();
  std::vector<std::string> names;
  for (const Column& column : columns) names.push_back(CsvColumnName(column.name, column.units));
  std::ostringstream out;
  CsvWriter csv(out, {}, names);
  for (const CampaignRow& row : table.rows) {
    std::vector<std::string> fields;
    for (const Column& column : columns) {
      fields.push_back(column.number ? CsvNumber(NumberOf(column, row), 10) : TextOf(column, row));
    }
    csv.Row(fields);
  }
  return out.str();
}

CampaignTable ReadCampaignTable(const std::string& path) {
  auto lock = hdf5::LockHdf5();
  const hdf5::File file = hdf5::File::OpenReadOnly(path);
  const hdf5::Group root = file.Root();
  RequireFormatTag(root, path, kCampaignFormat);
  CampaignTable table;
  table.source_folder = root.ReadStringAttribute("source_folder");
  const long long rows = root.ReadInt64Attribute("rows");
  table.rows.resize(static_cast<std::size_t>(std::max(rows, 0ll)));
  const hdf5::Group campaign = root.OpenGroup("campaign");
  for (const Column& column : Columns()) {
    const hdf5::Dataset dataset = campaign.OpenDataset(column.name);
    const std::size_t length = dataset.dims().empty() ? 0 : dataset.dims()[0];
    if (length != table.rows.size()) {
      throw std::runtime_error(path + ": " + dataset.path() + " has " + std::to_string(length) +
                               " rows, the table " + std::to_string(rows));
    }
    if (column.number) {
      const std::vector<double> values = dataset.ReadDoubles();
      for (std::size_t i = 0; i < length; ++i) column.number(table.rows[i]) = values.at(i);
    } else {
      const std::vector<std::string> values = dataset.ReadStrings();
      for (std::size_t i = 0; i < length; ++i) column.text(table.rows[i]) = values.at(i);
    }
  }
  std::set<std::string> inputs;
  for (const CampaignRow& row : table.rows) inputs.insert(row.input_path);
  table.recordings = static_cast<int>(inputs.size());
  return table;
}

CampaignCounts CountRecordings(const CampaignTable& table) {
  CampaignCounts counts;
  std::string last;
  for (const CampaignRow& row : table.rows) {
    // Rows are sorted by input path: a recording's axes are adjacent and share its status.
    if (row.input_path == last) continue;
    last = row.input_path;
    counts.ok += row.status == "ok";
    counts.failed += row.status == "failed";
    counts.missing += row.status == "missing";
  }
  return counts;
}

std::string FormatCampaignSummary(const std::string& path, const CampaignTable& table) {
  const CampaignCounts counts = CountRecordings(table);
  std::ostringstream out;
  out << path << "\n"
      << "  source     " << table.source_folder << "\n"
      << "  table      " << table.rows.size() << " rows, " << table.recordings << " recordings ("
      << counts.ok << " ok, " << counts.failed << " failed, " << counts.missing << " missing)\n";
  // The raw signal's N, B and K: the terms a campaign compares across units.
  constexpr std::size_t kRaw = 0;
  constexpr std::array<std::size_t, 3> kTerms = {1, 2, 3};
  char text[512];
  std::snprintf(text, sizeof(text), "\n%-28s %-8s %-7s", "recording", "axis", "status");
  out << text;
  for (std::size_t t : kTerms) {
    const std::string head = std::string(kCampaignSignals[kRaw]) + " " + kCampaignTerms[t] + " [" +
                             allan::EngineeringUnit(static_cast<int>(t)) + "]";
    std::snprintf(text, sizeof(text), " %-24s", head.c_str());
    out << text;
  }
  out << " flags\n";
  for (const CampaignRow& row : table.rows) {
    const std::string name = fs::path(row.input_path).filename().string();
    std::snprintf(text, sizeof(text), "%-28s %-8s %-7s", name.c_str(),
                  row.axis.empty() ? "-" : row.axis.c_str(), row.status.c_str());
    out << text;
    for (std::size_t t : kTerms) {
      std::snprintf(
          text, sizeof(text), " %-24s",
          (FormatNumber(row.term[kRaw][t]) + " +- " + FormatNumber(row.term_std_error[kRaw][t]))
              .c_str());
      out << text;
    }
    std::string flags;
    auto add = [&flags](const std::string& flag) { flags += (flags.empty() ? "" : "; ") + flag; };
    if (!row.unreliable_terms[kRaw].empty()) add("unreliable " + row.unreliable_terms[kRaw]);
    if (!row.data_warning.empty()) add("data warning: " + row.data_warning);
    if (!row.message.empty()) add(row.message);
    out << " " << (flags.empty() ? "-" : flags) << "\n";
  }
  return out.str();
}

}  // namespace fogpipe::io
