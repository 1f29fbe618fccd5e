// The campaign flow graph (oneTBB 2021.8): one results file per recording.
//
//   source (input_node: next admitted recording; stops on SIGINT/SIGTERM)
//     -> limiter (limiter_node: at most `files_in_flight` recordings in memory, from
//                 --memory-budget; released by the writer through decrementer(); a recording
//                 that alone exceeds the budget is refused in the preflight)
//     -> reader  (serial: SHA-256 of the file, then one axis at a time by hyperslabs, each axis
//                 sent on as soon as it is read)
//     -> decompose (unlimited: preprocessing + EMD, one axis per task; the sifts' envelope
//                   work through tbb::parallel_for inside, emd.h EmdOptions::for_each)
//     -> models    (unlimited: per-component AR + Kalman and method 2, tbb::parallel_for inside)
//     -> allan     (unlimited: three Allan tables + noise fits, tbb::parallel_for inside)
//     -> writer  (serial: gathers a file's axes, writes temp file + rename, status.jsonl line,
//                 progress line; then one decrement of the limiter per file. The chunks of the
//                 large datasets are compressed by tbb::parallel_for inside it,
//                 pipeline/io/column_datasets.h)
//
// Every node body catches every exception: a bad file is reported and marked failed, and the graph
// goes on. HDF5 is touched only by the preflight (main thread), the reader and the writer, each
// call under the io helper's global lock (pipeline/hdf5/hdf5_lock.h), and no HDF5 object outlives
// the call that opened it. Numeric results do not depend on the thread count: every parallel
// loop writes its own slot and every sum runs in a fixed order.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/method/method.h"
#include "algorithms/model/deterministic_fit.h"
#include "pipeline/graph/status_log.h"
#include "pipeline/io/inputs.h"
#include "pipeline/io/recording_reader.h"
#include "pipeline/io/results_writer.h"

namespace fogpipe::graph {

/// `run --model FILE`: the deterministic effects of a `compare --save-model` file
/// (schemas/model-file.md), subtracted from every axis of every recording before preprocessing,
/// EMD, AR and Kalman (algorithms/model/compensate.h; the bias is not subtracted).
struct ModelCompensationOptions {
  std::string path;    ///< the file as given
  std::string sha256;  ///< of its bytes; part of the configuration hash
  model::DeterministicModel deterministic;
  std::string terms;  ///< the compensated terms, comma-separated (e.g. "temperature")
  /// The /aux channels the terms read ("temperature" for the thermal terms), each once: every
  /// recording needs them.
  std::vector<std::string> aux_channels;
};

struct CampaignOptions {
  method::MethodOptions method;
  io::ResultsOptions results;
  io::ReadOptions read;
  std::string output_dir;
  /// Where each axis's IMFs wait in a nameless scratch file (io/spill_store.h): the output folder
  /// unless --scratch-dir says otherwise.
  std::string scratch_dir;
  int threads = 1;
  std::uint64_t memory_budget_bytes = 2ull << 30;
  bool force = false;
  bool dry_run = false;
  std::string config_toml;    ///< The effective configuration (stored in provenance).
  std::string config_sha256;  ///< Its hash: the rerun key.
  std::optional<ModelCompensationOptions> model;  ///< --model FILE (read once per run)
  std::FILE* progress_stream = stderr;
  bool redraw_progress = false;
  /// Print Tables 3 and 5 of every finished file to this stream at the end (nullptr: don't).
  std::FILE* tables_stream = stdout;
};

struct CampaignReport {
  std::vector<FileOutcome> outcomes;  ///< In input order.
  int ok = 0, failed = 0, skipped = 0;
  int ok_with_warnings = 0;  ///< ok files whose status message carries data warnings
  bool interrupted = false;
  int files_in_flight = 0;  ///< The limiter's capacity.
  std::uint64_t bytes_per_file = 0;
  /// 0 all ok or skipped, 1 some file failed, 128 + signal when interrupted.
  int ExitCode() const;
};

/// Runs the campaign (or, with dry_run, only reports what would be done). Never throws for
/// problems of individual files.
///
/// Memory: each recording is estimated to need axes x BytesPerAxis(N), plus with --model
/// ModelCompensationBytes(N, its aux channels) (memory_budget.h); the
/// process itself FixedBytes(threads). A recording whose estimate exceeds what the budget leaves
/// after FixedBytes is refused before it is read (status failed; the message says how much it
/// needs and which --memory-budget would admit it) and the others go on; otherwise at most
/// floor((budget - FixedBytes) / largest estimate), and at most 2 x threads, recordings are in
/// memory at once. So the peak stays within the budget whenever the estimate bounds the real
/// need (BytesPerAxis says how it was measured).
///
/// Throws std::runtime_error when OUTDIR cannot be created or status.jsonl cannot be opened.
CampaignReport RunCampaign(const std::vector<io::InputFile>& inputs,
                           const CampaignOptions& options);

/// Removes temporary files that a killed run left for `output_name` in `output_dir`
/// (hdf5::IsAtomicTempName), never one that another run is still writing
/// (hdf5::AtomicTempInUse). Returns how many were removed.
int RemoveStaleTempFiles(const std::string& output_dir, const std::string& output_name);

}  // namespace fogpipe::graph
