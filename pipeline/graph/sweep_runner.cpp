// Sweep file layout (<stem>.sweep.h5, format "fogpipe-sweep-v1", schemas/sweep-v1.json):
//   /                                   fogpipe_format, recording, rank_by
//   /axes/<axis>/emd_sifts_<S>/         one row per grid setting, one 1-D dataset per metric with a
//                                       `units` attribute (see Columns()); attributes num_imfs,
//                                       emd_sifts, has_truth, decompose_seconds, models_seconds
//     fit_one_step_percent [settings, components], fit_simulation_percent [settings, components]
//     ar_order_used [settings, components] (the order each filter ran; ar::SelectStationaryOrder)
//     ranking                           row indices, best first by rank_by
//   /reference/<axis>/emd_sifts_<S>/    the reference filters scored like settings, one row each:
//                                       name, parameter (+ parameter_name, parameter_units), the
//                                       Columns() terms
//                                       that apply (Q..R with std errors, rms_error, seconds),
//                                       grid_rank (grid settings ranked strictly better; -1: none)
#include "pipeline/graph/sweep_runner.h"

#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "algorithms/common/units.h"
#include "pipeline/graph/progress.h"
#include "pipeline/graph/tbb_for_each.h"
#include "pipeline/hdf5/atomic_output_file.h"
#include "pipeline/hdf5/file.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/csv_writer.h"
#include "pipeline/io/file_validation.h"
#include "pipeline/io/isolated_reader.h"
#include "pipeline/io/recording_reader.h"
#include "pipeline/io/recording_writer.h"
#include "pipeline/io/text_output_file.h"

