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
  kAllantoolsLog10,  ///< allantools' taus="log10" (AllantoolsLog10Factors), ~10 per decade.
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
/// `n_samples` (the record's rate samples) is needed by kAllantoolsLog10 only; <= 0 means
/// 2 max_m.
std::vector<long long> AveragingFactors(const TauGridOptions& options, long long max_m,
                                        long long n_samples = 0);

/// Averaging factors of allantools' taus="log10" grid for n rate samples, as allantools
/// 2024.06 builds it for frequency data (found by reproducing the reference table of
/// adis16405_imu1 exactly): the phase has L = n + 1 points, taus = logspace(0, log10(L),
/// int(10 log10(L))) samples, m = round(tau), unique, 1 <= m <= max_m.
std::vector<long long> AllantoolsLog10Factors(long long n_samples, long long max_m);

/// The one spelling of a tau grid, shared by every command: "octave", "decade" (10 per decade),
/// "decade:K" (K per decade, 1 <= K <= 1000), "all", "log10" (allantools-compatible). False with
/// *error (naming the accepted forms) for anything else.
bool ParseTauGrid(const std::string& text, TauGridOptions* grid, std::string* error);

}  // namespace fogpipe::allan
