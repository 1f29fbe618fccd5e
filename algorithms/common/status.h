// Termination codes shared by every algorithm's Summary (Ceres Solver style).
//
// Expected numerical outcomes (a sift that hits its cap, a non-stationary AR fit, a Riccati
// iteration that does not converge) are reported here as data. Exceptions are reserved for
// programming errors; nothing in algorithms/ calls exit().
#pragma once

#include <string>

namespace fogpipe {

enum class Termination {
  kSuccess,           ///< Finished as asked.
  kNoConvergence,     ///< An iteration hit its cap; the result is usable but flagged.
  kInvalidOptions,    ///< Options::IsValid() failed; the result is empty.
  kInsufficientData,  ///< Too few samples (or extrema, or lags) for what was asked.
  kNumericalFailure,  ///< Non-finite values or a singular system; the result is empty.
};

/// Lower-case name used in HDF5 attributes, JSON and logs, e.g. "no_convergence".
const char* ToString(Termination termination);

/// True for kSuccess and kNoConvergence: a result exists and may be used (with care).
inline bool HasResult(Termination t) {
  return t == Termination::kSuccess || t == Termination::kNoConvergence;
}

}  // namespace fogpipe
