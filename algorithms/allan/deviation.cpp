#include "algorithms/allan/deviation.h"

#include <algorithm>
#include <type_traits>
#include <vector>

#include "algorithms/allan/workers.h"
#include "algorithms/common/eigen_sums.h"

namespace fogpipe::allan {
namespace {

// 8192 doubles = 64 KiB per stream: a block and its neighbours at short lags stay in L2.
constexpr Eigen::Index kBlock = 8192;
// 64 blocks (4 MiB of each stream) per unit of work shared among threads.
constexpr Eigen::Index kChunk = 64 * kBlock;

using ConstSegment = Eigen::Map<const Eigen::VectorXd>;
using StridedSegment = Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<>>;

// Sum of squared d-th differences at lag m over starts [begin, end) (all starts).
double OverlappingBlockSum(const double* x, int d, Eigen::Index m, Eigen::Index begin,
                           Eigen::Index end) {
  const Eigen::Index len = end - begin;
  const ConstSegment x0(x + begin, len), x1(x + begin + m, len), x2(x + begin + 2 * m, len);
  if (d == 2) return (x2 - 2.0 * x1 + x0).squaredNorm();
  const ConstSegment x3(x + begin + 3 * m, len);
  return (x3 - 3.0 * x2 + 3.0 * x1 - x0).squaredNorm();
}

// Sum of squared d-th differences at lag m over starts 0, m, 2m, ... (count of them).
double NonOverlappingSum(const double* x, int d, Eigen::Index m, Eigen::Index count) {
  const Eigen::InnerStride<> stride(m);
  const StridedSegment x0(x, count, stride), x1(x + m, count, stride), x2(x + 2 * m, count, stride);
  if (d == 2) return (x2 - 2.0 * x1 + x0).squaredNorm();
  const StridedSegment x3(x + 3 * m, count, stride);
  return (x3 - 3.0 * x2 + 3.0 * x1 - x0).squaredNorm();
}

// Sum of squared S_j (deviation.h) over starts [begin, end) from the prefix sum P = hi + lo of
// the phase: S_j = W_{j+2m} - 2 W_{j+m} + W_j with W_k = P_{k+m} - P_k formed as
// (hi_{k+m} - hi_k) + (lo_{k+m} - lo_k). Each hi difference rounds relative to W, not to P.
double ModifiedBlockSum(const double* hi, const double* lo, Eigen::Index m, Eigen::Index begin,
                        Eigen::Index end) {
  const Eigen::Index len = end - begin;
  using Seg = Eigen::Map<const Eigen::ArrayXd>;
  const Seg h0(hi + begin, len), h1(hi + begin + m, len), h2(hi + begin + 2 * m, len),
      h3(hi + begin + 3 * m, len);
  const Seg l0(lo + begin, len), l1(lo + begin + m, len), l2(lo + begin + 2 * m, len),
      l3(lo + begin + 3 * m, len);
  return (((h3 - h2) + (l3 - l2)) - 2.0 * ((h2 - h1) + (l2 - l1)) + ((h1 - h0) + (l1 - l0)))
      .square()
      .sum();
}

// P_0 = 0, P_{k+1} = P_k + x_k as hi + lo: hi is the plain running sum, lo accumulates the exact
// rounding error of each addition (Knuth's TwoSum), so hi_k + lo_k = P_k to ~eps^2 sum |x|.
void PhasePrefixSum(const Eigen::VectorXd& x, Eigen::VectorXd* hi, Eigen::VectorXd* lo) {
  const Eigen::Index n = x.size();
  hi->resize(n + 1);
  lo->resize(n + 1);
  double s = 0.0, c = 0.0;
  (*hi)[0] = 0.0;
  (*lo)[0] = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = s + x[k];
    const double bp = t - s;
    c += (s - (t - bp)) + (x[k] - bp);
    s = t;
    (*hi)[k + 1] = s;
    (*lo)[k + 1] = c;
  }
}

// The reflected terms of the total variance: centres i in [1, N - 2] outside [m, N - 1 - m]
// (whose terms are the ordinary overlapping ones), at most 2 (m - 1) of them.
double TotalReflectedSum(const Eigen::VectorXd& x, long long m) {
  const long long last = x.size() - 1;
  auto at = [&x, last](long long k) {
    if (k < 0) return 2.0 * x[0] - x[-k];
    if (k > last) return 2.0 * x[last] - x[2 * last - k];
    return x[k];
  };
  double sum = 0.0;
  for (long long i = 1; i <= last - 1; ++i) {
    if (i == m && m <= last - m) {  // skip the ordinary centres
      i = last - m;
      continue;
    }
    const double d = at(i - m) - 2.0 * at(i) + at(i + m);
    sum += d * d;
  }
  return sum;
}

// Number of ordinary (unreflected, all-start) terms that the blocked sweep adds for factor m.
long long SweepCount(Deviation deviation, long long n, long long m) {
  if (deviation == Deviation::kTotal) return DifferenceCount(Deviation::kOverlappingAllan, n, m);
  return DifferenceCount(deviation, n, m);
}

}  // namespace

