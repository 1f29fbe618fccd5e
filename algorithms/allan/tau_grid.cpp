#include "algorithms/allan/tau_grid.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace fogpipe::allan {

bool TauGridOptions::IsValid(std::string* error) const {
  if (kind == TauGridKind::kDecade && (per_decade < 1 || per_decade > 1000)) {
    if (error) *error = "per_decade must be in [1, 1000]";
    return false;
  }
  if (kind == TauGridKind::kExplicit && explicit_m.empty()) {
    if (error) *error = "explicit_m is empty";
    return false;
  }
  return true;
}

std::vector<long long> AllantoolsLog10Factors(long long n_samples, long long max_m) {
  std::vector<long long> m;
  const double length = static_cast<double>(n_samples + 1);
  const double max_exponent = std::log10(length);
  const long long points = static_cast<long long>(10.0 * max_exponent);
  for (long long i = 0; i < points; ++i) {
    // numpy.logspace(0, stop, num): 10^(i * stop / (num - 1)).
    const double exponent = points > 1 ? max_exponent * static_cast<double>(i) / (points - 1) : 0.0;
    const double tau_samples = std::pow(10.0, exponent);
    if (!(tau_samples < length)) continue;  // allantools keeps tau < L tau0
    // numpy.round rounds half to even; std::nearbyint does the same in the default mode.
    const long long factor = static_cast<long long>(std::nearbyint(tau_samples));
    if (factor >= 1 && factor <= max_m) m.push_back(factor);
  }
  std::sort(m.begin(), m.end());
  m.erase(std::unique(m.begin(), m.end()), m.end());
  return m;
}

bool ParseTauGrid(const std::string& text, TauGridOptions* grid, std::string* error) {
  *grid = TauGridOptions{};
  if (text == "octave") {
    grid->kind = TauGridKind::kOctave;
  } else if (text == "all") {
    grid->kind = TauGridKind::kAll;
  } else if (text == "log10") {
    grid->kind = TauGridKind::kAllantoolsLog10;
  } else if (text == "decade" || text.rfind("decade:", 0) == 0) {
    grid->kind = TauGridKind::kDecade;
    if (text != "decade") {
      const std::string k = text.substr(7);
      if (k.empty() || k.size() > 4 ||
          !std::all_of(k.begin(), k.end(), [](unsigned char c) { return std::isdigit(c); }) ||
          std::stoi(k) < 1 || std::stoi(k) > 1000) {
        if (error)
          *error =
              "--taus decade:K needs a whole number 1 <= K <= 1000 of points per decade, "
              "got '" +
              k + "'";
        return false;
      }
      grid->per_decade = std::stoi(k);
    }
  } else {
    if (error) *error = "--taus must be octave, decade, decade:K, all or log10, got '" + text + "'";
    return false;
  }
  return true;
}

std::vector<long long> AveragingFactors(const TauGridOptions& options, long long max_m,
                                        long long n_samples) {
  std::vector<long long> m;
  if (max_m < 1) return m;
  switch (options.kind) {
    case TauGridKind::kOctave:
      for (long long v = 1; v <= max_m; v *= 2) m.push_back(v);
      break;
    case TauGridKind::kDecade: {
      const double step = 1.0 / options.per_decade;
      for (int j = 0;; ++j) {
        const long long v = std::llround(std::pow(10.0, j * step));
        if (v > max_m) break;
        if (m.empty() || v != m.back()) m.push_back(v);
      }
      break;
    }
    case TauGridKind::kDecade124:
      for (long long decade = 1; decade <= max_m; decade *= 10)
        for (long long f : {1, 2, 4})
          if (f * decade <= max_m) m.push_back(f * decade);
      break;
    case TauGridKind::kAll:
      m.reserve(static_cast<size_t>(max_m));
      for (long long v = 1; v <= max_m; ++v) m.push_back(v);
      break;
    case TauGridKind::kAllantoolsLog10:
      m = AllantoolsLog10Factors(n_samples > 0 ? n_samples : 2 * max_m, max_m);
      break;
    case TauGridKind::kExplicit:
      for (long long v : options.explicit_m)
        if (v >= 1 && v <= max_m) m.push_back(v);
      std::sort(m.begin(), m.end());
      m.erase(std::unique(m.begin(), m.end()), m.end());
      break;
  }
  return m;
}

}  // namespace fogpipe::allan
