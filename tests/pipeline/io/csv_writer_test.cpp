// Tests of pipeline/io/csv_writer.cpp: RFC 4180 quoting (section 2, rules 5-7), the column-name
// style, and a round trip through a parser written here from the RFC's grammar.
#include "pipeline/io/csv_writer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace fogpipe::io {
namespace {

// RFC 4180, section 2 grammar: records of fields separated by commas, a field either plain or
// DQUOTE-enclosed with "" for a quote; lines starting with '#' before the header are skipped.
std::vector<std::vector<std::string>> ParseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> records;
  std::size_t i = 0;
  while (i < text.size() && text[i] == '#') i = text.find('\n', i) + 1;
  std::vector<std::string> record(1);
  while (i < text.size()) {
    const char c = text[i];
    if (c == '"' && record.back().empty()) {
      for (++i; i < text.size(); ++i) {
        if (text[i] == '"' && i + 1 < text.size() && text[i + 1] == '"') {
          record.back() += '"';
          ++i;
        } else if (text[i] == '"') {
          break;
        } else {
          record.back() += text[i];
        }
      }
      ++i;  // the closing quote
    } else if (c == ',') {
      record.emplace_back();
      ++i;
    } else if (c == '\n') {
      records.push_back(record);
      record.assign(1, "");
      ++i;
    } else {
      record.back() += c;
      ++i;
    }
  }
  return records;
}

TEST(CsvField, LeavesAFieldWithoutSpecialCharactersAsItIs) {
  EXPECT_EQ(CsvField("run_25C.h5"), "run_25C.h5");
  EXPECT_EQ(CsvField(""), "");
  EXPECT_EQ(CsvField("deg/h; 3 IMFs"), "deg/h; 3 IMFs");
}

TEST(CsvField, QuotesCommasQuotesAndLineBreaksAndDoublesTheQuotes) {
  EXPECT_EQ(CsvField("a,b"), "\"a,b\"");
  EXPECT_EQ(CsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(CsvField("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(CsvField("cr\rhere"), "\"cr\rhere\"");
  EXPECT_EQ(CsvField("\""), "\"\"\"\"");
}

TEST(CsvNumber, WritesTheAskedDigitsAndSpellsNonFiniteValuesAsPythonReadsThem) {
  EXPECT_EQ(CsvNumber(0.1, 17), "0.10000000000000001");
  EXPECT_EQ(CsvNumber(1234.5678, 6), "1234.57");
  EXPECT_EQ(CsvNumber(std::numeric_limits<double>::quiet_NaN(), 6), "nan");
  EXPECT_EQ(CsvNumber(-std::numeric_limits<double>::infinity(), 6), "-inf");
}

TEST(CsvColumnName, AppendsTheUnitAsATokenUnlessTheNameAlreadyStatesIt) {
  EXPECT_EQ(CsvColumnName("sigma", "deg/h"), "sigma_deg_h");
  EXPECT_EQ(CsvColumnName("raw_N", "deg/sqrt(h)"), "raw_N_deg_sqrt_h");
  EXPECT_EQ(CsvColumnName("K", "deg/h/sqrt(h)"), "K_deg_h_sqrt_h");
  EXPECT_EQ(CsvColumnName("R", "deg/h^2"), "R_deg_h2");
  EXPECT_EQ(CsvColumnName("Q", "arcsec"), "Q_arcsec");
  EXPECT_EQ(CsvColumnName("duration_s", "s"), "duration_s");
  EXPECT_EQ(CsvColumnName("seconds", "s"), "seconds");
  EXPECT_EQ(CsvColumnName("fit_one_step_mean_percent", "%"), "fit_one_step_mean_percent");
  EXPECT_EQ(CsvColumnName("ar_order", "1"), "ar_order");
  EXPECT_EQ(CsvColumnName("status", ""), "status");
}

TEST(CsvWriter, RoundTripsFieldsWithQuotesCommasAndLineBreaks) {
  const std::vector<std::string> header = {"input_path", "message", "value_deg_h"};
  const std::vector<std::vector<std::string>> rows = {
      {"/data/run \"A\", 25C.h5", "failed: \"x\"\nsecond line", "0.5"},
      {"plain.h5", "", "nan"},
      {",", "\"\"", "\r\n"}};
  std::ostringstream out;
  CsvWriter csv(out, {"fogpipe test\nwith a line break"}, header);
  for (const auto& row : rows) csv.Row(row);
  EXPECT_EQ(out.str().substr(0, 35), "# fogpipe test with a line break\nin");
  const auto parsed = ParseCsv(out.str());
  ASSERT_EQ(parsed.size(), rows.size() + 1);
  EXPECT_EQ(parsed[0], header);
  for (std::size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(parsed[i + 1], rows[i]) << i;
}

TEST(CsvWriter, RefusesARowWhoseFieldCountIsNotTheHeaders) {
  std::ostringstream out;
  CsvWriter csv(out, {}, {"a", "b"});
  EXPECT_THROW(csv.Row({"1"}), std::logic_error);
  EXPECT_EQ(out.str(), "a,b\n");
}

}  // namespace
}  // namespace fogpipe::io
