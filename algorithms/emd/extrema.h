// Extrema of a sampled signal, and the knots of the EMD envelopes built from them.
//
// Positions are kept in half-sample units ("pos2" = 2 x sample index, int32) so that the centre of
// a flat run of equal values, which may fall between two samples, is exact: a flat run x[a] = ... =
// x[b] that is higher (lower) than both neighbours counts as ONE maximum (minimum) at (a + b) / 2,
// stored as pos2 = a + b. A run that goes up on one side and down on the other is not an extremum.
// The first and last samples are never extrema themselves; the ends are handled by MirrorEnds.
//
// Memory: an interior knot costs one int32 position and one double moment (the spline's second
// derivative, see cubic_spline.h). Its value is NOT copied: it is read from the signal at sample
// ceil(pos2 / 2), which lies inside the extremum's flat run. This is valid for as long as that
// sample is unchanged, which the fused envelope pass (envelope.h) guarantees by reading every
// piece's knot values before it overwrites the samples it covers. Only the (at most 2 per side)
// mirrored knots carry their own values.
#pragma once

#include <cstdint>
#include <vector>

#include "algorithms/common/for_each.h"

namespace fogpipe::emd {

/// Counts from one pass over a signal.
struct ExtremaCounts {
  int num_maxima = 0;          ///< Interior local maxima (flat runs count once).
  int num_minima = 0;          ///< Interior local minima (flat runs count once).
  int num_zero_crossings = 0;  ///< Sign changes between consecutive non-zero samples.
  int num_extrema() const { return num_maxima + num_minima; }
  /// Huang 1998: a signal can be sifted while it has at least two maxima and two minima.
  bool EnoughToSift() const { return num_maxima >= 2 && num_minima >= 2; }
};

/// The knots of one envelope (upper: maxima, lower: minima) in half-sample units, with the
/// spline moments. Implements the Knots accessor of cubic_spline.h.
class EnvelopeKnots {
 public:
  /// Mirrored knots per side (Rilling's `nbsym` = 2 in emd.m).
  static constexpr int kMaxMirrored = 2;

  /// Sets room for `interior_capacity` interior knots. Allocates exactly (the old buffers are
  /// released first), so memory stays proportional to the largest extremum count seen.
  void Reserve(int interior_capacity);
  int interior_capacity() const { return interior_capacity_; }

  // Knots accessor: j = 0..size()-1 runs over left mirrored, interior, right mirrored knots.
  int size() const { return num_left_ + num_interior_ + num_right_; }
  double t(int j) const { return pos2_[kMaxMirrored - num_left_ + j]; }
  double y(int j) const {
    const int k = j - num_left_;
    if (k >= 0 && k < num_interior_) return signal_[(pos2_[kMaxMirrored + k] + 1) >> 1];
    // Mirrored: left ones at [kMaxMirrored - num_left_, kMaxMirrored), right ones after.
    return mirror_value_[kMaxMirrored + (k < 0 ? k : k - num_interior_)];
  }
  /// Knot position in half samples.
  int32_t pos2(int j) const { return pos2_[kMaxMirrored - num_left_ + j]; }
  /// Second derivatives of the spline at the knots (size() entries, filled by SolveMoments).
  double* moments() { return moments_.data(); }
  const double* moments() const { return moments_.data(); }

  /// Points the interior knot values at `x`, a copy of the signal FindExtrema ran on (the EMD
  /// finds the extrema of the remainder, then sifts a copy of it).
  void RebindSignal(const double* x) { signal_ = x; }

  int num_interior() const { return num_interior_; }
  int32_t interior_pos2(int k) const { return pos2_[kMaxMirrored + k]; }
  double interior_value(int k) const { return signal_[(pos2_[kMaxMirrored + k] + 1) >> 1]; }

 private:
  friend ExtremaCounts FindExtrema(const double* x, int n, EnvelopeKnots* maxima,
                                   EnvelopeKnots* minima);
  friend ExtremaCounts FindExtremaInParts(const double* x, int n, EnvelopeKnots* maxima,
                                          EnvelopeKnots* minima, int parts, const ForEach& for_each,
                                          class ExtremaScratch* scratch);
  // After a scan that found `count` extrema of this kind (stored as far as the capacity reaches).
  void SetInterior(int count, const double* x) {
    num_left_ = num_right_ = 0;
    num_interior_ = count < interior_capacity_ ? count : interior_capacity_;
    signal_ = x;
  }
  friend void MirrorEnds(const double* x, int n, EnvelopeKnots* maxima, EnvelopeKnots* minima);

  std::vector<int32_t> pos2_;    // kMaxMirrored + capacity + kMaxMirrored
  std::vector<double> moments_;  // same size
  int interior_capacity_ = 0;
  int num_left_ = 0, num_interior_ = 0, num_right_ = 0;
  double mirror_value_[2 * kMaxMirrored] = {0.0, 0.0, 0.0, 0.0};
  const double* signal_ = nullptr;
};

/// One pass over x[0..n): counts maxima, minima and zero crossings, and stores the interior
/// extrema as knots of `maxima` / `minima` (pass nullptr to only count). Storing stops silently at
/// a knot set's capacity; the counts are always complete, so the caller compares them with
/// interior_capacity(), reserves and calls again if needed. Clears any mirrored knots.
ExtremaCounts FindExtrema(const double* x, int n, EnvelopeKnots* maxima, EnvelopeKnots* minima);

/// The per-part knot positions of FindExtremaInParts, kept between calls so that the sifts of a
/// decomposition reuse them (about as many int32 as the extrema of the signal).
class ExtremaScratch {
 public:
  std::vector<std::vector<int32_t>> max_pos, min_pos;  // per part; the last slot is a dump
};

/// FindExtrema split into `parts` contiguous ranges of samples scanned through `for_each`, each
/// range starting from the scan state the serial pass has there (the last non-zero step and
/// non-zero sample before it, found by looking back), so the counts and the stored knots are
/// identical to FindExtrema's whatever the parts and the schedule: extrema and zero crossings are
/// attributed to the step that completes them, which lies in exactly one range. Each part writes
/// its knots into `scratch`, and they are then copied into place in order. With parts < 2 or no
/// for_each: FindExtrema.
ExtremaCounts FindExtremaInParts(const double* x, int n, EnvelopeKnots* maxima,
                                 EnvelopeKnots* minima, int parts, const ForEach& for_each,
                                 ExtremaScratch* scratch);

/// Adds up to two mirrored knots per side and envelope, following Rilling, Flandrin & Goncalves
/// (2003) and their emd.m `boundary_conditions` (nbsym = 2): the extrema nearest an end are
/// reflected about the outermost extremum, or about the end sample itself when the signal at the
/// end lies beyond that extremum (the end sample then becomes a knot of the other envelope); if the
/// reflected knots would not reach past the end, the reflection is made about the end sample.
/// This keeps both envelopes defined up to the ends without extrapolating a cubic, which is what
/// makes end swings propagate inward (Huang 1998, sec. 5). Needs EnoughToSift() and knots stored by
/// FindExtrema on the same x.
void MirrorEnds(const double* x, int n, EnvelopeKnots* maxima, EnvelopeKnots* minima);

}  // namespace fogpipe::emd