const char* ToString(Deviation deviation) {
  switch (deviation) {
    case Deviation::kOverlappingAllan:
      return "oadev";
    case Deviation::kAllan:
      return "adev";
    case Deviation::kOverlappingHadamard:
      return "ohdev";
    case Deviation::kHadamard:
      return "hdev";
    case Deviation::kModifiedAllan:
      return "mdev";
    case Deviation::kTime:
      return "tdev";
    case Deviation::kTotal:
      return "totdev";
  }
  return "unknown";
}

const std::vector<Deviation>& AllDeviations() {
  static const std::vector<Deviation> all = {Deviation::kOverlappingAllan,
                                             Deviation::kAllan,
                                             Deviation::kModifiedAllan,
                                             Deviation::kTime,
                                             Deviation::kOverlappingHadamard,
                                             Deviation::kHadamard,
                                             Deviation::kTotal};
  return all;
}

bool ParseDeviation(const std::string& text, Deviation* deviation) {
  for (Deviation d : AllDeviations()) {
    if (text == ToString(d)) {
      *deviation = d;
      return true;
    }
  }
  return false;
}

int DifferenceOrder(Deviation deviation) {
  return (deviation == Deviation::kOverlappingHadamard || deviation == Deviation::kHadamard) ? 3
                                                                                             : 2;
}

bool IsOverlapping(Deviation deviation) {
  return deviation != Deviation::kAllan && deviation != Deviation::kHadamard;
}

bool IsModified(Deviation deviation) {
  return deviation == Deviation::kModifiedAllan || deviation == Deviation::kTime;
}

bool IsTimeDeviation(Deviation deviation) { return deviation == Deviation::kTime; }

bool IeeeModelApplies(Deviation deviation) {
  return deviation == Deviation::kOverlappingAllan || deviation == Deviation::kAllan;
}

long long MaxAveragingFactor(Deviation deviation, long long n_rate_samples) {
  if (deviation == Deviation::kTotal) return n_rate_samples < 1 ? 0 : (n_rate_samples - 1) / 2;
  if (IsModified(deviation)) return n_rate_samples / 3;
  return n_rate_samples / DifferenceOrder(deviation);
}

long long DifferenceCount(Deviation deviation, long long n_rate_samples, long long m) {
  if (m < 1) return 0;
  if (deviation == Deviation::kTotal) return m < n_rate_samples ? n_rate_samples - 1 : 0;
  if (IsModified(deviation)) return n_rate_samples + 2 - 3 * m;  // N - 3m + 1
  const int d = DifferenceOrder(deviation);
  if (IsOverlapping(deviation)) return n_rate_samples + 1 - d * m;
  return n_rate_samples / m - d + 1;
}