namespace fogpipe::graph {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// One numeric column of a sweep table.
struct Column {
  std::string name;
  std::string units;
  std::function<double(const method::SweepPoint&)> value;
};

double Term(const method::SweepPoint& p, double allan::NoiseTermsEngineering::*member) {
  if (!HasResult(p.termination)) return kNaN;
  return allan::ToEngineeringUnits(p.allan.noise.terms).*member;
}

std::vector<Column> Columns() {
  using E = allan::NoiseTermsEngineering;
  std::vector<Column> c = {
      {"ar_order", "1", [](const auto& p) { return double(p.setting.ar_order); }},
      // 1 for `fogpipe run`'s own rule (q from noise_defaults.h, R = R_k): its scales are NaN.
      {"default_rule", "1", [](const auto& p) { return p.setting.default_rule ? 1.0 : 0.0; }},
      {"q_scale", "1",
       [](const auto& p) { return p.setting.default_rule ? kNaN : p.setting.q_scale; }},
      {"r_scale", "1",
       [](const auto& p) { return p.setting.default_rule ? kNaN : p.setting.r_scale; }},
      {"fit_one_step_mean_percent", "%",
       [](const auto& p) { return method::CriterionValue(p, "fit"); }}};
  const struct {
    const char* name;
    double E::*value;
    double E::*se;
    const char* units;
  } terms[] = {{"Q", &E::q_arcsec, &E::q_se, units::kQuantizationUnit},
               {"N", &E::n_deg_sqrt_h, &E::n_se, units::kArwUnit},
               {"B", &E::b_deg_h, &E::b_se, units::kBiasUnit},
               {"K", &E::k_deg_h_sqrt_h, &E::k_se, units::kRrwUnit},
               {"R", &E::r_deg_h2, &E::r_se, units::kRampUnit}};
  for (const auto& t : terms) {
    const auto value = t.value, se = t.se;
    c.push_back({t.name, t.units, [value](const auto& p) { return Term(p, value); }});
    c.push_back(
        {std::string(t.name) + "_std_error", t.units, [se](const auto& p) { return Term(p, se); }});
  }
  c.push_back({"rms_error", units::kBiasUnit, [](const auto& p) {
                 return HasResult(p.termination) ? units::RadPerSecondToDegPerHour(p.rms_error)
                                                 : kNaN;
               }});
  c.push_back({"seconds", "s", [](const auto& p) { return p.seconds; }});
  return c;
}

std::string EffectiveRankBy(const SweepTable& table, const std::string& rank_by) {
  return rank_by == "rms_error" && !table.has_truth ? "n" : rank_by;
}

std::string Format(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

void WriteReferenceRows(hdf5::Group root, const SweepTable& table, const std::string& by,
                        const std::vector<Column>& columns) {
  const std::vector<method::SweepReference>& refs = table.result.reference;
  if (refs.empty()) return;
  hdf5::Group g =
      root.CreateGroup("reference/" + table.axis + "/emd_sifts_" + std::to_string(table.emd_sifts));
  std::vector<std::string> names, parameter_names, parameter_units, status;
  std::vector<double> parameter;
  std::vector<long long> grid_rank;
  for (const auto& r : refs) {
    names.push_back(r.name);
    parameter_names.push_back(r.parameter_name);
    parameter_units.push_back(r.parameter_units);
    parameter.push_back(r.parameter);
    status.push_back(HasResult(r.point.termination) ? "ok" : r.point.message);
    grid_rank.push_back(method::RankAmongGrid(table.result.points, r.point, by));
  }
  g.WriteStringDataset("name", names);
  g.WriteStringDataset("parameter_name", parameter_names);
  g.WriteStringDataset("parameter_units", parameter_units);
  g.WriteDataset("parameter", parameter, "see parameter_units");
  g.WriteStringDataset("status", status);
  g.WriteDataset("grid_rank", grid_rank, "1");
  for (const Column& column : columns) {
    const bool applies = column.name == "rms_error" || column.name == "seconds" ||
                         column.name.size() == 1 || column.name.find("_std_error") == 1;
    if (!applies) continue;
    std::vector<double> values;
    for (const auto& r : refs) values.push_back(column.value(r.point));
    g.WriteDataset(column.name, values, column.units);
  }
}

}  // namespace

bool SweepRecording(const std::string& recording, const SweepRunOptions& options,
                    std::vector<SweepTable>* tables, std::string* error) {
  tables->clear();
  io::RecordingInfo info;
  std::optional<Eigen::VectorXd> truth;
  try {
    info = io::InspectRecordingIsolated(recording);
    const std::string sidecar = io::TruthSidecarPath(recording);
    if (fs::exists(sidecar)) {
      std::ifstream in(sidecar);
      truth = io::TrueRateFromTruth(nlohmann::json::parse(in));
    }
  } catch (const std::exception& e) {
    *error = recording + ": " + e.what();
    return false;
  }
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(std::max(1, options.threads)));
  bool redraw = false;
  std::FILE* progress_stream = ProgressStream(options.progress, &redraw);
  WorkProgress progress("sweep " + recording, progress_stream, redraw);
  const std::size_t table_count = info.axis_names.size() * options.emd_sifts.size();
  for (const std::string& axis : info.axis_names) {
    progress.Step("axis " + axis + ": reading");
    Eigen::VectorXd x;
    try {
      x = io::ReadAxisRadPerSecondIsolated(info, axis, options.read);
    } catch (const std::exception& e) {
      *error = recording + ": axis " + axis + ": " + e.what();
      return false;
    }
    if (truth && truth->size() != x.size()) {
      *error = recording + ": the truth sidecar has " + std::to_string(truth->size()) +
               " samples, the recording " + std::to_string(x.size());
      return false;
    }
    for (int sifts : options.emd_sifts) {
      method::SweepOptions sweep = options.sweep;
      sweep.method.emd.fixed_sifts = sifts;
      sweep.method.emd.max_sifts = std::max(sweep.method.emd.max_sifts, sifts);
      SweepTable table;
      table.recording = recording;
      table.axis = axis;
      table.emd_sifts = sifts;
      table.has_truth = truth.has_value();
      progress.Step("table " + std::to_string(tables->size() + 1) + "/" +
                    std::to_string(table_count) + " (axis " + axis + ", " + std::to_string(sifts) +
                    " sifts)");
      table.result = method::RunSweep(x, info.sample_rate_hz, sweep, truth ? &*truth : nullptr,
                                      progress.Counting(TbbForEach));
      if (!HasResult(table.result.summary.termination)) {
        *error = recording + ": axis " + axis + ": " + table.result.summary.message;
        return false;
      }
      tables->push_back(std::move(table));
    }
  }
  const std::string stem = fs::path(recording).stem().string();
  const fs::path out = fs::path(options.output_dir) / (stem + ".sweep");
  progress.Step("writing " + out.string() + ".h5 and .csv");
  progress.Finish();
  try {
    fs::create_directories(options.output_dir);
    WriteSweepHdf5(out.string() + ".h5", *tables, options.rank_by);
    io::WriteTextFileAtomically(out.string() + ".csv", FormatSweepCsv(*tables));
  } catch (const std::exception& e) {
    *error = recording + ": " + e.what();
    return false;
  }
  if (options.report_stream != nullptr) {
    std::fputs(FormatSweepRanking(SummarizeSweep(*tables, options.rank_by, options.top)).c_str(),
               options.report_stream);
  }
  return true;
}

