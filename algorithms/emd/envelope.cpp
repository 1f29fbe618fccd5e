#include "algorithms/emd/envelope.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "algorithms/emd/cubic_spline.h"
#include "algorithms/kernels/lanes.h"

namespace fogpipe::emd {
namespace {

// Walks the pieces of one envelope spline along increasing sample index.
class PieceWalker {
 public:
  explicit PieceWalker(const EnvelopeKnots& knots) : knots_(knots), last_(knots.size() - 2) {}
  // Starts at piece `j` (converted in advance, `piece`); piece `preset_j` is taken from `preset`
  // instead of being converted from the knots when the walk enters it.
  PieceWalker(const EnvelopeKnots& knots, int j, const CubicPiece& piece, int preset_j,
              const CubicPiece& preset)
      : knots_(knots),
        last_(knots.size() - 2),
        j_(j),
        ready_(true),
        piece_(piece),
        preset_j_(preset_j),
        preset_(preset) {}

  // Moves to the piece that contains sample i (half-sample position 2i), computes its polynomial
  // in s = 2i - t_j if it changed, and returns the first sample index NOT covered by it (at most
  // `end`).
  int Advance(int i, int end) {
    const int32_t u = 2 * i;
    bool moved = !ready_;
    while (j_ < last_ && knots_.pos2(j_ + 1) <= u) {
      ++j_;
      moved = true;
    }
    if (moved) {
      piece_ = j_ == preset_j_ ? preset_ : PieceOf(knots_, knots_.moments(), j_);
      ready_ = true;
    }
    if (j_ == last_) return end;
    const int32_t next = knots_.pos2(j_ + 1);
    return std::min(end, (next + 1) >> 1);  // ceil(next / 2): first sample at or after the knot.
  }
  const CubicPiece& piece() const { return piece_; }

 private:
  const EnvelopeKnots& knots_;
  const int last_;  // Index of the last piece.
  int j_ = 0;
  bool ready_ = false;
  CubicPiece piece_;
  int preset_j_ = -1;
  CubicPiece preset_;
};

// The piece a walk from sample 0 is on at sample i: the last j <= size - 2 with t_j <= i (or 0).
int PieceIndex(const EnvelopeKnots& knots, int i) {
  int lo = 0, hi = knots.size() - 2;  // answer in [lo, hi]
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (knots.pos2(mid) <= 2 * i) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return lo;
}

// Samples [begin, end) of h.
template <SiftStatisticsKind kKind>
__attribute__((always_inline)) inline SiftStatistics Subtract(double* h, int begin, int end,
                                                              PieceWalker up, PieceWalker lo,
                                                              double theta1, double theta2) {
  SiftStatistics stats;
  double sum_m2 = 0.0, sum_h2 = 0.0;
  int64_t over1 = 0, over2 = 0;
  int i = begin;
  while (i < end) {
    const int stop = std::min(up.Advance(i, end), lo.Advance(i, end));
    // Local copies so the inner loop is plain arithmetic (vectorizable when no statistics).
    const CubicPiece pu = up.piece(), pl = lo.piece();
    for (; i < stop; ++i) {
      const double u = 2.0 * i;
      const double su = u - pu.origin, sl = u - pl.origin;
      const double eu = pu.c0 + su * (pu.c1 + su * (pu.c2 + su * pu.c3));
      const double el = pl.c0 + sl * (pl.c1 + sl * (pl.c2 + sl * pl.c3));
      const double m = 0.5 * (eu + el);
      if constexpr (kKind == SiftStatisticsKind::kCauchy) {
        sum_m2 += m * m;
        sum_h2 += h[i] * h[i];
      }
      if constexpr (kKind == SiftStatisticsKind::kRilling) {
        const double a = 0.5 * std::abs(eu - el);
        over1 += std::abs(m) > theta1 * a;
        over2 += std::abs(m) > theta2 * a;
      }
      h[i] -= m;
    }
  }
  stats.sum_mean_sq = sum_m2;
  stats.sum_input_sq = sum_h2;
  stats.num_over_theta1 = over1;
  stats.num_over_theta2 = over2;
  return stats;
}

// Compiled for AVX2 beside the baseline in the portable build (kernels/lanes.h): the subtraction
// is element-wise, so the wider vectors give the same bits.
FOGPIPE_LANE_KERNEL SiftStatistics SubtractRange(double* h, int begin, int end,
                                                 const PieceWalker& up, const PieceWalker& lo,
                                                 SiftStatisticsKind kind, double theta1,
                                                 double theta2) {
  switch (kind) {
    case SiftStatisticsKind::kCauchy:
      return Subtract<SiftStatisticsKind::kCauchy>(h, begin, end, up, lo, theta1, theta2);
    case SiftStatisticsKind::kRilling:
      return Subtract<SiftStatisticsKind::kRilling>(h, begin, end, up, lo, theta1, theta2);
    case SiftStatisticsKind::kNone:
      break;
  }
  return Subtract<SiftStatisticsKind::kNone>(h, begin, end, up, lo, theta1, theta2);
}

// A walker for samples [begin, end): its first piece and the piece holding sample end - 1 are
// converted now, while every knot still holds its value.
PieceWalker PartWalker(const EnvelopeKnots& knots, int begin, int end) {
  const int first = PieceIndex(knots, begin), last = PieceIndex(knots, end - 1);
  const CubicPiece first_piece = PieceOf(knots, knots.moments(), first);
  const CubicPiece last_piece = PieceOf(knots, knots.moments(), last);
  return PieceWalker(knots, first, first_piece, last, last_piece);
}

}  // namespace

SiftStatistics SubtractEnvelopeMean(double* h, int n, const EnvelopeKnots& upper,
                                    const EnvelopeKnots& lower, SiftStatisticsKind kind,
                                    double theta1, double theta2) {
  return SubtractRange(h, 0, n, PieceWalker(upper), PieceWalker(lower), kind, theta1, theta2);
}

SiftStatistics SubtractEnvelopeMeanInParts(double* h, int n, const EnvelopeKnots& upper,
                                           const EnvelopeKnots& lower, SiftStatisticsKind kind,
                                           double theta1, double theta2, int parts,
                                           const ForEach& for_each) {
  // The one place the Cauchy rule is kept serial: its two sums over all samples, added part by
  // part, would round differently from the serial pass (the IMFs must not depend on threads).
  if (kind == SiftStatisticsKind::kCauchy) {
    return SubtractEnvelopeMean(h, n, upper, lower, kind, theta1, theta2);
  }
  parts = std::clamp(parts, 1, std::max(1, n));
  std::vector<int> begin(parts + 1);
  for (int p = 0; p <= parts; ++p) begin[p] = static_cast<int>(static_cast<int64_t>(n) * p / parts);
  std::vector<PieceWalker> up, lo;
  up.reserve(parts);
  lo.reserve(parts);
  for (int p = 0; p < parts; ++p) {
    up.push_back(PartWalker(upper, begin[p], begin[p + 1]));
    lo.push_back(PartWalker(lower, begin[p], begin[p + 1]));
  }
  std::vector<SiftStatistics> part_stats(parts);
  for_each(parts, [&](int p) {
    part_stats[p] = SubtractRange(h, begin[p], begin[p + 1], up[p], lo[p], kind, theta1, theta2);
  });
  SiftStatistics stats;
  for (const SiftStatistics& s : part_stats) {
    stats.num_over_theta1 += s.num_over_theta1;
    stats.num_over_theta2 += s.num_over_theta2;
  }
  return stats;
}

}  // namespace fogpipe::emd
