#include "pipeline/io/csv_writer.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace fogpipe::io {

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string CsvNumber(double value, int significant_digits) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[40];
  std::snprintf(text, sizeof(text), "%.*g", significant_digits, value);
  return text;
}

std::string CsvUnitToken(const std::string& units) {
  if (units.empty() || units == "1") return "";
  if (units == "%") return "percent";
  std::string token;
  for (char c : units) {
    if (c == '/' || c == ' ' || c == '(') {
      if (!token.empty() && token.back() != '_') token += '_';
    } else if (c != ')' && c != '^') {
      token += c;
    }
  }
  return token;
}

std::string CsvColumnName(const std::string& name, const std::string& units) {
  const std::string token = CsvUnitToken(units);
  if (token.empty() || (units == "s" && name == "seconds")) return name;
  const std::string suffix = "_" + token;
  if (name.size() >= suffix.size() &&
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
    return name;
  }
  return name + suffix;
}

CsvWriter::CsvWriter(std::ostream& out, const std::vector<std::string>& comments,
                     const std::vector<std::string>& columns)
    : out_(out), columns_(columns.size()) {
  for (std::string comment : comments) {
    for (char& c : comment) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    out_ << "# " << comment << "\n";
  }
  Line(columns);
}

void CsvWriter::Row(const std::vector<std::string>& fields) {
  if (fields.size() != columns_) {
    throw std::logic_error("CSV row of " + std::to_string(fields.size()) + " fields under " +
                           std::to_string(columns_) + " columns");
  }
  Line(fields);
}

void CsvWriter::Line(const std::vector<std::string>& fields) {
  for (std::size_t i = 0; i < fields.size(); ++i) out_ << (i ? "," : "") << CsvField(fields[i]);
  out_ << "\n";
}

}  // namespace fogpipe::io
