// Test-only readers for the external reference data in tests/data/allan-reference (see its
// README.md for provenance): Stable32 "STATISTICS FOR FILE" reports and plain data columns.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fogpipe::allan::testing {

/// One row of a Stable32 report: AF, Tau, #, Alpha, Min Sigma, Sigma, Max Sigma.
struct Stable32Row {
  long long m = 0;
  double tau_s = 0.0;
  long long count = 0;
  int alpha = 0;
  double min_sigma = 0.0;
  double sigma = 0.0;
  double max_sigma = 0.0;
};

inline std::string ReferencePath(const std::string& relative) {
  return std::string(FOGPIPE_TEST_DATA_DIR) + "/allan-reference/" + relative;
}

/// Rows of the Stable32 report at `path`. Header and comment lines start with '#'; a data row is
/// any other line with exactly seven numeric fields. Blank or malformed lines are skipped, so a
/// report with trailing text still parses.
inline std::vector<Stable32Row> ReadStable32ReportAt(const std::string& path) {
  std::ifstream in(path);
  std::vector<Stable32Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> v;
    double value;
    while (fields >> value) v.push_back(value);
    if (v.size() != 7 || !fields.eof()) continue;
    Stable32Row row;
    row.m = std::llround(v[0]);
    row.tau_s = v[1];
    row.count = std::llround(v[2]);
    row.alpha = static_cast<int>(std::lround(v[3]));
    row.min_sigma = v[4];
    row.sigma = v[5];
    row.max_sigma = v[6];
    rows.push_back(row);
  }
  return rows;
}

/// ReadStable32ReportAt of a file in tests/data/allan-reference.
inline std::vector<Stable32Row> ReadStable32Report(const std::string& relative) {
  return ReadStable32ReportAt(ReferencePath(relative));
}

/// The first numeric column of a text file; '#' lines and blank lines are skipped.
inline Eigen::VectorXd ReadColumn(const std::string& relative) {
  std::ifstream in(ReferencePath(relative));
  std::vector<double> values;
  std::string line;
  while (std::getline(in, line)) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    values.push_back(std::stod(line.substr(first)));
  }
  return Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

/// PHASE.DAT (phase x in s, tau0 = 1 s) as frequency: y_i = (x_{i+1} - x_i) / tau0.
inline Eigen::VectorXd PhaseDatFrequency() {
  const Eigen::VectorXd x = ReadColumn("phasedat/PHASE.DAT");
  return x.tail(x.size() - 1) - x.head(x.size() - 1);
}

inline constexpr long long kOcxoSamples = 19982;

/// The OCXO record as fractional frequency y = f / 1e7 - 1 (allantools
/// frequency2fractional(mean_frequency=1e7)), tau0 = 1 s.
inline Eigen::VectorXd OcxoFractionalFrequency() {
  return (ReadColumn("ocxo/ocxo_frequency.txt").array() / 1.0e7 - 1.0).matrix();
}

/// NIST SP 1065 / Riley 1000-point test set, regenerated from its published generator:
/// n_0 = 1234567890, n_{i+1} = 16807 n_i mod 2147483647, y_i = n_i / 2147483647, i = 0..999
/// (the set starts with n_0: y_0 = 0.5748904732, y_1 = 0.1841829699, as SP 1065 lists them).
inline Eigen::VectorXd Nbs1000Point() {
  Eigen::VectorXd y(1000);
  long long n = 1234567890;
  for (int i = 0; i < 1000; ++i) {
    y[i] = static_cast<double>(n) / 2147483647.0;
    n = (16807 * n) % 2147483647;
  }
  return y;
}

}  // namespace fogpipe::allan::testing
