// Files of the model loop of `fogpipe compare`: the model file (JSON, `fogpipe compare
// --save-model FILE`, read by `compare --model FILE` and `run --model FILE`) and the model history
// in a RESULTS HDF5 file (`compare -o RESULTS` appends a step; `compare --history RESULTS` prints
// it). Layouts: schemas/model-file.md and schemas/model-history.md.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "algorithms/model/compare.h"

namespace fogpipe::io {

/// The JSON object `compare --json` prints: exactly error, consistent, view_errors, verdict,
/// failures, suggestions, model.
nlohmann::json CompareJson(const model::CompareResult& result);

/// The "model" object: {"terms": [...], "fitted": [{"term", "parameters": {name: {value,
/// standard_error, units}}}]}.
nlohmann::json ModelJson(const model::Evaluation& evaluation);

/// The IMF view (compare's "model"."imf" object): decimation, sample_rate_hz, critical_z,
/// message and one object per IMF (schemas/model-history.md).
nlohmann::json ImfJson(const model::ImfView& view);
/// The long-tau terms' check (model::LongTauCheck) as `compare --json` prints it under
/// "model"."long_tau_check".
nlohmann::json LongTauJson(const model::LongTauCheck& check);

/// A model file: the terms, the SI deterministic model (enough to compensate) and the fitted
/// parameters for people.
struct ModelFile {
  std::vector<model::ModelTerm> terms;
  model::DeterministicModel deterministic;
};

/// Writes the model file of an evaluation (atomically: temporary name then rename). Throws
/// std::runtime_error on I/O errors.
void WriteModelFile(const std::string& path, const model::Evaluation& evaluation);
/// Reads a model file. Throws std::runtime_error naming the file and the problem.
ModelFile ReadModelFile(const std::string& path);

/// Root `fogpipe_format` of a file `compare -o` creates (schemas/compare-v1.json).
inline constexpr const char* kCompareFormat = "fogpipe-compare-v1";

/// One step of the history as stored.
struct HistoryStep {
  int index = 0;
  std::vector<std::string> terms;
  double error = 0;
  bool consistent = false;
  std::string first_suggestion;  ///< "" when none
  std::string verdict;           ///< "consistent" | "inconsistent" | "unexplained"; "" if absent
  std::string recording;
  std::string axis;        ///< the axis compared
  std::string model_json;  ///< the "model" object
};

/// Appends the comparison as the next step under /compare in `results` (created if missing,
/// then tagged kCompareFormat), with the views' arrays for the report (scripts/report.py).
/// Atomic: the new file is written under a temporary name in the same folder and renamed over
/// `results`. Takes the HDF5 lock.
/// Returns the new step's index. Throws hdf5::Error / std::runtime_error.
int AppendHistory(const std::string& results, const std::string& recording, const std::string& axis,
                  const model::CompareResult& result);

/// Reads every step (takes the HDF5 lock). Throws on a file without /compare.
std::vector<HistoryStep> ReadHistory(const std::string& results);

/// The history as a table, one line per step: axis, error, consistent, the next suggestion, the
/// terms and the error's change from the step before on the same axis (`compare --axis all`
/// interleaves the axes' steps).
std::string FormatHistory(const std::vector<HistoryStep>& steps);

}  // namespace fogpipe::io