void WriteSweepHdf5(const std::string& path, const std::vector<SweepTable>& tables,
                    const std::string& rank_by) {
  auto lock = hdf5::LockHdf5();
  hdf5::AtomicOutputFile out{fs::absolute(path)};
  hdf5::Group root = out.Root();
  root.WriteStringAttribute("fogpipe_format", kSweepFormat);
  root.WriteStringAttribute("recording", tables.empty() ? "" : tables.front().recording);
  root.WriteStringAttribute("rank_by", rank_by);
  const std::vector<Column> columns = Columns();
  for (const SweepTable& table : tables) {
    hdf5::Group g =
        root.CreateGroup("axes/" + table.axis + "/emd_sifts_" + std::to_string(table.emd_sifts));
    const method::SweepResult& r = table.result;
    g.WriteInt64Attribute("num_imfs", r.summary.num_imfs);
    g.WriteInt64Attribute("emd_sifts", table.emd_sifts);
    g.WriteInt64Attribute("has_truth", table.has_truth ? 1 : 0);
    g.WriteDoubleAttribute("decompose_seconds", r.summary.decompose_seconds);
    g.WriteDoubleAttribute("models_seconds", r.summary.models_seconds);
    for (const Column& column : columns) {
      std::vector<double> values;
      for (const auto& point : r.points) values.push_back(column.value(point));
      g.WriteDataset(column.name, values, column.units);
    }
    const hsize_t rows = r.points.size();
    const hsize_t cols = static_cast<hsize_t>(r.summary.num_imfs) + 1;
    std::vector<double> one_step, simulation;
    for (const auto& point : r.points) {
      for (hsize_t k = 0; k < cols; ++k) {
        const bool has = k < point.fit_one_step_percent.size();
        one_step.push_back(has ? point.fit_one_step_percent[k] : kNaN);
        simulation.push_back(has ? point.fit_simulation_percent[k] : kNaN);
      }
    }
    g.WriteDataset("fit_one_step_percent", one_step.data(), {rows, cols}, "%");
    g.WriteDataset("fit_simulation_percent", simulation.data(), {rows, cols}, "%");
    std::vector<double> orders_used;  // small integers, exact as doubles (the 2-D writer's type)
    for (const auto& point : r.points) {
      for (hsize_t k = 0; k < cols; ++k)
        orders_used.push_back(k < point.ar_order_used.size() ? point.ar_order_used[k] : 0.0);
    }
    g.WriteDataset("ar_order_used", orders_used.data(), {rows, cols}, "1");
    std::vector<std::string> status;
    for (const auto& point : r.points) {
      status.push_back(HasResult(point.termination) ? "ok" : point.message);
    }
    g.WriteStringDataset("status", status);
    std::vector<long long> ranking;
    for (int i : method::RankSweep(r.points, EffectiveRankBy(table, rank_by))) ranking.push_back(i);
    g.WriteDataset("ranking", ranking, "1");
    g.OpenDataset("ranking").WriteStringAttribute("rank_by", EffectiveRankBy(table, rank_by));
    WriteReferenceRows(root, table, EffectiveRankBy(table, rank_by), columns);
  }
  out.Commit();
}

