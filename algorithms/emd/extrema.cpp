#include "algorithms/emd/extrema.h"

#include <algorithm>

#if defined(__AVX2__) || defined(__AVX512F__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

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

namespace {

// State of the extrema scan between samples.
struct ScanState {
  int num_max = 0, num_min = 0, num_zc = 0;
  int direction = 0;  // Sign of the last non-zero step x[i] - x[i-1].
  int run_start = 0;  // First sample of the current flat run.
  int last_sign = 0;  // Sign of the last non-zero sample.
};

// Where the scan writes knot positions. Writes past a capacity go to a dump slot: index
// `capacity` (the first right-mirror slot, rewritten by MirrorEnds) or a local when only counting.
struct ScanOutput {
  int32_t* max_pos;
  int32_t* min_pos;
  int max_capacity;
  int min_capacity;
};

// Scalar scan of samples [begin, end), any data (flat runs, zeros).
void ScanScalar(const double* x, int begin, int end, const ScanOutput& out, ScanState* st) {
  ScanState s = *st;
  for (int i = begin; i < end; ++i) {
    const double prev = x[i - 1], cur = x[i];
    const int step = (cur > prev) - (cur < prev);
    // The run [run_start, i-1] went down and now goes up (a minimum), or the reverse.
    const int turn = step * s.direction < 0;
    const int32_t pos2 = s.run_start + i - 1;
    out.max_pos[std::min(s.num_max, out.max_capacity)] = pos2;
    out.min_pos[std::min(s.num_min, out.min_capacity)] = pos2;
    s.num_max += turn & (step < 0);
    s.num_min += turn & (step > 0);
    s.run_start = step != 0 ? i : s.run_start;
    s.direction = step != 0 ? step : s.direction;
    // Zero crossings: sign changes between non-zero samples; zeros in between are skipped, so a
    // signal touching zero without changing sign does not cross.
    const int sign = (cur > 0.0) - (cur < 0.0);
    s.num_zc += (sign * s.last_sign < 0);
    s.last_sign = sign != 0 ? sign : s.last_sign;
  }
  *st = s;
}

// Bit k of the masks: x[k] > x[k-1], x[k] < x[k-1], x[k] > 0, x[k] < 0, for k = 0..63.
inline void CompareBlock(const double* x, uint64_t* up, uint64_t* down, uint64_t* positive,
                         uint64_t* negative) {
  uint64_t u = 0, d = 0, p = 0, m = 0;
#if defined(__AVX512F__)
  const __m512d zero = _mm512_setzero_pd();
  for (int k = 0; k < 64; k += 8) {
    const __m512d cur = _mm512_loadu_pd(x + k), prev = _mm512_loadu_pd(x + k - 1);
    u |= static_cast<uint64_t>(_mm512_cmp_pd_mask(cur, prev, _CMP_GT_OQ)) << k;
    d |= static_cast<uint64_t>(_mm512_cmp_pd_mask(cur, prev, _CMP_LT_OQ)) << k;
    p |= static_cast<uint64_t>(_mm512_cmp_pd_mask(cur, zero, _CMP_GT_OQ)) << k;
    m |= static_cast<uint64_t>(_mm512_cmp_pd_mask(cur, zero, _CMP_LT_OQ)) << k;
  }
#elif defined(__AVX2__)
  const __m256d zero = _mm256_setzero_pd();
  for (int k = 0; k < 64; k += 4) {
    const __m256d cur = _mm256_loadu_pd(x + k), prev = _mm256_loadu_pd(x + k - 1);
    u |= static_cast<uint64_t>(_mm256_movemask_pd(_mm256_cmp_pd(cur, prev, _CMP_GT_OQ))) << k;
    d |= static_cast<uint64_t>(_mm256_movemask_pd(_mm256_cmp_pd(cur, prev, _CMP_LT_OQ))) << k;
    p |= static_cast<uint64_t>(_mm256_movemask_pd(_mm256_cmp_pd(cur, zero, _CMP_GT_OQ))) << k;
    m |= static_cast<uint64_t>(_mm256_movemask_pd(_mm256_cmp_pd(cur, zero, _CMP_LT_OQ))) << k;
  }
#elif defined(__SSE2__)
  // The x86-64 baseline: two samples per compare (cmpgt/cmplt are ordered, false with a NaN, as
  // the scalar comparisons are).
  const __m128d zero = _mm_setzero_pd();
  for (int k = 0; k < 64; k += 2) {
    const __m128d cur = _mm_loadu_pd(x + k), prev = _mm_loadu_pd(x + k - 1);
    u |= static_cast<uint64_t>(_mm_movemask_pd(_mm_cmpgt_pd(cur, prev))) << k;
    d |= static_cast<uint64_t>(_mm_movemask_pd(_mm_cmplt_pd(cur, prev))) << k;
    p |= static_cast<uint64_t>(_mm_movemask_pd(_mm_cmpgt_pd(cur, zero))) << k;
    m |= static_cast<uint64_t>(_mm_movemask_pd(_mm_cmplt_pd(cur, zero))) << k;
  }
#else
  for (int k = 0; k < 64; ++k) {
    u |= static_cast<uint64_t>(x[k] > x[k - 1]) << k;
    d |= static_cast<uint64_t>(x[k] < x[k - 1]) << k;
    p |= static_cast<uint64_t>(x[k] > 0.0) << k;
    m |= static_cast<uint64_t>(x[k] < 0.0) << k;
  }
#endif
  *up = u;
  *down = d;
  *positive = p;
  *negative = m;
}

// Appends the extrema flagged in `mask` (bit k: sample base + k) to pos[], count in *num.
inline void Emit(uint64_t mask, int base, int32_t* pos, int capacity, int* num) {
  int count = *num;
  while (mask != 0) {
    const int k = __builtin_ctzll(mask);
    pos[std::min(count, capacity)] = 2 * (base + k);
    ++count;
    mask &= mask - 1;
  }
  *num = count;
}

// The scan of steps [begin, end) (step i compares x[i] with x[i-1]) from the state *state.
// Blocks of 64 steps as bit masks (on white noise the direction changes at 2 of 3 samples, so a
// per-sample branch would mispredict constantly). A block with an equal neighbour pair (a flat
// run) or an exact zero, or that starts inside a flat run or before the first step or non-zero
// sample, takes the scalar path, which gives the same result on every input (so neither does it
// depend on where the blocks start).
void ScanRange(const double* x, int begin, int end, const ScanOutput& out, ScanState* state) {
  constexpr int kBlock = 64;
  ScanState& st = *state;
  int i = begin;
  for (; i + kBlock <= end; i += kBlock) {
    uint64_t up, down, positive, negative;
    CompareBlock(x + i, &up, &down, &positive, &negative);
    if ((up | down) != ~uint64_t{0} || (positive | negative) != ~uint64_t{0} || st.direction == 0 ||
        st.last_sign == 0 || st.run_start != i - 1) {
      ScanScalar(x, i, i + kBlock, out, &st);
      continue;
    }
    // Step k goes up/down; a maximum sits at sample i+k-1 when step k-1 went up and step k down.
    const uint64_t prev_up = (up << 1) | static_cast<uint64_t>(st.direction > 0);
    const uint64_t prev_down = (down << 1) | static_cast<uint64_t>(st.direction < 0);
    Emit(down & prev_up, i - 1, out.max_pos, out.max_capacity, &st.num_max);
    Emit(up & prev_down, i - 1, out.min_pos, out.min_capacity, &st.num_min);
    const uint64_t prev_positive = (positive << 1) | static_cast<uint64_t>(st.last_sign > 0);
    st.num_zc += __builtin_popcountll(positive ^ prev_positive);
    st.direction = (up >> (kBlock - 1)) ? 1 : -1;
    st.run_start = i + kBlock - 1;
    st.last_sign = (positive >> (kBlock - 1)) ? 1 : -1;
  }
  ScanScalar(x, i, end, out, &st);
}

// The state of the scan that started at step 1 when it reaches step `begin` >= 1, with the counts
// at 0: the sign and index of the last non-zero step before `begin` and the sign of the last
// non-zero sample before it (sample 0 included), found by looking back from `begin`.
ScanState StateBefore(const double* x, int begin) {
  ScanState st;
  for (int j = begin - 1; j >= 1; --j) {
    const int step = (x[j] > x[j - 1]) - (x[j] < x[j - 1]);
    if (step != 0) {
      st.direction = step;
      st.run_start = j;
      break;
    }
  }
  for (int j = begin - 1; j >= 0; --j) {
    const int sign = (x[j] > 0.0) - (x[j] < 0.0);
    if (sign != 0) {
      st.last_sign = sign;
      break;
    }
  }
  return st;
}

ExtremaCounts CountsOf(const ScanState& st) {
  ExtremaCounts counts;
  counts.num_maxima = st.num_max;
  counts.num_minima = st.num_min;
  counts.num_zero_crossings = st.num_zc;
  return counts;
}

// Grows a part's buffer to `needed` knots (and its dump slot), with a little slack.
void GrowPart(int needed, std::vector<int32_t>* pos) {
  if (needed + 1 <= static_cast<int>(pos->size())) return;
  *pos = std::vector<int32_t>();
  pos->resize(static_cast<size_t>(needed) + needed / 32 + 17);
}

}  // namespace

