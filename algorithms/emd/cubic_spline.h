// Cubic interpolating splines for the EMD envelopes, in second-derivative ("moment") form.
//
// A cubic spline through knots (t_j, y_j), j = 0..n-1, is fixed by its second derivatives M_j at
// the knots; continuity of the first derivative gives, for every interior knot j = 1..n-2,
//   h_{j-1} M_{j-1} + 2 (h_{j-1} + h_j) M_j + h_j M_{j+1} = 6 (D_j - D_{j-1}),
// with h_j = t_{j+1} - t_j and D_j = (y_{j+1} - y_j) / h_j (de Boor, "A Practical Guide to
// Splines", 1978, ch. IV). The two missing equations are the end conditions:
//   - not-a-knot (default; MATLAB `spline`, scipy CubicSpline, Rilling's emd.m): the third
//     derivative is continuous at t_1 and t_{n-2}, i.e. the first two and the last two pieces are
//     one cubic. It reproduces any cubic polynomial exactly.
//   - natural: M_0 = M_{n-1} = 0 (zero curvature at the ends).
// Both are reduced to a tridiagonal system in M_1..M_{n-2} that is strictly diagonally dominant,
// so the Thomas algorithm needs no pivoting. Cost O(n), no allocation: the caller passes the
// moment array and one work array, both of n doubles.
//
// Knots are read through a small accessor ("Knots": size(), t(j), y(j)) so the EMD can keep
// knot positions as integers and read knot values straight from the signal being sifted
// (see extrema.h); ArrayKnots adapts two plain arrays.
#pragma once