std::vector<double> DeviationVariances(const Eigen::VectorXd& phase, Deviation deviation,
                                       const std::vector<long long>& m, int threads) {
  const Eigen::Index n_phase = phase.size();
  const long long n = n_phase - 1;
  const int d = DifferenceOrder(deviation);
  const bool modified = IsModified(deviation);
  std::vector<double> sums(m.size(), 0.0);
  const double* x = phase.data();
  Eigen::VectorXd hi, lo;
  if (modified) PhasePrefixSum(phase, &hi, &lo);
  if (IsOverlapping(deviation)) {
    // Sweeps over blocks of start indices; for each block every factor adds its terms. The starts
    // are cut into fixed chunks whose partial sums are added in chunk order, so the result does
    // not depend on how many threads share the chunks.
    long long max_count = 0;
    for (long long mk : m) max_count = std::max(max_count, SweepCount(deviation, n, mk));
    const Eigen::Index chunks = (max_count + kChunk - 1) / kChunk;
    std::vector<double> partial(static_cast<size_t>(chunks) * m.size(), 0.0);
    auto sweep_chunk = [&](Eigen::Index c) {
      double* out = partial.data() + static_cast<size_t>(c) * m.size();
      const Eigen::Index chunk_end = std::min<Eigen::Index>((c + 1) * kChunk, max_count);
      for (Eigen::Index b = c * kChunk; b < chunk_end; b += kBlock) {
        auto end_of = [&](size_t k) {
          return std::min<Eigen::Index>(std::min<Eigen::Index>(b + kBlock, chunk_end),
                                        SweepCount(deviation, n, m[k]));
        };
        size_t k = 0;
        if (!modified) {
          // Four factors at a time where they share the block's length (all but the last
          // blocks); each sum has the bits OverlappingBlockSum gives it.
          for (; k + 4 <= m.size(); k += 4) {
            const Eigen::Index end = end_of(k);
            if (end <= b || end_of(k + 1) != end || end_of(k + 2) != end || end_of(k + 3) != end)
              break;
            double sums4[4];
            internal::OverlappingBlockSums4(x, d, {m[k], m[k + 1], m[k + 2], m[k + 3]}, b, end - b,
                                            sums4);
            for (int j = 0; j < 4; ++j) out[k + j] += sums4[j];
          }
        }
        for (; k < m.size(); ++k) {
          const Eigen::Index end = end_of(k);
          if (end <= b) continue;
          out[k] += modified ? ModifiedBlockSum(hi.data(), lo.data(), m[k], b, end)
                             : OverlappingBlockSum(x, d, m[k], b, end);
        }
      }
    };
    internal::ShareAmongThreads(threads, chunks, sweep_chunk);
    for (Eigen::Index c = 0; c < chunks; ++c)
      for (size_t k = 0; k < m.size(); ++k)
        sums[k] += partial[static_cast<size_t>(c) * m.size() + k];
    if (deviation == Deviation::kTotal)
      for (size_t k = 0; k < m.size(); ++k) sums[k] += TotalReflectedSum(phase, m[k]);
  } else {
    for (size_t k = 0; k < m.size(); ++k)
      sums[k] = NonOverlappingSum(x, d, m[k], DifferenceCount(deviation, n, m[k]));
  }
  std::vector<double> variance(m.size());
  for (size_t k = 0; k < m.size(); ++k) {
    const double mm = static_cast<double>(m[k]);
    const double count = static_cast<double>(DifferenceCount(deviation, n, m[k]));
    double norm = (d == 2 ? 2.0 : 6.0) * mm * mm;  // c_d m^2
    if (deviation == Deviation::kModifiedAllan) norm = 2.0 * mm * mm * mm * mm;
    if (deviation == Deviation::kTime) norm = 6.0 * mm * mm;  // (m^2 / 3) / (2 m^4)
    variance[k] = sums[k] / (norm * count);
  }
  return variance;
}

namespace internal {

namespace {

template <int kD>
void OverlappingBlockSums4Of(const double* x, const long long (&m)[4], Eigen::Index begin,
                             Eigen::Index len, double (&out)[4]) {
  namespace ei = Eigen::internal;
  const double* start = x + begin;
  SumsInEigensOrder<4>(
      len,
      [&](int k, Eigen::Index i, auto like) {
        using T = decltype(like);
        const double* p = start + i;
        const Eigen::Index mk = m[k];
        // As Eigen evaluates x2 - 2.0 * x1 + x0 (or x3 - 3.0 * x2 + 3.0 * x1 - x0) from the left,
        // the constant times the segment, then its square.
        if constexpr (std::is_same_v<T, double>) {
          const double e = kD == 2 ? (p[2 * mk] - 2.0 * p[mk]) + p[0]
                                   : ((p[3 * mk] - 3.0 * p[2 * mk]) + 3.0 * p[mk]) - p[0];
          return e * e;
        } else {
          T e;
          if constexpr (kD == 2) {
            e = ei::padd(ei::psub(ei::ploadu<T>(p + 2 * mk),
                                  ei::pmul(ei::pset1<T>(2.0), ei::ploadu<T>(p + mk))),
                         ei::ploadu<T>(p));
          } else {
            const T three = ei::pset1<T>(3.0);
            e = ei::psub(ei::padd(ei::psub(ei::ploadu<T>(p + 3 * mk),
                                           ei::pmul(three, ei::ploadu<T>(p + 2 * mk))),
                                  ei::pmul(three, ei::ploadu<T>(p + mk))),
                         ei::ploadu<T>(p));
          }
          return ei::pmul(e, e);
        }
      },
      out);
}

}  // namespace

void OverlappingBlockSums4(const double* x, int d, const long long (&m)[4], Eigen::Index begin,
                           Eigen::Index len, double (&out)[4]) {
  if (d == 2) {
    OverlappingBlockSums4Of<2>(x, m, begin, len, out);
  } else {
    OverlappingBlockSums4Of<3>(x, m, begin, len, out);
  }
}

}  // namespace internal

}  // namespace fogpipe::allan
