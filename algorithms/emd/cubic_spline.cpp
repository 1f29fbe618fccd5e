#include "algorithms/emd/cubic_spline.h"

#include <algorithm>

namespace fogpipe::emd {

const char* ToString(SplineKind kind) {
  switch (kind) {
    case SplineKind::kNotAKnot:
      return "not_a_knot";
    case SplineKind::kNatural:
      return "natural";
  }
  return "unknown";
}

double EvaluateSpline(const ArrayKnots& knots, const double* moment, double t) {
  if (knots.n == 1) return knots.y(0);
  // Interval j with t_j <= t < t_{j+1}, clamped to the end pieces outside the knots.
  const double* first = knots.t_values;
  const double* last = knots.t_values + knots.n;
  int j = static_cast<int>(std::upper_bound(first, last, t) - first) - 1;
  j = std::clamp(j, 0, knots.n - 2);
  return PieceOf(knots, moment, j)(t);
}

}  // namespace fogpipe::emd
