#include "pipeline/io/text_import.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <utility>

#include "pipeline/io/sha256.h"

namespace fogpipe::io {
namespace {

namespace fs = std::filesystem;

/// The delimiter value that stands for runs of blanks (spaces and tabs).
constexpr char kBlanks = '\0';
constexpr std::size_t kBlockBytes = 1 << 20;
/// Kept lines looked at to detect the delimiter: enough to see a header and several data lines.
constexpr std::size_t kDetectionLines = 50;

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

/// A blank line, or one whose first non-blank characters are `comment` (when not empty).
bool IsSkipped(std::string_view line, const std::string& comment) {
  std::size_t start = 0;
  while (start < line.size() && IsBlank(line[start])) ++start;
  if (start == line.size()) return true;
  return !comment.empty() && line.compare(start, comment.size(), comment) == 0;
}

/// The lines of a stream, read in blocks; every block also goes into the SHA-256, so that the
/// file is read once.
class LineReader {
 public:
  LineReader(std::istream& in, Sha256* sha) : in_(in), sha_(sha), buffer_(kBlockBytes) {}

  /// The next line without its end of line; false at the end. The view lives until the next call.
  bool Next(std::string_view* line) {
    for (;;) {
      const char* start = buffer_.data() + begin_;
      const void* newline = std::memchr(start, '\n', end_ - begin_);
      if (newline != nullptr) {
        const std::size_t length =
            static_cast<std::size_t>(static_cast<const char*>(newline) - start);
        *line = WithoutCarriageReturn(start, length);
        begin_ += length + 1;
        break;
      }
      if (eof_) {
        if (begin_ == end_) return false;
        *line = WithoutCarriageReturn(start, end_ - begin_);
        begin_ = end_;
        break;
      }
      Refill();
    }
    ++line_number_;
    if (line_number_ == 1 && line->substr(0, 3) == "\xEF\xBB\xBF") line->remove_prefix(3);
    return true;
  }
  long long line_number() const { return line_number_; }
  long long bytes() const { return bytes_; }
  bool read_error() const { return read_error_; }

 private:
  static std::string_view WithoutCarriageReturn(const char* start, std::size_t length) {
    if (length > 0 && start[length - 1] == '\r') --length;
    return {start, length};
  }

  void Refill() {
    // The unfinished line moves to the front; a line longer than the buffer grows it.
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
    if (end_ == buffer_.size()) buffer_.resize(buffer_.size() * 2);
    in_.read(buffer_.data() + end_, static_cast<std::streamsize>(buffer_.size() - end_));
    const std::streamsize got = in_.gcount();
    if (got > 0) {
      sha_->Update(buffer_.data() + end_, static_cast<std::size_t>(got));
      end_ += static_cast<std::size_t>(got);
      bytes_ += got;
    }
    if (!in_) {
      eof_ = true;
      read_error_ = in_.bad();
    }
  }