namespace fogpipe::emd {

/// End condition of the envelope splines.
enum class SplineKind {
  kNotAKnot,  ///< Third derivative continuous at the second and second-to-last knots (default).
  kNatural,   ///< Zero second derivative at the first and last knots.
};

/// "not_a_knot" or "natural".
const char* ToString(SplineKind kind);

/// Knots given as two arrays of length n; t strictly increasing.
struct ArrayKnots {
  const double* t_values;
  const double* y_values;
  int n;
  int size() const { return n; }
  double t(int j) const { return t_values[j]; }
  double y(int j) const { return y_values[j]; }
};

/// One piece of the spline: S(t) = c0 + c1 s + c2 s^2 + c3 s^3 with s = t - origin.
struct CubicPiece {
  double origin = 0.0;
  double c0 = 0.0, c1 = 0.0, c2 = 0.0, c3 = 0.0;
  double operator()(double t) const {
    const double s = t - origin;
    return c0 + s * (c1 + s * (c2 + s * c3));
  }
  /// Second derivative at t.
  double SecondDerivative(double t) const { return 2.0 * c2 + 6.0 * c3 * (t - origin); }
};

/// Solves for the knot second derivatives `moment[0..n-1]` of the spline through `knots`.
/// `work` must hold n doubles. Needs n >= 2 and strictly increasing t (not checked here: the EMD
/// produces them by construction). n = 2 gives the straight line; n = 3 with not-a-knot gives the
/// parabola through the three points (as MATLAB's `spline` does).
template <class Knots>
void SolveMoments(const Knots& knots, SplineKind kind, double* moment, double* work);

/// The polynomial of the spline on [t_j, t_{j+1}], j in [0, n-2]. Used unchanged outside the knots
/// (extrapolation by the end pieces).
template <class Knots>
CubicPiece PieceOf(const Knots& knots, const double* moment, int j);

/// Evaluates the spline at t by binary search over the knots. For tests and one-off evaluation;
/// the EMD walks the knots in order instead.
double EvaluateSpline(const ArrayKnots& knots, const double* moment, double t);

// ---------------------------------------------------------------------------------------------
// Implementation (templates).

template <class Knots>
void SolveMoments(const Knots& knots, SplineKind kind, double* moment, double* work) {
  const int n = knots.size();
  if (n <= 2) {  // A straight line (or a constant).
    for (int j = 0; j < n; ++j) moment[j] = 0.0;
    return;
  }
  auto h = [&](int j) { return knots.t(j + 1) - knots.t(j); };
  auto slope = [&](int j) { return (knots.y(j + 1) - knots.y(j)) / h(j); };
  if (n == 3) {
    const double h0 = h(0), h1 = h(1), d0 = slope(0), d1 = slope(1);
    if (kind == SplineKind::kNotAKnot) {  // One parabola: constant second derivative.
      const double m = 2.0 * (d1 - d0) / (h0 + h1);
      moment[0] = moment[1] = moment[2] = m;
    } else {
      moment[0] = moment[2] = 0.0;
      moment[1] = 3.0 * (d1 - d0) / (h0 + h1);
    }
    return;
  }
  // Forward sweep of the Thomas algorithm over rows j = 1..n-2 (unknowns M_1..M_{n-2}).
  // Row j: a M_{j-1} + b M_j + c M_{j+1} = r. work[j] holds the eliminated super-diagonal,
  // moment[j] the eliminated right-hand side.
  const bool not_a_knot = kind == SplineKind::kNotAKnot;
  double h_prev = h(0), d_prev = slope(0);
  for (int j = 1; j <= n - 2; ++j) {
    const double h_j = h(j), d_j = slope(j);
    double a = h_prev, b = 2.0 * (h_prev + h_j), c = h_j, r = 6.0 * (d_j - d_prev);
    if (not_a_knot && j == 1) {
      // Substitute M_0 = ((h0 + h1) M_1 - h0 M_2) / h1 and multiply the row by h1.
      b = (h_prev + h_j) * (h_prev + 2.0 * h_j);
      c = (h_j - h_prev) * (h_j + h_prev);
      r *= h_j;
    }
    if (not_a_knot && j == n - 2) {
      // Substitute M_{n-1} = ((p + q) M_{n-2} - q M_{n-3}) / p with p = h_{n-3}, q = h_{n-2},
      // and multiply the row by p. (n >= 4 here, so this is never also row 1.)
      const double p = h_prev, q = h_j;
      a = (p - q) * (p + q);
      b = (p + q) * (2.0 * p + q);
      c = 0.0;
      r *= p;
    }
    if (!not_a_knot && j == n - 2) c = 0.0;  // M_{n-1} = 0.
    if (j == 1) {  // M_0 is known (natural: 0) or substituted (not-a-knot).
      const double inv = 1.0 / b;
      work[j] = c * inv;
      moment[j] = r * inv;
    } else {
      const double inv = 1.0 / (b - a * work[j - 1]);
      work[j] = c * inv;
      moment[j] = (r - a * moment[j - 1]) * inv;
    }
    h_prev = h_j;
    d_prev = d_j;
  }
  for (int j = n - 3; j >= 1; --j) moment[j] -= work[j] * moment[j + 1];
  if (not_a_knot) {
    const double h0 = h(0), h1 = h(1), p = h(n - 3), q = h(n - 2);
    moment[0] = ((h0 + h1) * moment[1] - h0 * moment[2]) / h1;
    moment[n - 1] = ((p + q) * moment[n - 2] - q * moment[n - 3]) / p;
  } else {
    moment[0] = moment[n - 1] = 0.0;
  }
}

template <class Knots>
CubicPiece PieceOf(const Knots& knots, const double* moment, int j) {
  const double t0 = knots.t(j), hj = knots.t(j + 1) - t0, inv_h = 1.0 / hj;
  const double y0 = knots.y(j), y1 = knots.y(j + 1);
  const double m0 = moment[j], m1 = moment[j + 1];
  CubicPiece piece;
  piece.origin = t0;
  piece.c0 = y0;
  piece.c1 = (y1 - y0) * inv_h - hj * (2.0 * m0 + m1) * (1.0 / 6.0);
  piece.c2 = 0.5 * m0;
  piece.c3 = (m1 - m0) * inv_h * (1.0 / 6.0);
  return piece;
}

}  // namespace fogpipe::emd
