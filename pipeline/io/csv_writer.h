// Every CSV fogpipe writes (`allan --csv`, `merge --csv`, `<stem>.sweep.csv`) goes through this
// writer: RFC 4180 fields (a field holding a comma, a double quote, CR or LF is quoted, its quotes
// doubled), lines ended by LF, one header line, and one style of column name: the quantity, then
// its unit as a token (`tau_s`, `sigma_deg_h`, `N_deg_sqrt_h`). Lines starting with '#' may come
// before the header; readers skip them (Python: `csv.reader(l for l in f if l[0] != '#')`).
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace fogpipe::io {

/// `text` as one CSV field (RFC 4180, section 2, rules 5-7).
std::string CsvField(const std::string& text);

/// `value` with `significant_digits` digits (printf %g); NaN as "nan", infinities as "inf" /
/// "-inf", which Python's float() and numpy read.
std::string CsvNumber(double value, int significant_digits);

/// A unit as it appears in a column name: "deg/sqrt(h)" -> "deg_sqrt_h", "deg/h^2" -> "deg_h2",
/// "%" -> "percent"; empty for a dimensionless "1" or no unit.
std::string CsvUnitToken(const std::string& units);

/// The column name of a quantity in `units`: name + "_" + CsvUnitToken(units), unless the unit is
/// empty or "1", or the name already ends with it (`duration_s` in "s", `..._percent` in "%"),
/// or the name is "seconds" in "s".
std::string CsvColumnName(const std::string& name, const std::string& units);

/// Writes '#' comment lines (line breaks inside a comment become spaces), then the header; Row()
/// writes one line and throws std::logic_error if its field count is not the header's.
class CsvWriter {
 public:
  CsvWriter(std::ostream& out, const std::vector<std::string>& comments,
            const std::vector<std::string>& columns);
  void Row(const std::vector<std::string>& fields);

 private:
  void Line(const std::vector<std::string>& fields);
  std::ostream& out_;
  std::size_t columns_;
};

}  // namespace fogpipe::io
