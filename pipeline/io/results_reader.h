// Reads back what `fogpipe info` prints and what a rerun needs to decide whether to skip a file.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/method/tables.h"
#include "pipeline/io/results_writer.h"

namespace fogpipe::io {

struct AxisSummary {
  std::string name;
  long long samples = 0;
  double sample_rate_hz = 0.0;
  std::string input_units;
  int num_imfs = 0;
  long long dropped_samples = 0;
  long long outliers = 0;
  double mean_removed_rad_s = 0.0;
  std::string data_warning;              ///< preprocessing/repeat_warning ("" when none or absent)
  std::vector<method::FitRow> table3;    ///< method 2's model first, then IMFs and residue
  std::vector<method::NoiseRow> table5;  ///< raw, method 1, method 2
};

/// One signal's noise terms as a results file holds them (allan/<signal>/noise: the `terms`
/// table and its attributes), indexed by term Q, N, B, K, R (allan::TermSymbol), engineer's units.
struct NoiseTable {
  std::array<double, 5> value{}, std_error{}, readoff{};
  std::array<bool, 5> reliable{};
  std::array<std::string, 5> reason{};  ///< why a term is unreliable ("" when reliable)
  double chi2 = 0.0;
  long long dof = 0;
  double p_value = 0.0;
  std::string misfit_tau_ranges;
};

/// Reads a `noise` group of a results file (under the caller's HDF5 lock). Throws hdf5::Error,
/// or std::runtime_error when the table lacks a term.
NoiseTable ReadNoiseTable(const hdf5::Group& noise);

struct ResultsSummary {
  std::string path;
  Provenance provenance;
  std::vector<AxisSummary> axes;
};

/// Reads the summary of a results file (takes the HDF5 lock). Throws hdf5::Error, or
/// std::runtime_error naming the file when it is not a fogpipe-results-v2 file.
ResultsSummary ReadResultsSummary(const std::string& path);

/// The configuration hash of a complete results file, or nullopt when the file does not exist,
/// cannot be read or is not a fogpipe-results-v2 file (takes the HDF5 lock; never throws).
std::optional<std::string> ReadConfigHash(const std::string& path);

/// What a rerun finds at an output path (CheckCompletedResults).
struct CompletedResults {
  enum class Verdict {
    kAbsent,     ///< no results file: analyse
    kDone,       ///< valid, same configuration, same input path and content: skip
    kRerun,      ///< analyse again; `reason` says why ("" for a changed configuration)
    kCollision,  ///< the file holds the results of another input with the same output name
  };
  Verdict verdict = Verdict::kAbsent;
  std::string reason;
};

/// "Done" means: the results file at `output_path` passes its layout schema (checked in a child
/// process, so a damaged file cannot take the campaign down), its configuration hash equals
/// `config_sha256`, and its recorded input path, size and SHA-256 are those of `input_path` now.
/// Hashing the input reads it once. The same path with other content means the input changed
/// (rerun); another path means two inputs share the output name (collision), even when their
/// bytes are equal. Never throws.
CompletedResults CheckCompletedResults(const std::string& output_path,
                                       const std::string& input_path,
                                       const std::string& config_sha256);

/// The collision of CheckCompletedResults alone, without hashing the input: the reason when
/// `output_path` holds the results of another input than `input_path`, else "" (also when there
/// is no file there or it cannot be used, which this input's results may replace).
std::string ResultsOfAnotherInput(const std::string& output_path, const std::string& input_path);

/// Human-readable summary: provenance, then per axis Table 3 and Table 5 with units.
std::string FormatSummary(const ResultsSummary& summary);

}  // namespace fogpipe::io