std::string FormatSweepCsv(const std::vector<SweepTable>& tables) {
  const std::vector<Column> columns = Columns();
  std::vector<std::string> names = {"recording", "axis", "emd_sifts"};
  for (const Column& c : columns) names.push_back(io::CsvColumnName(c.name, c.units));
  names.push_back("fit_one_step_percent_per_component");  // ';'-separated, one per component
  names.push_back("status");
  std::ostringstream out;
  io::CsvWriter csv(out, {}, names);
  for (const SweepTable& table : tables) {
    for (const auto& point : table.result.points) {
      std::vector<std::string> fields = {table.recording, table.axis,
                                         std::to_string(table.emd_sifts)};
      for (const Column& c : columns) fields.push_back(io::CsvNumber(c.value(point), 6));
      std::string per_component;
      for (std::size_t k = 0; k < point.fit_one_step_percent.size(); ++k) {
        per_component += (k ? ";" : "") + io::CsvNumber(point.fit_one_step_percent[k], 6);
      }
      fields.push_back(per_component);
      fields.push_back(HasResult(point.termination) ? "ok" : "failed");
      csv.Row(fields);
    }
  }
  return out.str();
}

namespace {

/// The rows shown for comparison beside the top of the ranking: `fogpipe run`'s rule and the
/// hardest filtering (smallest q / R), each at the best-ranked AR order among its own settings
/// (-1 when there is none).
std::pair<int, int> DefaultAndHardest(const std::vector<int>& ranking,
                                      const std::vector<method::SweepSetting>& settings) {
  int default_best = -1, hardest_best = -1;
  double hardest_ratio = std::numeric_limits<double>::infinity();
  for (const auto& s : settings) {
    if (!s.default_rule) hardest_ratio = std::min(hardest_ratio, s.q_scale / s.r_scale);
  }
  for (int i : ranking) {
    const auto& s = settings[i];
    if (default_best < 0 && s.default_rule) default_best = i;
    if (hardest_best < 0 && !s.default_rule && s.q_scale / s.r_scale == hardest_ratio) {
      hardest_best = i;
    }
  }
  return {default_best, hardest_best};
}

/// The lines of one table's summary: the top of `ranking`, then the comparison rows.
std::vector<SweepRankedLine> RankedLines(const std::vector<int>& ranking,
                                         const std::vector<method::SweepSetting>& settings, int top,
                                         const std::function<SweepRankedLine(int)>& line) {
  std::vector<SweepRankedLine> lines;
  for (int r = 0; r < static_cast<int>(ranking.size()) && r < top; ++r) {
    lines.push_back(line(ranking[r]));
    lines.back().label = std::to_string(r + 1);
  }
  const auto [default_best, hardest_best] = DefaultAndHardest(ranking, settings);
  if (default_best >= 0) lines.push_back(line(default_best)), lines.back().label = "dflt";
  if (hardest_best >= 0) lines.push_back(line(hardest_best)), lines.back().label = "hard";
  return lines;
}

}  // namespace

