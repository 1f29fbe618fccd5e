// Text recordings (comma-, semicolon- or tab-separated values, or columns separated by blanks)
// read for `fogpipe import` (recording_import.h writes them as contract-v1 recordings).
//
// The file is read once, front to back, in blocks of 1 MiB, and its SHA-256 is computed on the
// way; memory is the samples (8 bytes per value) and nothing per line. The rules:
// - Lines end with "\n" or "\r\n"; a UTF-8 byte-order mark at the start is ignored. The first
//   `skip_rows` lines are dropped whatever they hold; after them, blank lines and lines whose
//   first non-blank characters are `comment_prefix` are skipped anywhere. Line numbers in
//   messages count every line of the file, from 1.
// - Delimiter "auto": the first of tab, ';', ',' and runs of blanks that splits the first kept
//   line into more than one field and most of the first 50 kept lines into as many; when none
//   does, the file is one column. Fields are trimmed of blanks and of one pair of enclosing double
//   quotes; a quoted field cannot hold the delimiter.
// - Header "auto": the first kept line is a header when none of its fields is a number and not
//   all of them are missing-value markers. Its names select columns in every column option.
// - A column is given by a header name or, failing that, by its 0-based index.
// - Missing values: an empty field, NaN in any case ("nan", "NaN", "-nan") and "NA" become NaN
//   (contract v1: a NaN marks a missing sample; the reader bridges short runs). An infinite value
//   or anything else that is not a number is an error naming the line and the column. Every
//   data line must have as many fields as the first.
// - Time column: its steps (in time_units) must each be within time_tolerance_percent of their
//   median; the first step outside is refused by its line, and the message counts the gaps
//   (steps of a whole number of median steps: missing samples) and the other irregular steps.
//   The sample rate is (rows - 1) / (last time - first time), rounded to 9 significant digits
//   so that timestamps such as k * 0.01 give exactly 100 Hz. Integer timestamps (e.g. epoch
//   nanoseconds) are differenced exactly.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/io/recording_import.h"

namespace fogpipe::io {

struct TextImportOptions {
  /// "auto" (default), "comma" or ",", "semicolon" or ";", "tab", or "space" (runs of blanks:
  /// spaces and tabs).
  std::string delimiter = "auto";
  /// Lines dropped at the top of the file, whatever they hold (a preamble). Default 0.
  long long skip_rows = 0;
  /// "auto" (default: see the file comment), "yes" (the first kept line names the columns) or
  /// "no".
  std::string header = "auto";
  /// Lines starting with this (after blanks) are skipped; "" keeps every line. Default "#".
  std::string comment_prefix = "#";
  /// Numbers are written with a decimal comma (1,5 for 1.5); the delimiter is then ';', tab or
  /// blanks. Default false.
  bool decimal_comma = false;
  /// The rate columns, one per axis, in order. Empty (default): the one column that is neither
  /// the time column nor an aux source; with more than one such column the import is refused.
  std::vector<std::string> rate_columns;
  /// The time column; "" (default): none (the sample rate must then be given).
  std::string time_column;
  /// Unit of the time column: "s" (default), "ms", "us" or "ns".
  std::string time_units = "s";
  /// Largest deviation of a time step from the median step, percent of the median. Default 1.
  double time_tolerance_percent = 1.0;
  /// Units, scale factor, sample rate, axis names, aux channels (columns), root attributes.
  ImportMetadataOptions metadata;

  bool IsValid(std::string* error) const;
  /// The text-specific options (metadata apart), for the provenance.
  nlohmann::json ToJson() const;
};

/// Reads the text file at `path` (opened read-only) and applies the options (FinishImport).
/// Never throws for problems of the file: they are ImportResult::error, naming the file, the
/// line and the column.
ImportResult ImportText(const std::string& path, const TextImportOptions& options);

}  // namespace fogpipe::io
