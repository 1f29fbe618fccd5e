// The campaign table written by `fogpipe merge OUTDIR -o campaign.h5`: one row per recording and
// axis, gathered from the results files (fogpipe-results-v2) and OUTDIR/status.jsonl.
//
// Layout of campaign.h5 (fogpipe-campaign-v1, schemas/campaign-v1.json):
//   /                 attributes fogpipe_format, rows, source_folder
//   /campaign/<col>   one 1-D dataset per column, numeric ones with a `units` attribute:
//                     input_path, results_file, axis, serial, instrument, duration_s; per signal S
//                     of kCampaignSignals and term T of kCampaignTerms S_T, S_T_std_error,
//                     S_T_readoff (the term's unit), then S_unreliable_terms,
//                     S_unreliable_reasons, S_noise_fit_chi2_per_dof, S_noise_fit_p_value,
//                     S_noise_fit_misfit_tau_ranges (CampaignRow); model_loop_error, status,
//                     message
//   /results/<name>   an HDF5 external link to the root of each results file (relative to the
//                     campaign file's folder, so the folder may be moved as a whole)
//
// Merging is idempotent: the table is rebuilt from what OUTDIR holds and written through a
// temporary file renamed when complete, so it can run again whenever late or resubmitted shards
// arrive. A recording is keyed by its input path: a file processed twice (a resubmitted shard, a
// --force rerun) has one results file name and contributes its rows once.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace fogpipe::io {

/// Root `fogpipe_format` of a campaign table (schemas/campaign-v1.json).
inline constexpr const char* kCampaignFormat = "fogpipe-campaign-v1";

/// The signals whose noise terms are tabulated, as named under /axes/<axis>/allan.
inline constexpr std::array<const char*, 3> kCampaignSignals = {"raw", "method1", "method2"};
/// IEEE Std 952-1997 noise terms in the order Q, N, B, K, R (engineer's units, units.h).
inline constexpr std::array<const char*, 5> kCampaignTerms = {"Q", "N", "B", "K", "R"};

struct CampaignRow {
  std::string input_path;    ///< The recording (provenance input_path, or status.jsonl "file").
  std::string results_file;  ///< Results file name inside OUTDIR; empty when there is none.
  std::string axis;          ///< Axis group name; empty for a file without results.
  std::string serial;        ///< Recording attribute `serial` (empty when absent or unreadable).
  std::string instrument;    ///< Recording attribute `instrument`.
  double duration_s = 0.0;   ///< Analysed samples / sample rate, s (NaN without results).
  /// [signal][term]: value and standard error in Q arcsec, N deg/sqrt(h), B deg/h,
  /// K deg/h/sqrt(h), R deg/h^2; NaN where not fitted.
  std::array<std::array<double, 5>, 3> term{}, term_std_error{};
  /// [signal][term]: the slope read-off (IEEE Std 952-1997 Annex C) in the term's unit above;
  /// NaN where there is none.
  std::array<std::array<double, 5>, 3> term_readoff{};
  /// [signal]: the noise fit's terms marked unreliable, e.g. "B,K" ("" when none), their reasons
  /// ("B: <reason> | K: <reason>", the results file's noise/<T>_reason), the fit's chi2 / dof and
  /// chi-square p-value (NaN when unknown), and the tau ranges the model misses
  /// ("0.1-0.3 s, 200-800 s", noise/misfit_tau_ranges; "" when none).
  std::array<std::string, 3> unreliable_terms{};
  std::array<std::string, 3> unreliable_reasons{};
  std::array<double, 3> noise_fit_chi2_per_dof{};
  std::array<double, 3> noise_fit_p_value{};
  std::array<std::string, 3> misfit_tau_ranges{};
  /// RMS error of the model loop (fogpipe compare) when the results file has a model history;
  /// NaN otherwise (fogpipe-results-v2 has none yet).
  double model_loop_error = 0.0;
  /// Why the recorded column is suspect though it was analysed ("" when not): the results
  /// file's preprocessing/repeat_warning (a run of one repeated value, repeated_samples.h).
  std::string data_warning;
  std::string status;   ///< "ok", "failed" (status.jsonl) or "missing" (in the manifest only).
  std::string message;  ///< Why it failed, from status.jsonl.
};

struct CampaignTable {
  std::string source_folder;
  std::vector<CampaignRow> rows;      ///< Sorted by input path, then axis.
  int recordings = 0;                 ///< Distinct input paths.
  int results_files = 0;              ///< Results files used.
  int duplicate_results = 0;          ///< Results files ignored: an older one of the same input.
  std::vector<std::string> problems;  ///< Unreadable results files, bad status lines.
};

/// Builds the table from `outdir`: every *.fogpipe.h5 directly in it (temporary files of killed
/// runs are ignored), OUTDIR/status.jsonl (the last line per input wins), and, when `manifest` is
/// not empty, a "missing" row for every listed recording with neither results nor a status line.
/// Takes the HDF5 lock itself; never throws for a bad results file (it goes to `problems`).
CampaignTable CollectCampaign(const std::string& outdir, const std::string& manifest);

/// Writes the table to `path` atomically (hdf5::AtomicOutputFile). Throws hdf5::Error or
/// std::runtime_error.
void WriteCampaignTable(const std::string& path, const CampaignTable& table);

/// The table as CSV (pipeline/io/csv_writer.h), the columns of /campaign with their units in
/// the names (`raw_N_deg_sqrt_h`).
std::string FormatCampaignCsv(const CampaignTable& table);

/// Reads a campaign table back (rows, source folder, recordings; takes the HDF5 lock). Throws
/// hdf5::Error, or std::runtime_error naming the file when it is not a campaign table or a
/// column is missing or of another length.
CampaignTable ReadCampaignTable(const std::string& path);

/// Recordings by status; a recording counts once, whatever its number of axes.
struct CampaignCounts {
  int ok = 0, failed = 0, missing = 0;
};
CampaignCounts CountRecordings(const CampaignTable& table);

/// What `fogpipe info` shows of a campaign table: rows and counts, then per row the recording,
/// axis, status, the raw signal's N, B and K with standard errors and units, and the flags
/// (unreliable terms, data warnings, failure messages).
std::string FormatCampaignSummary(const std::string& path, const CampaignTable& table);

}  // namespace fogpipe::io