std::vector<SweepTableSummary> SummarizeSweep(const std::vector<SweepTable>& tables,
                                              const std::string& rank_by, int top) {
  std::vector<SweepTableSummary> out;
  for (const SweepTable& table : tables) {
    const auto& points = table.result.points;
    SweepTableSummary s;
    s.recording = table.recording;
    s.axis = table.axis;
    s.emd_sifts = table.emd_sifts;
    s.num_imfs = table.result.summary.num_imfs;
    s.decompose_seconds = table.result.summary.decompose_seconds;
    s.rank_by = EffectiveRankBy(table, rank_by);
    s.settings = static_cast<int>(points.size());
    std::vector<method::SweepSetting> settings;
    for (const auto& p : points) settings.push_back(p.setting);
    s.lines = RankedLines(method::RankSweep(points, s.rank_by), settings, top, [&](int i) {
      const auto& p = points[i];
      return SweepRankedLine{"",
                             p.setting,
                             method::CriterionValue(p, "fit"),
                             method::CriterionValue(p, "n"),
                             method::CriterionValue(p, "k"),
                             units::RadPerSecondToDegPerHour(p.rms_error)};
    });
    for (const method::SweepReference& r : table.result.reference) {
      s.references.push_back({r.name, r.parameter_name, r.parameter_units, r.parameter,
                              method::CriterionValue(r.point, "n"),
                              method::CriterionValue(r.point, "k"),
                              units::RadPerSecondToDegPerHour(r.point.rms_error),
                              method::RankAmongGrid(points, r.point, s.rank_by)});
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<SweepTableSummary> ReadSweepSummary(const std::string& path, int top) {
  auto lock = hdf5::LockHdf5();
  const hdf5::File file = hdf5::File::OpenReadOnly(path);
  const hdf5::Group root = file.Root();
  io::RequireFormatTag(root, path, kSweepFormat);
  const std::string recording = root.ReadStringAttribute("recording");
  std::vector<SweepTableSummary> out;
  const hdf5::Group axes = root.OpenGroup("axes");
  for (const std::string& axis : axes.ChildNames()) {
    for (const std::string& sifts : axes.OpenGroup(axis).ChildNames()) {
      const hdf5::Group g = axes.OpenGroup(axis + "/" + sifts);
      SweepTableSummary s;
      s.recording = recording;
      s.axis = axis;
      s.emd_sifts = static_cast<int>(g.ReadInt64Attribute("emd_sifts"));
      s.num_imfs = static_cast<int>(g.ReadInt64Attribute("num_imfs"));
      s.decompose_seconds = g.ReadDoubleAttribute("decompose_seconds");
      s.rank_by = g.OpenDataset("ranking").ReadStringAttribute("rank_by");
      auto column = [&](const char* name) { return g.OpenDataset(name).ReadDoubles(); };
      const std::vector<double> order = column("ar_order"), rule = column("default_rule"),
                                q = column("q_scale"), r = column("r_scale"),
                                fit = column("fit_one_step_mean_percent"), n = column("N"),
                                k = column("K"), rms = column("rms_error");
      s.settings = static_cast<int>(order.size());
      std::vector<method::SweepSetting> settings(order.size());
      for (std::size_t i = 0; i < order.size(); ++i) {
        settings[i].ar_order = static_cast<int>(order[i]);
        settings[i].default_rule = i < rule.size() && rule[i] != 0.0;
        // The file stores NaN scales for the default rule, whose scales are 1 and unused.
        settings[i].q_scale = settings[i].default_rule || i >= q.size() ? 1.0 : q[i];
        settings[i].r_scale = settings[i].default_rule || i >= r.size() ? 1.0 : r[i];
      }
      std::vector<int> ranking;
      for (double i : g.OpenDataset("ranking").ReadDoubles()) {
        if (i < 0 || i >= static_cast<double>(order.size())) {
          throw std::runtime_error(path + ": " + g.path() + "/ranking names row " + Format(i) +
                                   " of " + std::to_string(order.size()));
        }
        ranking.push_back(static_cast<int>(i));
      }
      auto at = [](const std::vector<double>& v, int i) {
        return i < static_cast<int>(v.size()) ? v[i] : kNaN;
      };
      s.lines = RankedLines(ranking, settings, top, [&](int i) {
        return SweepRankedLine{"", settings[i], at(fit, i), at(n, i), at(k, i), at(rms, i)};
      });
      const std::string reference = "reference/" + axis + "/" + sifts;
      if (root.KindOf(reference) == hdf5::ObjectKind::kGroup) {
        const hdf5::Group ref = root.OpenGroup(reference);
        const std::vector<std::string> names = ref.OpenDataset("name").ReadStrings();
        // Optional in the layout: a table without it shows the value and units alone.
        const std::vector<std::string> parameter_names =
            ref.KindOf("parameter_name") == hdf5::ObjectKind::kDataset
                ? ref.OpenDataset("parameter_name").ReadStrings()
                : std::vector<std::string>{};
        const std::vector<std::string> parameter_units =
            ref.OpenDataset("parameter_units").ReadStrings();
        const std::vector<double> parameter = ref.OpenDataset("parameter").ReadDoubles(),
                                  ref_n = ref.OpenDataset("N").ReadDoubles(),
                                  ref_k = ref.OpenDataset("K").ReadDoubles(),
                                  ref_rms = ref.OpenDataset("rms_error").ReadDoubles(),
                                  grid_rank = ref.OpenDataset("grid_rank").ReadDoubles();
        for (std::size_t i = 0; i < names.size(); ++i) {
          const int j = static_cast<int>(i);
          s.references.push_back({names[i], i < parameter_names.size() ? parameter_names[i] : "",
                                  i < parameter_units.size() ? parameter_units[i] : "",
                                  at(parameter, j), at(ref_n, j), at(ref_k, j), at(ref_rms, j),
                                  i < grid_rank.size() ? static_cast<int>(grid_rank[i]) : -1});
        }
      }
      out.push_back(std::move(s));
    }
  }
  return out;
}

std::string FormatSweepRanking(const std::vector<SweepTableSummary>& summaries) {
  std::ostringstream out;
  for (const SweepTableSummary& s : summaries) {
    out << s.recording << "  axis " << s.axis << "  emd_sifts " << s.emd_sifts << "  ("
        << s.settings << " settings, " << s.num_imfs << " IMFs, EMD " << Format(s.decompose_seconds)
        << " s; ranked by " << s.rank_by << ")\n";
    out << "  rank  order  q_scale  r_scale  fit% (mean)   N [deg/sqrt(h)]   K [deg/h/sqrt(h)]"
        << "   RMS error vs truth [deg/h]\n";
    for (const SweepRankedLine& l : s.lines) {
      char text[200];
      std::snprintf(text, sizeof(text), "  %-5s %5d  %7s  %7s  %11.4g  %16.5g  %18.5g  %27.5g\n",
                    l.label.c_str(), l.setting.ar_order,
                    l.setting.default_rule ? "rule" : Format(l.setting.q_scale).c_str(),
                    l.setting.default_rule ? "rule" : Format(l.setting.r_scale).c_str(),
                    l.fit_percent, l.n, l.k, l.rms_error_deg_h);
      out << text;
    }
    // The reference filters, tuned without the truth, with their place among the grid.
    for (const SweepReferenceLine& r : s.references) {
      char text[240];
      std::snprintf(text, sizeof(text),
                    "  ref   %-14s %s = %-10.4g %-7s  N %.5g  K %.5g  RMS vs truth %.5g deg/h  "
                    "(ranks %s of the grid)\n",
                    r.name.c_str(), r.parameter_name.c_str(), r.parameter,
                    r.parameter_units.c_str(), r.n, r.k, r.rms_error_deg_h,
                    r.grid_rank < 0 ? "-" : std::to_string(r.grid_rank + 1).c_str());
      out << text;
    }
  }
  return out.str();
}

}  // namespace fogpipe::graph
