// Helpers shared by the import tests (text_import_test.cpp, matlab_import_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "pipeline/io/recording_import.h"

namespace fogpipe::testing {

/// Writes `text` byte for byte to `path` and returns the path.
inline std::string WriteTextFile(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

/// The import failed and its message holds `part`.
inline ::testing::AssertionResult Refused(const io::ImportResult& result, const std::string& part) {
  if (result.ok()) return ::testing::AssertionFailure() << "imported, expected: " << part;
  if (result.error.find(part) == std::string::npos) {
    return ::testing::AssertionFailure() << "'" << result.error << "' lacks '" << part << "'";
  }
  return ::testing::AssertionSuccess();
}

/// The imported rate is exactly `rows` (NaN where a row says NaN).
inline ::testing::AssertionResult RateIs(const io::ImportResult& result,
                                         const std::vector<std::vector<double>>& rows) {
  if (!result.ok()) return ::testing::AssertionFailure() << result.error;
  const Eigen::MatrixXd& rate = result.recording.data.rate_in_output_unit;
  if (rate.rows() != static_cast<Eigen::Index>(rows.size())) {
    return ::testing::AssertionFailure() << rate.rows() << " rows, expected " << rows.size();
  }
  for (Eigen::Index k = 0; k < rate.rows(); ++k) {
    const std::vector<double>& row = rows[static_cast<std::size_t>(k)];
    if (rate.cols() != static_cast<Eigen::Index>(row.size())) {
      return ::testing::AssertionFailure() << rate.cols() << " columns, expected " << row.size();
    }
    for (Eigen::Index a = 0; a < rate.cols(); ++a) {
      const double expected = row[static_cast<std::size_t>(a)];
      const bool same = std::isnan(expected) ? std::isnan(rate(k, a)) : rate(k, a) == expected;
      if (!same) {
        return ::testing::AssertionFailure()
               << "(" << k << ", " << a << ") is " << rate(k, a) << ", expected " << expected;
      }
    }
  }
  return ::testing::AssertionSuccess();
}

/// How many entries `folder` holds.
inline int EntriesIn(const std::filesystem::path& folder) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    count += !entry.path().empty();
  return count;
}

}  // namespace fogpipe::testing
