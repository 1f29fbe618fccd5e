#include "algorithms/filters/search.h"

#include <cmath>
#include <limits>
#include <vector>

namespace fogpipe::filters {

LogSearchResult MinimizeOnLogScale(const std::function<double(double)>& f, double lo, double hi,
                                   int grid_points, double relative_tolerance,
                                   const GridCriterion& grid_criterion) {
  LogSearchResult out;
  auto finite = [](double v) {
    return std::isfinite(v) ? v : std::numeric_limits<double>::infinity();
  };
  auto eval = [&](double log_arg) {
    ++out.evaluations;
    return finite(f(std::exp(log_arg)));
  };
  const double a = std::log(lo), b = std::log(hi);
  std::vector<double> grid(grid_points), values(grid_points);
  for (int i = 0; i < grid_points; ++i) grid[i] = a + (b - a) * i / (grid_points - 1);
  if (grid_criterion) {
    std::vector<double> arguments(grid_points);
    for (int i = 0; i < grid_points; ++i) arguments[i] = std::exp(grid[i]);
    grid_criterion(arguments.data(), grid_points, values.data());
    for (double& v : values) v = finite(v);
    out.evaluations += grid_points;
  } else {
    for (int i = 0; i < grid_points; ++i) values[i] = eval(grid[i]);
  }
  int best = 0;
  for (int i = 1; i < grid_points; ++i) {
    if (values[i] < values[best]) best = i;
  }
  out.at_lower_bound = best == 0;
  out.at_upper_bound = best == grid_points - 1;
  // Golden section on [grid[best - 1], grid[best + 1]] (clamped to the grid).
  double left = grid[best > 0 ? best - 1 : 0];
  double right = grid[best + 1 < grid_points ? best + 1 : grid_points - 1];
  double best_x = grid[best], best_v = values[best];
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  const double tolerance = std::log1p(relative_tolerance);
  double x1 = right - ratio * (right - left), x2 = left + ratio * (right - left);
  double f1 = eval(x1), f2 = eval(x2);
  while (right - left > tolerance) {
    if (f1 <= f2) {
      right = x2;
      x2 = x1;
      f2 = f1;
      x1 = right - ratio * (right - left);
      f1 = eval(x1);
    } else {
      left = x1;
      x1 = x2;
      f1 = f2;
      x2 = left + ratio * (right - left);
      f2 = eval(x2);
    }
  }
  if (f1 < best_v) best_x = x1, best_v = f1;
  if (f2 < best_v) best_x = x2, best_v = f2;
  out.argument = std::exp(best_x);
  out.value = best_v;
  return out;
}

}  // namespace fogpipe::filters