  std::istream& in_;
  Sha256* sha_;
  std::vector<char> buffer_;
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  bool eof_ = false;
  bool read_error_ = false;
  long long line_number_ = 0;
  long long bytes_ = 0;
};

std::string_view TrimField(std::string_view field) {
  while (!field.empty() && IsBlank(field.front())) field.remove_prefix(1);
  while (!field.empty() && IsBlank(field.back())) field.remove_suffix(1);
  if (field.size() >= 2 && field.front() == '"' && field.back() == '"') {
    field.remove_prefix(1);
    field.remove_suffix(1);
  }
  return field;
}

void SplitFields(std::string_view line, char delimiter, std::vector<std::string_view>* fields) {
  fields->clear();
  if (delimiter == kBlanks) {
    std::size_t i = 0;
    for (;;) {
      while (i < line.size() && IsBlank(line[i])) ++i;
      if (i == line.size()) return;
      std::size_t j = i;
      while (j < line.size() && !IsBlank(line[j])) ++j;
      fields->push_back(TrimField(line.substr(i, j - i)));
      i = j;
    }
  }
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = line.find(delimiter, start);
    if (end == std::string_view::npos) {
      fields->push_back(TrimField(line.substr(start)));
      return;
    }
    fields->push_back(TrimField(line.substr(start, end - start)));
    start = end + 1;
  }
}

bool IsMissingMarker(std::string_view field) {
  if (field.empty() || field == "NA") return true;
  if (field.front() == '+' || field.front() == '-') field.remove_prefix(1);
  return field.size() == 3 && (field[0] | 0x20) == 'n' && (field[1] | 0x20) == 'a' &&
         (field[2] | 0x20) == 'n';
}

enum class Cell { kNumber, kMissing, kInvalid };

// std::from_chars: locale-independent and correctly rounded, so a value written with enough
// digits comes back bit for bit.
Cell ParseCell(std::string_view field, bool decimal_comma, double* value) {
  if (IsMissingMarker(field)) {
    *value = std::numeric_limits<double>::quiet_NaN();
    return Cell::kMissing;
  }
  char buffer[64];
  if (decimal_comma) {
    if (field.size() > sizeof buffer) return Cell::kInvalid;
    std::replace_copy(field.begin(), field.end(), buffer, ',', '.');
    field = std::string_view(buffer, field.size());
  }
  const char* first = field.data();
  const char* last = first + field.size();
  const bool plus = *first == '+';  // from_chars takes no '+'
  if (plus) ++first;
  if (first == last || (plus && (*first == '+' || *first == '-'))) return Cell::kInvalid;
  const auto [end, ec] = std::from_chars(first, last, *value);
  if (ec != std::errc() || end != last) return Cell::kInvalid;
  return std::isnan(*value) ? Cell::kMissing : Cell::kNumber;
}

// Integer time stamps are kept exact: epoch nanoseconds need more than a double's 53 bits, and
// a long double holds every 64-bit integer.
bool ParseTime(std::string_view field, bool decimal_comma, long double* value) {
  const char* first = field.data() + (!field.empty() && field.front() == '+' ? 1 : 0);
  const char* last = field.data() + field.size();
  long long integer = 0;
  const auto [end, ec] = std::from_chars(first, last, integer);
  if (first != last && ec == std::errc() && end == last) {
    *value = static_cast<long double>(integer);
    return true;
  }
  double real = 0.0;
  if (ParseCell(field, decimal_comma, &real) != Cell::kNumber || !std::isfinite(real)) {
    return false;
  }
  *value = real;
  return true;
}

std::string FormatNumber(double x) {
  std::ostringstream out;
  out.precision(10);
  out << x;
  return out.str();
}

/// x rounded to `digits` significant digits (locale-independent).
double RoundSignificant(double x, int digits) {
  char buffer[64];
  const auto printed =
      std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, digits);
  double rounded = x;
  std::from_chars(buffer, printed.ptr, rounded);
  return rounded;
}

std::optional<double> SecondsPerTimeUnit(const std::string& units) {
  if (units == "s") return 1.0;
  if (units == "ms") return 1e-3;
  if (units == "us") return 1e-6;
  if (units == "ns") return 1e-9;
  return std::nullopt;
}

const char* DelimiterName(char delimiter) {
  switch (delimiter) {
    case '\t':
      return "tab";
    case ';':
      return ";";
    case ',':
      return ",";
    default:
      return "space";
  }
}

struct KeptLine {
  std::string text;
  long long number = 0;
};

class TextReader {
 public:
  TextReader(std::string path, const TextImportOptions& options)
      : path_(std::move(path)), options_(options) {}

  ImportResult Run();

