// Averaging-factor grids for Allan-type deviations (NIST SP 1065, section 5.2; Stable32
// conventions).
//
// The averaging factor m is tau / tau0. Grids are returned sorted ascending and deduplicated.
#pragma once

#include <string>
#include <vector>

namespace fogpipe::allan {

enum class TauGridKind {
  kOctave,     ///< m = 1, 2, 4, 8, ... (Stable32 "octave").
  kDecade,     ///< per_decade log-spaced points: m = round(10^(j / per_decade)), deduplicated.
  kAll,        ///< Every m = 1 .. max_m (Stable32 "all tau").
  kDecade124,  ///< m = 1, 2, 4, 10, 20, 40, 100, ... (Stable32's "decade" grid).
  kExplicit,   ///< The factors in TauGridOptions::explicit_m (sorted, deduplicated, clipped).
};

struct TauGridOptions {
  TauGridKind kind = TauGridKind::kOctave;
  /// Points per decade for kDecade (before rounding and deduplication). Default 10.
  int per_decade = 10;
  /// Averaging factors for kExplicit; values outside [1, max_m] are dropped.
  std::vector<long long> explicit_m;

  bool IsValid(std::string* error) const;
};

/// The averaging factors of `options` that do not exceed `max_m` (max_m < 1 gives an empty grid).
std::vector<long long> AveragingFactors(const TauGridOptions& options, long long max_m);

}  // namespace fogpipe::allan
