#include "algorithms/method/tables.h"

#include <cstdio>
#include <limits>

#include "algorithms/ar/diagnostics.h"
#include "algorithms/method/method.h"

namespace fogpipe::method {
namespace {

FitRow MakeFitRow(const std::string& name, const ComponentModel& c) {
  FitRow row;
  row.component = name;
  row.order = c.fit.model.order;
  row.fit_one_step_percent = c.fit.diagnostics.fit_one_step_percent;
  row.fit_simulation_percent = c.fit.diagnostics.fit_simulation_percent;
  row.smoother_replaced = c.kalman.summary.smoother_replaced;
  return row;
}

NoiseRow MakeNoiseRow(const std::string& name, const AllanEvaluation& e) {
  NoiseRow row;
  row.signal = name;
  const allan::NoiseTermsEngineering t = allan::ToEngineeringUnits(e.noise.terms);
  row.q_arcsec = t.q_arcsec;
  row.n_deg_sqrt_h = t.n_deg_sqrt_h;
  row.b_deg_h = t.b_deg_h;
  row.k_deg_h_sqrt_h = t.k_deg_h_sqrt_h;
  row.r_deg_h2 = t.r_deg_h2;
  if (e.noise.dof > 0) row.chi2_per_dof = e.noise.chi2 / e.noise.dof;
  row.p_value = e.noise.p_value;
  for (int j = 0; j < allan::kNoiseTermCount; ++j)
    row.unreliable_reason[j] = e.noise.assessment[j].reason;
  const allan::NoiseTermsEngineering r = allan::ToEngineeringUnits(e.noise.slope_readoff);
  row.readoff = {r.q_arcsec, r.n_deg_sqrt_h, r.b_deg_h, r.k_deg_h_sqrt_h, r.r_deg_h2};
  return row;
}

}  // namespace

std::vector<FitRow> Table3(const MethodResult& result) {
  std::vector<FitRow> rows;
  rows.push_back(MakeFitRow("raw (method 2)", result.direct));
  const int n = static_cast<int>(result.components.size()) - 1;
  for (int k = 0; k <= n; ++k)
    rows.push_back(MakeFitRow(ComponentName(k, n), result.components[k]));
  return rows;
}

std::vector<NoiseRow> Table5(const MethodResult& result) {
  std::vector<NoiseRow> rows = {MakeNoiseRow("raw", result.raw_allan),
                                MakeNoiseRow("method 1", result.method1_allan),
                                MakeNoiseRow("method 2", result.method2_allan)};
  for (const ReferenceEvaluation& r : result.reference) {
    if (HasResult(r.allan.allan.summary.termination)) {
      rows.push_back(MakeNoiseRow(r.output.name, r.allan));
    } else {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      rows.push_back({r.output.name, nan, nan, nan, nan, nan});
    }
  }
  return rows;
}

std::string FormatTable3(const std::vector<FitRow>& rows) {
  std::string out;
  char line[160];
  std::snprintf(line, sizeof(line), "%-16s %5s %14s %14s\n", "component", "AR(p)", "fit 1-step %",
                "fit sim %");
  out += line;
  for (const FitRow& r : rows) {
    char simulation[32];
    if (ar::FreeRunDiverged(r.fit_simulation_percent)) {
      std::snprintf(simulation, sizeof(simulation), "%14s", "diverged");
    } else {
      std::snprintf(simulation, sizeof(simulation), "%14.2f", r.fit_simulation_percent);
    }
    std::snprintf(line, sizeof(line), "%-16s %5d %14.2f %s\n", r.component.c_str(), r.order,
                  r.fit_one_step_percent, simulation);
    out += line;
  }
  std::string replaced;
  for (const FitRow& r : rows)
    if (r.smoother_replaced) replaced += (replaced.empty() ? "" : ", ") + r.component;
  if (!replaced.empty()) {
    out += "  smoother: " + replaced +
           " output their filter's estimate (the record contradicts the model in the smoother's "
           "direction: smoothed residuals below the filtered ones)\n";
  }
  return out;
}

std::string FormatTable5(const std::vector<NoiseRow>& rows) {
  // Each term's slope read-off (IEEE 952 Annex C) beside it: a term that disagrees with it beyond
  // the noise fit's checks is marked '*' with the reason below the table.
  std::string out, symbols, term_units;
  char cell[64];
  std::snprintf(cell, sizeof(cell), "%-14s", "signal");
  symbols += cell;
  std::snprintf(cell, sizeof(cell), "%-14s", "");
  term_units += cell;
  for (int j = 0; j < 5; ++j) {
    std::snprintf(cell, sizeof(cell), " %13s  %13s", allan::TermSymbol(j),
                  (std::string(allan::TermSymbol(j)) + " read-off").c_str());
    symbols += cell;
    std::snprintf(cell, sizeof(cell), " %13s  %13s", allan::EngineeringUnit(j),
                  allan::EngineeringUnit(j));
    term_units += cell;
  }
  std::snprintf(cell, sizeof(cell), " %9s %9s\n", "chi2/dof", "p-value");
  out += symbols + cell;
  std::snprintf(cell, sizeof(cell), " %9s %9s\n", "1", "1");
  out += term_units + cell;
  std::string notes;
  for (const NoiseRow& r : rows) {
    const double value[5] = {r.q_arcsec, r.n_deg_sqrt_h, r.b_deg_h, r.k_deg_h_sqrt_h, r.r_deg_h2};
    std::snprintf(cell, sizeof(cell), "%-14s", r.signal.c_str());
    std::string line = cell;
    for (int j = 0; j < 5; ++j) {
      // '*' after a value: the noise fit marked the term unreliable (reasons below the table).
      std::snprintf(cell, sizeof(cell), " %13.4e%c %13.3e", value[j],
                    r.unreliable_reason[j].empty() ? ' ' : '*', r.readoff[j]);
      line += cell;
      if (!r.unreliable_reason[j].empty())
        notes +=
            "  * " + r.signal + " " + allan::TermSymbol(j) + ": " + r.unreliable_reason[j] + "\n";
    }
    std::snprintf(cell, sizeof(cell), " %9.3g %9.2g\n", r.chi2_per_dof, r.p_value);
    out += line + cell;
  }
  return out + notes;
}

}  // namespace fogpipe::method