 private:
  /// Sets the error (prefixed with the path) and returns false, for `return Fail(...)`.
  bool Fail(const std::string& message) {
    error_ = path_ + ": " + message;
    return false;
  }
  bool ReadPreamble(LineReader* reader);
  bool ChooseDelimiter();
  bool ChooseColumns();
  bool ResolveColumn(const std::string& key, const char* option, int* index);
  std::string ColumnLabel(int index) const;
  bool AddRow(std::string_view line, long long line_number);
  bool ParseValue(std::string_view field, int column, long long line_number, double* value);
  long long LineOfRow(long long row) const;
  bool CheckTime(double* sample_rate_hz, nlohmann::json* found);
  /// Checks the options and opens the file for reading.
  bool Open(std::ifstream* in);
  void ReserveRows();
  /// Every data row: the detection lines first, then the rest of the file.
  bool ReadRows(LineReader* reader);
  /// What the reader found (delimiter, header, columns, lines), for the provenance.
  nlohmann::json Found() const;
  bool FillSource(ImportSource* source);

  std::string path_;
  const TextImportOptions& options_;
  std::string error_;
  std::vector<KeptLine> first_lines_;  ///< the kept lines used for detection, data not yet read
  char delimiter_ = kBlanks;
  bool delimiter_detected_ = false;
  bool header_ = false;
  long long header_line_ = 0;
  std::vector<std::string> names_;  ///< header names; empty without a header
  std::size_t field_count_ = 0;
  std::vector<int> rate_columns_;
  int time_column_ = -1;
  std::vector<int> aux_columns_;  ///< one per options_.metadata.aux entry

  std::vector<std::string_view> fields_;
  std::vector<double> rate_;  ///< row-major [rows, axes]
  std::vector<std::vector<double>> aux_;
  std::vector<double> time_;  ///< time - first time, in the time column's unit
  long double first_time_ = 0.0L;
  long long rows_ = 0;
  /// (row, line) wherever a row does not follow its predecessor's line: skipped lines inside the
  /// data. Enough to find any row's line without storing one per row.
  std::vector<std::pair<long long, long long>> line_jumps_;
  long long next_line_ = -1;
};

bool TextReader::ReadPreamble(LineReader* reader) {
  std::string_view line;
  for (long long k = 0; k < options_.skip_rows; ++k) {
    if (!reader->Next(&line)) {
      return Fail("has " + std::to_string(k) + " lines, fewer than the " +
                  std::to_string(options_.skip_rows) + " to skip (--skip-rows)");
    }
  }
  while (first_lines_.size() < kDetectionLines && reader->Next(&line)) {
    if (IsSkipped(line, options_.comment_prefix)) continue;
    first_lines_.push_back({std::string(line), reader->line_number()});
  }
  if (first_lines_.empty()) return Fail("has no data lines");
  return true;
}

bool TextReader::ChooseDelimiter() {
  const std::string& given = options_.delimiter;
  if (given != "auto") {
    delimiter_ = given == "tab"                     ? '\t'
                 : given == "space"                 ? kBlanks
                 : given == "comma" || given == "," ? ','
                                                    : ';';
    return true;
  }
  delimiter_detected_ = true;
  // A stray short or long row among the first lines does not decide the delimiter: it is
  // reported by its line when the data are read.
  const char candidates[] = {'\t', ';', ',', kBlanks};
  std::vector<std::string_view> fields;
  for (char candidate : candidates) {
    if (candidate == ',' && options_.decimal_comma) continue;
    SplitFields(first_lines_.front().text, candidate, &fields);
    const std::size_t count = fields.size();
    std::size_t agreeing = 0;
    for (const KeptLine& line : first_lines_) {
      SplitFields(line.text, candidate, &fields);
      agreeing += fields.size() == count;
    }
    if (count > 1 && 2 * agreeing > first_lines_.size()) {
      delimiter_ = candidate;
      return true;
    }
    if (count == 1 && candidate == kBlanks) {
      delimiter_ = kBlanks;  // one column
      return true;
    }
  }
  return Fail("line " + std::to_string(first_lines_.front().number) +
              ": cannot tell the delimiter: no tab, ';', ',' or run of blanks splits most of the "
              "first " +
              std::to_string(first_lines_.size()) +
              " lines into as many fields as the first; give --delimiter, or --skip-rows to drop "
              "a preamble");
}

