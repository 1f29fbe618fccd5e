#include "algorithms/allan/phase.h"

#include <cmath>

#include "algorithms/kernels/lanes.h"

namespace fogpipe::allan {
namespace {

using kernels::LoadLanes4;
using Lanes = kernels::Lanes4;

// Compensated running sum (Kahan-Babuska-Neumaier class): Knuth's branch-free TwoSum gives the
// exact rounding error of every addition, accumulated in `carry`; value = sum + carry is within
// one rounding of the exact running sum however long the series. Branch-free, so the only serial
// dependency is one addition per element. T = Lanes: four independent sums in one vector, each
// element computing exactly what T = double computes (additions and subtractions only, so
// nothing can be contracted into a multiply-add).
template <typename T>
struct CompensatedSum {
  T sum = T{};
  T carry = T{};
  void Add(T v) {
    const T t = sum + v;
    const T v_virtual = t - sum;
    carry += (sum - (t - v_virtual)) + (v - v_virtual);
    sum = t;
  }
  T Value() const { return sum + carry; }
};

// Element c of a vector of sums as a sum of its own.
CompensatedSum<double> Part(const CompensatedSum<Lanes>& sums, int c) {
  CompensatedSum<double> part;
  part.sum = sums.sum[c];
  part.carry = sums.carry[c];
  return part;
}

}  // namespace

Eigen::VectorXd MeanRemovedPhase(const Eigen::Ref<const Eigen::VectorXd>& rate) {
  Eigen::VectorXd x;
  MeanRemovedPhase(rate, &x);
  return x;
}

void MeanRemovedPhase(const Eigen::Ref<const Eigen::VectorXd>& rate, Eigen::VectorXd* phase) {
  const Eigen::Index n = rate.size();
  if (n == 0) {
    phase->resize(0);
    return;
  }
  // Four interleaved compensated sums for the mean break the dependency chain (in one vector,
  // element k summing elements 4j + k).
  CompensatedSum<Lanes> parts;
  Eigen::Index i = 0;
  for (; i + 4 <= n; i += 4) {
    parts.Add(LoadLanes4(rate.data() + i));
  }
  CompensatedSum<double> part[4] = {Part(parts, 0), Part(parts, 1), Part(parts, 2), Part(parts, 3)};
  for (; i < n; ++i) part[0].Add(rate[i]);
  CompensatedSum<double> total;
  for (const CompensatedSum<double>& p : part) {
    total.Add(p.sum);
    total.Add(p.carry);
  }
  const double mean = total.Value() / static_cast<double>(n);
  phase->resize(n + 1);
  Eigen::VectorXd& x = *phase;
  x[0] = 0.0;
  // The running sum in four parts side by side: each part's compensated sum from 0 (four
  // independent chains the CPU overlaps; one chain is bound by an addition's latency per sample,
  // measured 3.5 % of a `fogpipe sweep`), then parts 1-3 shifted by the compensated total of the
  // parts before them. Each value is within a rounding or two of the exact running sum, as with
  // one chain.
  const Eigen::Index quarter = n >= 4096 ? n / 4 : 0;
  CompensatedSum<double> running[4];
  if (quarter > 0) {
    // The four parts' sums in one vector (element c: part c).
    CompensatedSum<Lanes> sums;
    const double* r = rate.data();
    double* out = x.data() + 1;
    for (Eigen::Index k = 0; k < quarter; ++k) {
      sums.Add(Lanes{r[k], r[quarter + k], r[2 * quarter + k], r[3 * quarter + k]} - mean);
      const Lanes value = sums.Value();
      out[k] = value[0];
      out[quarter + k] = value[1];
      out[2 * quarter + k] = value[2];
      out[3 * quarter + k] = value[3];
    }
    for (int c = 0; c < 4; ++c) running[c] = Part(sums, c);
  }
  for (Eigen::Index i = 4 * quarter; i < n; ++i) {  // the rest belongs to the last part
    const int c = quarter > 0 ? 3 : 0;
    running[c].Add(rate[i] - mean);
    x[i + 1] = running[c].Value();
  }
  if (quarter > 0) {
    CompensatedSum<double> offset;
    for (int c = 1; c < 4; ++c) {
      offset.Add(running[c - 1].sum);
      offset.Add(running[c - 1].carry);
      const double hi = offset.sum, lo = offset.carry;
      const Eigen::Index end = c < 3 ? (c + 1) * quarter : n;
      for (Eigen::Index i = c * quarter; i < end; ++i) x[i + 1] = hi + (x[i + 1] + lo);
    }
  }
}

}  // namespace fogpipe::allan
