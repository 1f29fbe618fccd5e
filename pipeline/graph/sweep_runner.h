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
/// One CSV line per setting of every table, header first, units in the header.
std::string FormatSweepCsv(const std::vector<SweepTable>& tables);
/// The ranked summary (top `top` settings per table) as text, with the default setting
/// (q_scale = r_scale = 1) and the hardest filtering (smallest q_scale / r_scale) for comparison.
std::string FormatSweepRanking(const std::vector<SweepTable>& tables, const std::string& rank_by,
                               int top);

}  // namespace fogpipe::graph