std::string TextReader::ColumnLabel(int index) const {
  if (names_.empty()) return "column " + std::to_string(index) + " (0-based)";
  return "column '" + names_[static_cast<std::size_t>(index)] + "' (index " +
         std::to_string(index) + ")";
}

bool TextReader::ResolveColumn(const std::string& key, const char* option, int* index) {
  const auto named = std::find(names_.begin(), names_.end(), key);
  if (named != names_.end()) {
    *index = static_cast<int>(named - names_.begin());
    return true;
  }
  int number = -1;
  const auto [end, ec] = std::from_chars(key.data(), key.data() + key.size(), number);
  if (!key.empty() && ec == std::errc() && end == key.data() + key.size() && number >= 0 &&
      static_cast<std::size_t>(number) < field_count_) {
    *index = number;
    return true;
  }
  std::string available;
  for (const std::string& name : names_)
    available += (available.empty() ? "'" : ", '") + name + "'";
  return Fail(std::string(option) + ": no column '" + key + "' (" +
              (names_.empty() ? std::string("the file has no header") : "columns " + available) +
              "; or a 0-based index below " + std::to_string(field_count_) + ")");
}

bool TextReader::ChooseColumns() {
  std::vector<std::string_view> fields;
  const KeptLine& first = first_lines_.front();
  SplitFields(first.text, delimiter_, &fields);
  field_count_ = fields.size();
  if (options_.header == "yes") {
    header_ = true;
  } else if (options_.header == "auto") {
    bool any_name = false;
    bool any_number = false;
    for (std::string_view field : fields) {
      double value = 0.0;
      const Cell cell = ParseCell(field, options_.decimal_comma, &value);
      any_number = any_number || cell == Cell::kNumber;
      any_name = any_name || cell == Cell::kInvalid;
    }
    header_ = any_name && !any_number;
  }
  if (header_) {
    for (std::string_view field : fields) names_.emplace_back(field);
    header_line_ = first.number;
    first_lines_.erase(first_lines_.begin());
  }

  if (!options_.time_column.empty() &&
      !ResolveColumn(options_.time_column, "--time-column", &time_column_)) {
    return false;
  }
  for (const AuxImportSpec& spec : options_.metadata.aux) {
    int index = -1;
    if (!ResolveColumn(spec.source, "--aux", &index)) return false;
    aux_columns_.push_back(index);
  }
  for (const std::string& key : options_.rate_columns) {
    int index = -1;
    if (!ResolveColumn(key, "--rate-columns", &index)) return false;
    if (index == time_column_) return Fail(ColumnLabel(index) + " is the time column");
    rate_columns_.push_back(index);
  }
  if (rate_columns_.empty()) {
    std::vector<int> unused;
    for (int c = 0; c < static_cast<int>(field_count_); ++c) {
      if (c != time_column_ &&
          std::find(aux_columns_.begin(), aux_columns_.end(), c) == aux_columns_.end()) {
        unused.push_back(c);
      }
    }
    if (unused.size() != 1) {
      std::string list;
      for (int c : unused) list += (list.empty() ? "" : ", ") + ColumnLabel(c);
      return Fail(unused.empty()
                      ? std::string("no column is left for the rate")
                      : "which columns hold the rate? " + list + " could; give --rate-columns");
    }
    rate_columns_ = unused;
  }
  aux_.resize(aux_columns_.size());
  return true;
}

bool TextReader::ParseValue(std::string_view field, int column, long long line_number,
                            double* value) {
  const Cell cell = ParseCell(field, options_.decimal_comma, value);
  if (cell == Cell::kNumber && std::isfinite(*value)) return true;
  if (cell == Cell::kMissing) return true;
  const std::string where = "line " + std::to_string(line_number) + ", " + ColumnLabel(column);
  if (cell == Cell::kNumber) {
    return Fail(where + ": '" + std::string(field) +
                "' is infinite (only an empty cell, NaN or NA marks a missing value)");
  }
  return Fail(where + ": '" + std::string(field) + "' is not a number" +
              (options_.decimal_comma ? " (with a decimal comma)" : ""));
}

