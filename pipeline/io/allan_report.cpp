#include "pipeline/io/allan_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "pipeline/io/csv_writer.h"
#include "pipeline/io/noise_fit_report.h"

namespace fogpipe::io {
namespace {

/// What each kind is, for --help; the unit is added from UnitsOf.
const char* Description(allan::Deviation deviation) {
  switch (deviation) {
    case allan::Deviation::kOverlappingAllan:
      return "overlapping Allan (IEEE 952 terms fitted)";
    case allan::Deviation::kAllan:
      return "non-overlapping Allan (IEEE 952 terms fitted)";
    case allan::Deviation::kModifiedAllan:
      return "modified Allan, separates white from flicker angle noise";
    case allan::Deviation::kTime:
      return "time deviation tau MDEV / sqrt(3), an angle";
    case allan::Deviation::kOverlappingHadamard:
      return "overlapping Hadamard, blind to a rate ramp";
    case allan::Deviation::kHadamard:
      return "non-overlapping Hadamard";
    case allan::Deviation::kTotal:
      return "total (doubly reflected), tighter bounds at long tau";
  }
  return "";
}

/// The IEEE 952 terms are not fitted on this table: why, for the text and the JSON.
std::string NotFittedReason(allan::Deviation deviation) {
  return std::string("not fitted: the IEEE 952 terms are coefficients of the Allan variance; ") +
         allan::ToString(deviation) +
         " responds differently to the same noises (use --deviation oadev or adev)";
}

std::string Fixed(double value, const char* format) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

/// JSON cannot hold NaN or Inf: those become null.
nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

}  // namespace

std::string DeviationList() {
  std::string list;
  for (allan::Deviation d : allan::AllDeviations())
    list += (list.empty() ? "" : ", ") + std::string(allan::ToString(d));
  return list;
}

std::string DeviationHelp() {
  std::string help = "Which deviation, in the units shown:";
  for (allan::Deviation d : allan::AllDeviations()) {
    help += std::string("\n  ") + allan::ToString(d) + ": " + Description(d) + " [" +
            (allan::IsTimeDeviation(d) ? "rad and arcsec" : "recording's unit and deg/h") + "]";
  }
  return help;
}

DeviationUnits UnitsOf(allan::Deviation deviation, const std::string& rate_units,
                       units::RateUnit rate_unit) {
  if (allan::IsTimeDeviation(deviation)) return {"rad", 1.0, "arcsec", units::kArcsecPerRad};
  return {rate_units, 1.0 / units::ToRadPerSecond(rate_unit), "deg/h",
          units::RadPerSecondToDegPerHour(1.0)};
}

void PrintAllanText(std::ostream& out, const AllanReport& r) {
  const allan::AllanTable& t = r.table;
  const DeviationUnits du = UnitsOf(t.deviation, r.rate_units, r.rate_unit);
  const std::string e = " [" + du.engineering + "]";
  out << "fogpipe allan: " << r.file << ", axis " << r.axis << "\n"
      << "  " << r.samples << " samples at " << r.sample_rate_hz << " Hz ("
      << Fixed(r.samples / r.sample_rate_hz / 3600.0, "%.3f") << " h), rate in " << r.rate_units;
  if (r.nan_bridged > 0) out << ", " << r.nan_bridged << " missing samples bridged";
  if (!r.data_warning.empty()) out << "\n  warning: " << r.data_warning;
  out << "\n  " << allan::ToString(t.deviation) << " on the " << r.taus << " grid, "
      << Fixed(100.0 * r.confidence, "%.1f") << " % confidence interval (Stable32 convention), "
      << "noise types by the " << allan::ToString(t.noise_id_rule) << " rule\n"
      << "  alpha: S_y(f) ~ f^alpha, 2 white PM, 1 flicker PM, 0 white FM, -1 flicker FM, -2 "
         "random-walk FM\n"
      << "  EDF from: noise_type = Greenhall's EDF of alpha, model = the fitted noise terms' "
         "(where the fit holds)\n\n";
  out << std::setw(14) << "tau [s]" << std::setw(10) << "m" << std::setw(15)
      << "sigma [" + du.primary + "]" << std::setw(16) << "sigma" + e << std::setw(16)
      << "ci_low" + e << std::setw(17) << "ci_high" + e << std::setw(10) << "EDF" << std::setw(11)
      << "EDF from" << std::setw(7) << "alpha" << std::setw(9) << "method" << std::setw(11)
      << "count"
      << "\n";
  for (size_t i = 0; i < t.size(); ++i) {
    out << std::setw(14) << Fixed(t.tau_s[i], "%.6g") << std::setw(10) << t.m[i] << std::setw(15)
        << Fixed(t.sigma[i] * du.primary_per_si, "%.6e") << std::setw(16)
        << Fixed(t.sigma[i] * du.engineering_per_si, "%.6e") << std::setw(16)
        << Fixed(t.ci_low[i] * du.engineering_per_si, "%.6e") << std::setw(17)
        << Fixed(t.ci_high[i] * du.engineering_per_si, "%.6e") << std::setw(10)
        << Fixed(t.edf[i], "%.4g") << std::setw(11) << allan::ToString(t.edf_source[i])
        << std::setw(7) << t.alpha[i] << std::setw(9) << allan::ToString(t.alpha_method[i])
        << std::setw(11) << t.count[i] << "\n";
  }
  if (!r.fitted) {
    out << "\nNoise terms: " << NotFittedReason(t.deviation) << ".\n";
    return;
  }
  PrintNoiseFitText(out, r.fit);
  out << "  " << NoiseTypeCrossCheckLine(t, r.fit) << "\n";
}

namespace {

std::vector<std::string> AllanCsvComments(const AllanReport& r) {
  std::ostringstream about;
  about << "fogpipe allan: " << r.file << ", axis " << r.axis << ", " << r.samples << " samples at "
        << r.sample_rate_hz << " Hz, " << allan::ToString(r.table.deviation) << ", " << r.taus
        << " taus, CI " << r.confidence << ", noise types by the "
        << allan::ToString(r.table.noise_id_rule) << " rule";
  std::vector<std::string> comments = {about.str()};
  if (!r.data_warning.empty()) comments.push_back("warning: " + r.data_warning);
  return comments;
}

// The comments of every report, one header and the rows of every report; with `axis_column`
// each row starts with its axis. The reports share the recording, so they share the units of the
// header.
void PrintAllanCsvTable(std::ostream& out, const std::vector<AllanReport>& reports,
                        bool axis_column) {
  const AllanReport& first = reports.front();
  const DeviationUnits du = UnitsOf(first.table.deviation, first.rate_units, first.rate_unit);
  std::vector<std::string> comments;
  for (const AllanReport& r : reports) {
    const std::vector<std::string> c = AllanCsvComments(r);
    comments.insert(comments.end(), c.begin(), c.end());
  }
  // A recording in the engineering unit (deg/h) has one sigma column, not two of the same name.
  const bool both = CsvUnitToken(du.primary) != CsvUnitToken(du.engineering);
  std::vector<std::string> columns;
  if (axis_column) columns.push_back("axis");
  columns.insert(columns.end(), {"tau_s", "m"});
  if (both) columns.push_back(CsvColumnName("sigma", du.primary));
  for (const char* name : {"sigma", "ci_low", "ci_high"}) {
    columns.push_back(CsvColumnName(name, du.engineering));
  }
  for (const char* name : {"edf", "edf_source", "alpha", "alpha_method", "count"}) {
    columns.push_back(name);
  }
  CsvWriter csv(out, comments, columns);
  auto g = [](double v) { return CsvNumber(v, 17); };
  for (const AllanReport& r : reports) {
    const allan::AllanTable& t = r.table;
    for (size_t i = 0; i < t.size(); ++i) {
      std::vector<std::string> row;
      if (axis_column) row.push_back(r.axis);
      row.insert(row.end(), {g(t.tau_s[i]), std::to_string(t.m[i])});
      if (both) row.push_back(g(t.sigma[i] * du.primary_per_si));
      row.insert(row.end(),
                 {g(t.sigma[i] * du.engineering_per_si), g(t.ci_low[i] * du.engineering_per_si),
                  g(t.ci_high[i] * du.engineering_per_si), g(t.edf[i]),
                  allan::ToString(t.edf_source[i]), std::to_string(t.alpha[i]),
                  allan::ToString(t.alpha_method[i]), std::to_string(t.count[i])});
      csv.Row(row);
    }
  }
}

}  // namespace

void PrintAllanCsv(std::ostream& out, const AllanReport& r) { PrintAllanCsvTable(out, {r}, false); }

void PrintAllanCsv(std::ostream& out, const std::vector<AllanReport>& reports) {
  if (reports.empty()) return;
  PrintAllanCsvTable(out, reports, true);
}

nlohmann::json AllanReportJson(const AllanReport& r) {
  const allan::AllanTable& t = r.table;
  const DeviationUnits du = UnitsOf(t.deviation, r.rate_units, r.rate_unit);
  nlohmann::json table;
  std::vector<nlohmann::json> sigma_file, sigma_eng, low, high, edf;
  for (size_t i = 0; i < t.size(); ++i) {
    sigma_file.push_back(Number(t.sigma[i] * du.primary_per_si));
    sigma_eng.push_back(Number(t.sigma[i] * du.engineering_per_si));
    low.push_back(Number(t.ci_low[i] * du.engineering_per_si));
    high.push_back(Number(t.ci_high[i] * du.engineering_per_si));
    edf.push_back(Number(t.edf[i]));
  }
  table["tau_s"] = t.tau_s;
  table["m"] = t.m;
  table[CsvColumnName("sigma", du.primary)] = sigma_file;
  table[CsvColumnName("sigma", du.engineering)] = sigma_eng;
  table[CsvColumnName("ci_low", du.engineering)] = low;
  table[CsvColumnName("ci_high", du.engineering)] = high;
  table["edf"] = edf;
  table["edf_source"] = allan::EdfSourceNames(t.edf_source);
  table["alpha"] = t.alpha;
  table["alpha_method"] = allan::MethodNames(t.alpha_method);
  table["noise_id_rule"] = allan::ToString(t.noise_id_rule);
  table["count"] = t.count;
  auto terms_json = [](const allan::NoiseTerms& terms) {
    const allan::NoiseTermsEngineering e = allan::ToEngineeringUnits(terms);
    return nlohmann::json{{"q_arcsec", Number(e.q_arcsec)},
                          {"q_arcsec_se", Number(e.q_se)},
                          {"n_deg_sqrt_h", Number(e.n_deg_sqrt_h)},
                          {"n_deg_sqrt_h_se", Number(e.n_se)},
                          {"b_deg_h", Number(e.b_deg_h)},
                          {"b_deg_h_se", Number(e.b_se)},
                          {"k_deg_h_sqrt_h", Number(e.k_deg_h_sqrt_h)},
                          {"k_deg_h_sqrt_h_se", Number(e.k_se)},
                          {"r_deg_h2", Number(e.r_deg_h2)},
                          {"r_deg_h2_se", Number(e.r_se)}};
  };
  nlohmann::json report{
      {"file", r.file},
      {"axis", r.axis},
      {"rate_units", r.rate_units},
      {"sample_rate_hz", r.sample_rate_hz},
      {"samples", r.samples},
      {"nan_bridged", r.nan_bridged},
      {"data_warning", r.data_warning},
      {"deviation", allan::ToString(t.deviation)},
      {"deviation_units", du.primary},
      {"taus", r.taus},
      {"confidence", r.confidence},
      {"table", table},
  };
  if (!r.fitted) {
    report["noise_terms"] = nullptr;
    report["noise_fit"] = {{"termination", "not_fitted"},
                           {"message", NotFittedReason(t.deviation)}};
    return report;
  }
  report["noise_terms"] = terms_json(r.fit.terms);
  report["model_alpha"] = allan::ModelDominantAlpha(r.fit.terms, t.tau_s);
  report["noise_fit"] = {{"termination", ToString(r.fit.summary.termination)},
                         {"message", r.fit.summary.message},
                         {"points", r.fit.summary.points},
                         {"chi2", Number(r.fit.chi2)},
                         {"dof", r.fit.dof},
                         {"p_value", Number(r.fit.p_value)},
                         {"generalized", r.fit.generalized},
                         {"misfit_tau_ranges", allan::FormatTauRanges(r.fit.misfit_ranges)},
                         {"terms", NoiseFitAssessmentJson(r.fit)}};
  report["slope_readoff"] = terms_json(r.fit.slope_readoff);
  return report;
}

nlohmann::json AllanReportJson(const std::vector<AllanReport>& reports) {
  nlohmann::json axes = nlohmann::json::array();
  for (const AllanReport& r : reports) axes.push_back(AllanReportJson(r));
  return {{"file", reports.empty() ? "" : reports.front().file}, {"axes", axes}};
}

}  // namespace fogpipe::io