ExtremaCounts FindExtrema(const double* x, int n, EnvelopeKnots* maxima, EnvelopeKnots* minima) {
  return FindExtremaInParts(x, n, maxima, minima, 1, ForEach(), nullptr);
}

ExtremaCounts FindExtremaInParts(const double* x, int n, EnvelopeKnots* maxima,
                                 EnvelopeKnots* minima, int parts, const ForEach& for_each,
                                 ExtremaScratch* scratch) {
  constexpr int kOffset = EnvelopeKnots::kMaxMirrored;
  const bool store_max = maxima && !maxima->pos2_.empty();
  const bool store_min = minima && !minima->pos2_.empty();
  const bool storing = store_max || store_min;
  const int max_capacity = store_max ? maxima->interior_capacity_ : 0;
  const int min_capacity = store_min ? minima->interior_capacity_ : 0;
  int32_t* max_dest = store_max ? maxima->pos2_.data() + kOffset : nullptr;
  int32_t* min_dest = store_min ? minima->pos2_.data() + kOffset : nullptr;

  ScanState first;
  first.last_sign = n > 0 ? (x[0] > 0.0) - (x[0] < 0.0) : 0;
  const int steps = std::max(n - 1, 0);  // steps 1..n-1
  if (!for_each || (storing && scratch == nullptr)) parts = 1;
  parts = std::clamp(parts, 1, std::max(1, steps));

  ScanState total;
  if (parts == 1) {
    // Straight into the knot sets; writes past a capacity go to its dump slot (the first
    // right-mirror slot, rewritten by MirrorEnds) or to a local when only counting.
    int32_t dump[2];
    const ScanOutput out{max_dest ? max_dest : dump, min_dest ? min_dest : dump + 1, max_capacity,
                         min_capacity};
    total = first;
    ScanRange(x, 1, std::max(n, 1), out, &total);
  } else {
    std::vector<int> begin(parts + 1);
    for (int p = 0; p <= parts; ++p)
      begin[p] = 1 + static_cast<int>(static_cast<int64_t>(steps) * p / parts);
    if (storing) {
      scratch->max_pos.resize(parts);
      scratch->min_pos.resize(parts);
    }
    std::vector<ScanState> found(parts);
    for_each(parts, [&](int p) {
      const ScanState start = p == 0 ? first : StateBefore(x, begin[p]);
      int32_t dump[2];
      for (;;) {
        ScanState st = start;
        ScanOutput out{dump, dump + 1, 0, 0};
        if (store_max) {
          std::vector<int32_t>& pos = scratch->max_pos[p];
          if (pos.empty()) pos.resize(1);
          out.max_pos = pos.data();
          out.max_capacity = static_cast<int>(pos.size()) - 1;
        }
        if (store_min) {
          std::vector<int32_t>& pos = scratch->min_pos[p];
          if (pos.empty()) pos.resize(1);
          out.min_pos = pos.data();
          out.min_capacity = static_cast<int>(pos.size()) - 1;
        }
        ScanRange(x, begin[p], begin[p + 1], out, &st);
        const bool fits = st.num_max <= out.max_capacity || !store_max;
        const bool fits_min = st.num_min <= out.min_capacity || !store_min;
        if (fits && fits_min) {
          found[p] = st;
          break;
        }
        // Rare after the first sifts: the part found more extrema than it had room for.
        if (store_max) GrowPart(st.num_max, &scratch->max_pos[p]);
        if (store_min) GrowPart(st.num_min, &scratch->min_pos[p]);
      }
    });
    std::vector<int> max_offset(parts), min_offset(parts);
    for (int p = 0; p < parts; ++p) {
      max_offset[p] = total.num_max;
      min_offset[p] = total.num_min;
      total.num_max += found[p].num_max;
      total.num_min += found[p].num_min;
      total.num_zc += found[p].num_zc;
    }
    if (storing) {
      for_each(parts, [&](int p) {
        auto place = [](const std::vector<int32_t>& from, int count, int offset, int capacity,
                        int32_t* to) {
          const int kept = std::clamp(capacity - offset, 0, count);
          std::copy(from.begin(), from.begin() + kept, to + offset);
        };
        if (store_max)
          place(scratch->max_pos[p], found[p].num_max, max_offset[p], max_capacity, max_dest);
        if (store_min)
          place(scratch->min_pos[p], found[p].num_min, min_offset[p], min_capacity, min_dest);
      });
    }
  }
  if (maxima) maxima->SetInterior(total.num_max, x);
  if (minima) minima->SetInterior(total.num_min, x);
  return CountsOf(total);
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