bool TextReader::AddRow(std::string_view line, long long line_number) {
  SplitFields(line, delimiter_, &fields_);
  if (fields_.size() != field_count_) {
    return Fail("line " + std::to_string(line_number) + ": " + std::to_string(fields_.size()) +
                " field" + (fields_.size() == 1 ? "" : "s") + " where the " +
                (header_ ? "header has " : "first data line has ") + std::to_string(field_count_) +
                " (delimiter " + DelimiterName(delimiter_) + ")");
  }
  for (int column : rate_columns_) {
    double value = 0.0;
    if (!ParseValue(fields_[static_cast<std::size_t>(column)], column, line_number, &value)) {
      return false;
    }
    rate_.push_back(value);
  }
  for (std::size_t k = 0; k < aux_columns_.size(); ++k) {
    double value = 0.0;
    const int column = aux_columns_[k];
    if (!ParseValue(fields_[static_cast<std::size_t>(column)], column, line_number, &value)) {
      return false;
    }
    aux_[k].push_back(value);
  }
  if (time_column_ >= 0) {
    long double t = 0.0L;
    const std::string_view field = fields_[static_cast<std::size_t>(time_column_)];
    if (!ParseTime(field, options_.decimal_comma, &t)) {
      return Fail("line " + std::to_string(line_number) + ", " + ColumnLabel(time_column_) + ": '" +
                  std::string(field) + "' is not a time (a finite number is needed)");
    }
    if (rows_ == 0) first_time_ = t;
    time_.push_back(static_cast<double>(t - first_time_));
  }
  if (line_number != next_line_) line_jumps_.emplace_back(rows_, line_number);
  next_line_ = line_number + 1;
  ++rows_;
  return true;
}

long long TextReader::LineOfRow(long long row) const {
  auto jump = std::upper_bound(line_jumps_.begin(), line_jumps_.end(),
                               std::make_pair(row, std::numeric_limits<long long>::max()));
  --jump;  // the first row always starts a jump
  return jump->second + (row - jump->first);
}

bool TextReader::CheckTime(double* sample_rate_hz, nlohmann::json* found) {
  const std::string column = ColumnLabel(time_column_);
  if (rows_ < 2) return Fail("the time column needs at least 2 rows to give a sample rate");
  const double seconds = *SecondsPerTimeUnit(options_.time_units);
  std::vector<double> steps(static_cast<std::size_t>(rows_ - 1));
  for (std::size_t k = 0; k + 1 < time_.size(); ++k) steps[k] = (time_[k + 1] - time_[k]) * seconds;
  std::vector<double> sorted = steps;
  const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  const double median = *middle;
  if (!(median > 0.0)) {
    return Fail(column + ": the time does not increase (median step " + FormatNumber(median) +
                " s)");
  }
  const double tolerance = options_.time_tolerance_percent / 100.0 * median;
  long long first_bad = -1, off = 0, gaps = 0, missing = 0, longest_gap = 0, longest_gap_row = -1;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    if (std::abs(steps[k] - median) <= tolerance) continue;
    ++off;
    if (first_bad < 0) first_bad = static_cast<long long>(k);
    const double whole = std::round(steps[k] / median);
    if (whole >= 2.0 && std::abs(steps[k] - whole * median) <= tolerance) {
      ++gaps;
      const long long lost = static_cast<long long>(whole) - 1;
      missing += lost;
      if (lost > longest_gap) {
        longest_gap = lost;
        longest_gap_row = static_cast<long long>(k);
      }
    }
  }
  if (first_bad >= 0) {
    const std::size_t k = static_cast<std::size_t>(first_bad);
    auto time_s = [&](std::size_t row) {
      return FormatNumber(static_cast<double>((first_time_ + time_[row]) * seconds));
    };
    std::string message =
        "line " + std::to_string(LineOfRow(first_bad + 1)) + ", " + column +
        ": the time steps from " + time_s(k) + " s (line " + std::to_string(LineOfRow(first_bad)) +
        ") to " + time_s(k + 1) + " s, a step of " + FormatNumber(steps[k]) +
        " s, where the median step is " + FormatNumber(median) +
        " s and a step may differ from it by " + FormatNumber(options_.time_tolerance_percent) +
        " % (--time-tolerance-percent). The sampling is not uniform: " + std::to_string(off) +
        " of " + std::to_string(steps.size()) + " steps are off: ";
    if (gaps > 0) {
      message += std::to_string(gaps) + " gap" + (gaps == 1 ? "" : "s") + " of whole steps (" +
                 std::to_string(missing) + " missing sample" + (missing == 1 ? "" : "s") +
                 ", the longest " + std::to_string(longest_gap) + " after line " +
                 std::to_string(LineOfRow(longest_gap_row)) + ")";
    } else {
      message += "no gap of whole steps";
    }
    message += " and " + std::to_string(off - gaps) + " other irregular step" +
               (off - gaps == 1 ? "" : "s") +
               ". Resample the data or cut it at the gaps; if only the time stamps are "
               "irregular, leave out --time-column and give --sample-rate-hz";
    return Fail(message);
  }
  const double span_s = time_.back() * seconds;
  const double derived = RoundSignificant(static_cast<double>(rows_ - 1) / span_s, 9);
  const double given = options_.metadata.sample_rate_hz;
  if (given > 0.0 && std::abs(derived - given) > options_.time_tolerance_percent / 100.0 * given) {
    return Fail(column + " gives a sample rate of " + FormatNumber(derived) +
                " Hz, --sample-rate-hz says " + FormatNumber(given) + " Hz");
  }
  *sample_rate_hz = derived;
  (*found)["time_median_step_s"] = median;
  (*found)["time_span_s"] = span_s;
  return true;
}

