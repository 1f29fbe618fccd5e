#include "algorithms/emd/envelope.h"

#include <algorithm>
#include <cmath>

#include "algorithms/emd/cubic_spline.h"

namespace fogpipe::emd {
namespace {

// Walks the pieces of one envelope spline along increasing sample index.
class PieceWalker {
 public:
  explicit PieceWalker(const EnvelopeKnots& knots) : knots_(knots), last_(knots.size() - 2) {}

  // Moves to the piece that contains sample i (half-sample position 2i), computes its polynomial
  // in s = 2i - t_j if it changed, and returns the first sample index NOT covered by it.
  int Advance(int i, int n) {
    const int32_t u = 2 * i;
    bool moved = !ready_;
    while (j_ < last_ && knots_.pos2(j_ + 1) <= u) {
      ++j_;
      moved = true;
    }
    if (moved) {
      piece_ = PieceOf(knots_, knots_.moments(), j_);
      ready_ = true;
    }
    if (j_ == last_) return n;
    const int32_t next = knots_.pos2(j_ + 1);
    return std::min(n, (next + 1) >> 1);  // ceil(next / 2): first sample at or after the knot.
  }
  const CubicPiece& piece() const { return piece_; }

 private:
  const EnvelopeKnots& knots_;
  const int last_;  // Index of the last piece.
  int j_ = 0;
  bool ready_ = false;
  CubicPiece piece_;
};

template <SiftStatisticsKind kKind>
SiftStatistics Subtract(double* h, int n, const EnvelopeKnots& upper, const EnvelopeKnots& lower,
                        double theta1, double theta2) {
  PieceWalker up(upper), lo(lower);
  SiftStatistics stats;
  double sum_m2 = 0.0, sum_h2 = 0.0;
  int64_t over1 = 0, over2 = 0;
  int i = 0;
  while (i < n) {
    const int end = std::min(up.Advance(i, n), lo.Advance(i, n));
    // Local copies so the inner loop is plain arithmetic (vectorizable when no statistics).
    const CubicPiece pu = up.piece(), pl = lo.piece();
    for (; i < end; ++i) {
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

}  // namespace

SiftStatistics SubtractEnvelopeMean(double* h, int n, const EnvelopeKnots& upper,
                                    const EnvelopeKnots& lower, SiftStatisticsKind kind,
                                    double theta1, double theta2) {
  switch (kind) {
    case SiftStatisticsKind::kCauchy:
      return Subtract<SiftStatisticsKind::kCauchy>(h, n, upper, lower, theta1, theta2);
    case SiftStatisticsKind::kRilling:
      return Subtract<SiftStatisticsKind::kRilling>(h, n, upper, lower, theta1, theta2);
    case SiftStatisticsKind::kNone:
      break;
  }
  return Subtract<SiftStatisticsKind::kNone>(h, n, upper, lower, theta1, theta2);
}

}  // namespace fogpipe::emd
