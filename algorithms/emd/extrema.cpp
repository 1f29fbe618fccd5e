#include "algorithms/emd/extrema.h"

#include <algorithm>

namespace fogpipe::emd {

void EnvelopeKnots::Reserve(int interior_capacity) {
  const size_t size = static_cast<size_t>(interior_capacity) + 2 * kMaxMirrored;
  // Release before allocating so the peak is the new size, not old + new; resize() of an empty
  // vector allocates exactly `size`.
  pos2_ = std::vector<int32_t>();
  moments_ = std::vector<double>();
  pos2_.resize(size);
  moments_.resize(size);
  interior_capacity_ = interior_capacity;
  num_left_ = num_interior_ = num_right_ = 0;
}

ExtremaCounts FindExtrema(const double* x, int n, EnvelopeKnots* maxima, EnvelopeKnots* minima) {
  constexpr int kOffset = EnvelopeKnots::kMaxMirrored;
  // Branch-free loop (on white noise the direction changes at 2 of 3 samples, so branches would
  // mispredict constantly): every sample writes its candidate position, and the count advances
  // only at an extremum. Writes past the capacity go to a dump slot: index `capacity`, the first
  // right-mirror slot (rewritten by MirrorEnds), or a local when only counting.
  int32_t dump[2];
  const bool store_max = maxima && !maxima->pos2_.empty();
  const bool store_min = minima && !minima->pos2_.empty();
  int32_t* max_pos = store_max ? maxima->pos2_.data() + kOffset : dump;
  int32_t* min_pos = store_min ? minima->pos2_.data() + kOffset : dump + 1;
  const int max_capacity = store_max ? maxima->interior_capacity_ : 0;
  const int min_capacity = store_min ? minima->interior_capacity_ : 0;

  int num_max = 0, num_min = 0, num_zc = 0;
  int direction = 0;  // Sign of the last non-zero step x[i] - x[i-1].
  int run_start = 0;  // First sample of the current flat run.
  int last_sign = (x[0] > 0.0) - (x[0] < 0.0);
  for (int i = 1; i < n; ++i) {
    const double prev = x[i - 1], cur = x[i];
    const int step = (cur > prev) - (cur < prev);
    // The run [run_start, i-1] went down and now goes up (a minimum), or the reverse.
    const int turn = step * direction < 0;
    const int32_t pos2 = run_start + i - 1;
    max_pos[std::min(num_max, max_capacity)] = pos2;
    min_pos[std::min(num_min, min_capacity)] = pos2;
    num_max += turn & (step < 0);
    num_min += turn & (step > 0);
    run_start = step != 0 ? i : run_start;
    direction = step != 0 ? step : direction;
    // Zero crossings: sign changes between non-zero samples; zeros in between are skipped, so a
    // signal touching zero without changing sign does not cross.
    const int sign = (cur > 0.0) - (cur < 0.0);
    num_zc += (sign * last_sign < 0);
    last_sign = sign != 0 ? sign : last_sign;
  }
  if (maxima) {
    maxima->num_left_ = maxima->num_right_ = 0;
    maxima->num_interior_ = std::min(num_max, max_capacity);
    maxima->signal_ = x;
  }
  if (minima) {
    minima->num_left_ = minima->num_right_ = 0;
    minima->num_interior_ = std::min(num_min, min_capacity);
    minima->signal_ = x;
  }
  ExtremaCounts counts;
  counts.num_maxima = num_max;
  counts.num_minima = num_min;
  counts.num_zero_crossings = num_zc;
  return counts;
}

namespace {

// A knot to be reflected: its position (half samples) and value.
struct Source {
  int32_t pos2;
  double value;
};

// Up to kMaxMirrored sources, in the order MATLAB's fliplr() gives them (nearest the end last on
// the left side, first on the right side).
struct SourceList {
  int count = 0;
  Source item[EnvelopeKnots::kMaxMirrored];
  void Add(const Source& s) { item[count++] = s; }
  // Adds interior extrema k = last-1, last-2, ..., first (fliplr of indices first..last-1).
  void AddReversed(const EnvelopeKnots& knots, int first, int last) {
    first = std::max(first, 0);
    for (int k = last - 1; k >= first; --k) Add({knots.interior_pos2(k), knots.interior_value(k)});
  }
};

}  // namespace

void MirrorEnds(const double* x, int n, EnvelopeKnots* maxima, EnvelopeKnots* minima) {
  const EnvelopeKnots& mx = *maxima;
  const EnvelopeKnots& mn = *minima;
  const int n_max = mx.num_interior(), n_min = mn.num_interior();
  constexpr int kSym = EnvelopeKnots::kMaxMirrored;

  // Left end (sample 0, pos2 = 0). Port of emd.m boundary_conditions, 0-based.
  SourceList lmax, lmin;
  int32_t lsym = 0;
  const Source left_end{0, x[0]};
  if (mx.interior_pos2(0) < mn.interior_pos2(0)) {  // First extremum is a maximum.
    if (x[0] > mn.interior_value(0)) {
      lmax.AddReversed(mx, 1, std::min(n_max, kSym + 1));
      lmin.AddReversed(mn, 0, std::min(n_min, kSym));
      lsym = mx.interior_pos2(0);
    } else {
      lmax.AddReversed(mx, 0, std::min(n_max, kSym));
      lmin.AddReversed(mn, 0, std::min(n_min, kSym - 1));
      lmin.Add(left_end);
      lsym = 0;
    }
  } else {
    if (x[0] < mx.interior_value(0)) {
      lmax.AddReversed(mx, 0, std::min(n_max, kSym));
      lmin.AddReversed(mn, 1, std::min(n_min, kSym + 1));
      lsym = mn.interior_pos2(0);
    } else {
      lmax.AddReversed(mx, 0, std::min(n_max, kSym - 1));
      lmax.Add(left_end);
      lmin.AddReversed(mn, 0, std::min(n_min, kSym));
      lsym = 0;
    }
  }
  // The outermost reflected knot must reach sample 0; otherwise reflect about the end sample.
  if (2 * lsym - lmin.item[0].pos2 > 0 || 2 * lsym - lmax.item[0].pos2 > 0) {
    if (lsym == mx.interior_pos2(0)) {
      lmax = SourceList();
      lmax.AddReversed(mx, 0, std::min(n_max, kSym));
    } else {
      lmin = SourceList();
      lmin.AddReversed(mn, 0, std::min(n_min, kSym));
    }
    lsym = 0;
  }

  // Right end (sample n-1, pos2 = 2(n-1)).
  const int32_t end2 = 2 * (n - 1);
  SourceList rmax, rmin;
  int32_t rsym = end2;
  const Source right_end{end2, x[n - 1]};
  if (mx.interior_pos2(n_max - 1) < mn.interior_pos2(n_min - 1)) {  // Last is a minimum.
    if (x[n - 1] < mx.interior_value(n_max - 1)) {
      rmax.AddReversed(mx, n_max - kSym, n_max);
      rmin.AddReversed(mn, n_min - kSym - 1, n_min - 1);
      rsym = mn.interior_pos2(n_min - 1);
    } else {
      rmax.Add(right_end);
      rmax.AddReversed(mx, n_max - kSym + 1, n_max);
      rmin.AddReversed(mn, n_min - kSym, n_min);
      rsym = end2;
    }
  } else {
    if (x[n - 1] > mn.interior_value(n_min - 1)) {
      rmax.AddReversed(mx, n_max - kSym - 1, n_max - 1);
      rmin.AddReversed(mn, n_min - kSym, n_min);
      rsym = mx.interior_pos2(n_max - 1);
    } else {
      rmax.AddReversed(mx, n_max - kSym, n_max);
      rmin.Add(right_end);
      rmin.AddReversed(mn, n_min - kSym + 1, n_min);
      rsym = end2;
    }
  }
  if (2 * rsym - rmin.item[rmin.count - 1].pos2 < end2 ||
      2 * rsym - rmax.item[rmax.count - 1].pos2 < end2) {
    if (rsym == mx.interior_pos2(n_max - 1)) {
      rmax = SourceList();
      rmax.AddReversed(mx, n_max - kSym, n_max);
    } else {
      rmin = SourceList();
      rmin.AddReversed(mn, n_min - kSym, n_min);
    }
    rsym = end2;
  }

  auto store = [&](EnvelopeKnots* knots, const SourceList& left, const SourceList& right) {
    knots->num_left_ = left.count;
    for (int k = 0; k < left.count; ++k) {
      knots->pos2_[kSym - left.count + k] = 2 * lsym - left.item[k].pos2;
      knots->mirror_value_[kSym - left.count + k] = left.item[k].value;
    }
    knots->num_right_ = right.count;
    for (int k = 0; k < right.count; ++k) {
      knots->pos2_[kSym + knots->num_interior_ + k] = 2 * rsym - right.item[k].pos2;
      knots->mirror_value_[kSym + k] = right.item[k].value;
    }
  };
  store(maxima, lmax, rmax);
  store(minima, lmin, rmin);
}

}  // namespace fogpipe::emd