bool TextReader::Open(std::ifstream* in) {
  std::string error;
  if (!options_.IsValid(&error)) return Fail(error);
  std::error_code ec;
  if (fs::is_directory(path_, ec)) return Fail("is a folder, not a text file");
  in->open(path_, std::ios::binary);
  if (!*in) return Fail(std::string("cannot open for reading: ") + std::strerror(errno));
  return true;
}

// Room for the expected rows at once (from the first lines' length), so that a large file is not
// copied on every doubling of the vectors.
void TextReader::ReserveRows() {
  std::error_code ec;
  const auto size = fs::file_size(path_, ec);
  if (ec || first_lines_.empty()) return;
  std::size_t bytes = 0;
  for (const KeptLine& line : first_lines_) bytes += line.text.size() + 1;
  const std::size_t expected = static_cast<std::size_t>(
      1.05 * static_cast<double>(size) / (static_cast<double>(bytes) / first_lines_.size()));
  rate_.reserve(expected * rate_columns_.size());
  if (time_column_ >= 0) time_.reserve(expected);
  for (std::vector<double>& channel : aux_) channel.reserve(expected);
}

bool TextReader::ReadRows(LineReader* reader) {
  ReserveRows();
  for (const KeptLine& line : first_lines_) {
    if (!AddRow(line.text, line.number)) return false;
  }
  std::string_view line;
  while (reader->Next(&line)) {
    if (IsSkipped(line, options_.comment_prefix)) continue;
    if (!AddRow(line, reader->line_number())) return false;
  }
  if (reader->read_error()) {
    return Fail("read error after line " + std::to_string(reader->line_number()));
  }
  if (rows_ == 0) {
    return Fail("has a header (line " + std::to_string(header_line_) + ") but no data lines");
  }
  return true;
}

