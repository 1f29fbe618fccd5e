// The one-dimensional search every truth-free tuning here uses: a criterion (GCV, minus a
// likelihood) of one positive parameter, minimised over a log grid and then by golden-section
// search (Kiefer 1953) in the log of the parameter between the best grid point's neighbours.
#pragma once

#include <functional>

namespace fogpipe::filters {

struct LogSearchResult {
  double argument = 0.0;        ///< the minimiser found
  double value = 0.0;           ///< the criterion there
  bool at_lower_bound = false;  ///< the best grid point was the lowest one
  bool at_upper_bound = false;  ///< the best grid point was the highest one
  int evaluations = 0;
};

/// Minimises f over [lo, hi] (0 < lo < hi): `grid_points` (>= 3) log-spaced values, then golden
/// section in log(argument) until the bracket is narrower than a factor (1 + relative_tolerance).
/// Non-finite values of f count as +infinity.
/// `grid` (optional) evaluates f at count grid arguments at once, values[i] = f(arguments[i]) (a
/// criterion whose passes over the data can share one walk); the golden section then calls f.
using GridCriterion = std::function<void(const double* arguments, int count, double* values)>;
LogSearchResult MinimizeOnLogScale(const std::function<double(double)>& f, double lo, double hi,
                                   int grid_points, double relative_tolerance,
                                   const GridCriterion& grid = nullptr);

}  // namespace fogpipe::filters
