#include "algorithms/allan/tau_grid.h"

#include <algorithm>
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

std::vector<long long> AveragingFactors(const TauGridOptions& options, long long max_m) {
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