nlohmann::json TextReader::Found() const {
  nlohmann::json found;
  found["delimiter"] = DelimiterName(delimiter_);
  found["delimiter_detected"] = delimiter_detected_;
  found["header_line"] = header_ ? nlohmann::json(header_line_) : nullptr;
  found["column_names"] = names_;
  nlohmann::json rate_labels = nlohmann::json::array();
  for (int c : rate_columns_) rate_labels.push_back(ColumnLabel(c));
  found["rate_columns"] = rate_labels;
  found["time_column"] = time_column_ >= 0 ? nlohmann::json(ColumnLabel(time_column_)) : nullptr;
  found["data_rows"] = rows_;
  found["first_data_line"] = line_jumps_.front().second;
  found["last_data_line"] = LineOfRow(rows_ - 1);
  return found;
}

// Hands the rows read over to `source` (the rate's row buffer is freed once copied).
bool TextReader::FillSource(ImportSource* source) {
  source->path = path_;
  source->format = "text";
  source->found = Found();
  if (time_column_ >= 0) {
    if (!CheckTime(&source->sample_rate_hz, &source->found)) return false;
    source->sample_rate_from = "the time column, " + ColumnLabel(time_column_);
  }
  const auto axes = static_cast<Eigen::Index>(rate_columns_.size());
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  source->rate = Eigen::Map<const RowMajor>(rate_.data(), rows_, axes);
  std::vector<double>().swap(rate_);
  if (header_) {
    for (int c : rate_columns_) source->axis_names.push_back(names_[static_cast<std::size_t>(c)]);
  }
  for (std::size_t k = 0; k < aux_.size(); ++k) {
    source->aux[options_.metadata.aux[k].name] = Eigen::Map<const Eigen::VectorXd>(
        aux_[k].data(), static_cast<Eigen::Index>(aux_[k].size()));
  }
  source->options = options_.ToJson();
  return true;
}

ImportResult TextReader::Run() {
  ImportResult failed;
  auto failure = [&]() {
    failed.error = error_;
    return failed;
  };
  std::ifstream in;
  if (!Open(&in)) return failure();
  Sha256 sha;
  LineReader reader(in, &sha);
  ImportSource source;
  if (!ReadPreamble(&reader) || !ChooseDelimiter() || !ChooseColumns() || !ReadRows(&reader) ||
      !FillSource(&source)) {
    return failure();
  }
  source.sha256 = sha.FinishHex();
  source.size_bytes = reader.bytes();
  return FinishImport(std::move(source), options_.metadata);
}

}  // namespace

bool TextImportOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  static const char* const kDelimiters[] = {"auto", "comma", ",", "semicolon", ";", "tab", "space"};
  if (std::find(std::begin(kDelimiters), std::end(kDelimiters), delimiter) ==
      std::end(kDelimiters)) {
    return fail("the delimiter must be auto, comma, semicolon, tab or space (given: '" + delimiter +
                "')");
  }
  if (decimal_comma && (delimiter == "," || delimiter == "comma")) {
    return fail("a decimal comma needs another delimiter than ','");
  }
  if (skip_rows < 0) return fail("the rows to skip must be >= 0");
  if (header != "auto" && header != "yes" && header != "no") {
    return fail("header must be auto, yes or no (given: '" + header + "')");
  }
  if (!SecondsPerTimeUnit(time_units)) {
    return fail("the time units must be s, ms, us or ns (given: '" + time_units + "')");
  }
  if (!(time_tolerance_percent > 0.0 && time_tolerance_percent < 50.0)) {
    return fail("the time tolerance must be in (0, 50) %");
  }
  if (std::find(rate_columns.begin(), rate_columns.end(), std::string()) != rate_columns.end()) {
    return fail("a rate column is empty");
  }
  return metadata.IsValid(error);
}

nlohmann::json TextImportOptions::ToJson() const {
  return {{"delimiter", delimiter},
          {"skip_rows", skip_rows},
          {"header", header},
          {"comment_prefix", comment_prefix},
          {"decimal_comma", decimal_comma},
          {"rate_columns", rate_columns},
          {"time_column", time_column},
          {"time_units", time_units},
          {"time_tolerance_percent", time_tolerance_percent}};
}

ImportResult ImportText(const std::string& path, const TextImportOptions& options) {
  return TextReader(path, options).Run();
}

}  // namespace fogpipe::io
