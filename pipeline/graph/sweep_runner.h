// fogpipe sweep: the parameter sweep of one or more recordings (algorithms/method/sweep_evaluate.h)
// with its I/O: recordings read by the io reader, the truth sidecar of simulated recordings
// (`<file>.truth.json`, read only for scoring), the sweep table in HDF5 and CSV, and a ranking.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "algorithms/method/sweep_evaluate.h"
#include "pipeline/io/recording_reader.h"

namespace fogpipe::graph {

struct SweepRunOptions {
  /// Method options (as `fogpipe run` resolves them) and the grid.
  method::SweepOptions sweep;
  /// How recordings are read (NaN bridging, minimum length), as `fogpipe run` resolves it.
  io::ReadOptions read;
  /// EMD sifts per IMF: one decomposition per value (fixed_sifts rule).
  std::vector<int> emd_sifts = {10};
  /// Folder for <stem>.sweep.h5 and <stem>.sweep.csv.
  std::string output_dir;
  /// Ranking criterion (method::RankCriteria()); "rms_error" falls back to "n" without truth.
  std::string rank_by = "rms_error";
  int threads = 1;
  /// How many ranked settings to print per axis.
  int top = 5;
  std::FILE* report_stream = stdout;
  /// Progress lines on stderr (graph::WorkProgress) even when it is not a terminal; on a terminal
  /// they are always shown, as `run` does.
  bool progress = false;
};

/// One decomposition's sweep of one axis.
struct SweepTable {
  std::string recording;
  std::string axis;
  int emd_sifts = 0;
  bool has_truth = false;
  method::SweepResult result;
};

/// Sweeps every axis of `recording`, writes OUT/<stem>.sweep.h5 and .csv, prints the ranked
/// summary. Returns false with *error for a file that could not be read or written (nothing is
/// left under the final names then).
bool SweepRecording(const std::string& recording, const SweepRunOptions& options,
                    std::vector<SweepTable>* tables, std::string* error);

/// Writes the tables atomically to `path` (layout in sweep_runner.cpp). Throws on failure.
void WriteSweepHdf5(const std::string& path, const std::vector<SweepTable>& tables,
                    const std::string& rank_by);
/// One CSV line per setting of every table (pipeline/io/csv_writer.h), units in the column names.
std::string FormatSweepCsv(const std::vector<SweepTable>& tables);
/// Root `fogpipe_format` of a sweep file (schemas/sweep-v1.json).
inline constexpr const char* kSweepFormat = "fogpipe-sweep-v1";

/// One setting in the ranked summary, with the scores it is ranked by.
struct SweepRankedLine {
  std::string label;  ///< its rank ("1", "2", ...), "dflt" or "hard"
  method::SweepSetting setting;
  double fit_percent = 0.0;      ///< mean one-step fit, %
  double n = 0.0;                ///< N, deg/sqrt(h)
  double k = 0.0;                ///< K, deg/h/sqrt(h)
  double rms_error_deg_h = 0.0;  ///< against the truth (NaN without one)
};

/// A reference filter in the ranked summary.
struct SweepReferenceLine {
  std::string name, parameter_name, parameter_units;
  double parameter = 0.0;
  double n = 0.0, k = 0.0, rms_error_deg_h = 0.0;
  int grid_rank = -1;  ///< grid settings ranked strictly better; -1: none
};

/// What the ranked summary shows of one table.
struct SweepTableSummary {
  std::string recording, axis;
  int emd_sifts = 0, num_imfs = 0, settings = 0;
  double decompose_seconds = 0.0;
  std::string rank_by;  ///< the criterion used (rms_error becomes n without a truth)
  /// The top settings, then `fogpipe run`'s rule ("dflt") and the hardest filtering ("hard",
  /// smallest q_scale / r_scale), each at its best-ranked AR order.
  std::vector<SweepRankedLine> lines;
  std::vector<SweepReferenceLine> references;
};

/// The ranked summary of swept tables (top `top` settings per table).
std::vector<SweepTableSummary> SummarizeSweep(const std::vector<SweepTable>& tables,
                                              const std::string& rank_by, int top);
/// The same summary read back from a sweep file (takes the HDF5 lock). Throws hdf5::Error, or
/// std::runtime_error naming the file when it is not a sweep file.
std::vector<SweepTableSummary> ReadSweepSummary(const std::string& path, int top);
/// The ranked summary as text, the lines `fogpipe sweep` prints and `fogpipe info` shows.
std::string FormatSweepRanking(const std::vector<SweepTableSummary>& summaries);

}  // namespace fogpipe::graph
