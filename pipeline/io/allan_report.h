// The quick Allan report of one recording axis (`fogpipe allan`): tau grid parsing, the table in
// the recording's rate unit and in deg/h, the five IEEE noise terms, and its text / CSV / JSON
// renderings. The numbers come from fogpipe::allan (ComputeAllan, FitNoiseTerms); this file only
// chooses, converts and prints.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "algorithms/allan/allan.h"
#include "algorithms/allan/noise_fit.h"
#include "algorithms/common/units.h"

namespace fogpipe::io {

/// "oadev, adev, mdev, tdev, ohdev, hdev, totdev".
std::string DeviationList();
/// --deviation's help: every kind with what it is, its unit and which one is the default.
std::string DeviationHelp();

/// The units a table of `deviation` is printed in: rate kinds in the recording's unit and deg/h;
/// TDEV (an angle) in rad and arcsec. Labels are as printed ("deg/s"), tokens as in CSV / JSON
/// column names ("deg_s").
struct DeviationUnits {
  std::string primary;      ///< e.g. "deg/s", or "rad" for TDEV
  double primary_per_si;    ///< value in primary units per SI value (rad/s or rad)
  std::string engineering;  ///< "deg/h", or "arcsec" for TDEV
  double engineering_per_si;
};
DeviationUnits UnitsOf(allan::Deviation deviation, const std::string& rate_units,
                       units::RateUnit rate_unit);

/// Everything `fogpipe allan` prints.
struct AllanReport {
  std::string file;
  std::string axis;
  std::string rate_units;  ///< the recording's unit, e.g. "deg/s"
  units::RateUnit rate_unit = units::RateUnit::kRadPerSecond;
  double sample_rate_hz = 0.0;
  long long samples = 0;
  long long nan_bridged = 0;
  /// "" or why the column is suspect: a flagged run of one repeated value (repeated_samples.h).
  std::string data_warning;
  std::string taus;           ///< the grid as asked, e.g. "octave"
  double confidence = 0.683;  ///< of ci_low / ci_high
  allan::AllanTable table;    ///< SI: sigma, ci_low, ci_high in rad/s (TDEV: rad)
  bool fitted = true;         ///< false: no noise terms (the table is not an Allan variance)
  allan::NoiseFitResult fit;  ///< SI; meaningful only when fitted
};

/// Human-readable table + noise terms, units in every header.
void PrintAllanText(std::ostream& out, const AllanReport& report);
/// The table as CSV (pipeline/io/csv_writer.h; '#' comment lines before the header).
void PrintAllanCsv(std::ostream& out, const AllanReport& report);
/// One JSON object with the table and the terms (units in every key name).
nlohmann::json AllanReportJson(const AllanReport& report);
/// Several axes of one recording (`--axis all`): CSV with an `axis` column first (one header,
/// every axis's comment lines before it); JSON as {"file", "axes": [one object per axis]}.
void PrintAllanCsv(std::ostream& out, const std::vector<AllanReport>& reports);
nlohmann::json AllanReportJson(const std::vector<AllanReport>& reports);

}  // namespace fogpipe::io
