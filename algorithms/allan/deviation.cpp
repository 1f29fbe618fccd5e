#include "algorithms/allan/deviation.h"

#include <algorithm>

namespace fogpipe::allan {
namespace {

// 8192 doubles = 64 KiB per stream: a block and its neighbours at short lags stay in L2.
constexpr Eigen::Index kBlock = 8192;

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
  }
  return "unknown";
}

int DifferenceOrder(Deviation deviation) {
  return (deviation == Deviation::kOverlappingHadamard || deviation == Deviation::kHadamard) ? 3
                                                                                             : 2;
}

bool IsOverlapping(Deviation deviation) {
  return deviation == Deviation::kOverlappingAllan || deviation == Deviation::kOverlappingHadamard;
}

long long MaxAveragingFactor(Deviation deviation, long long n_rate_samples) {
  return n_rate_samples / DifferenceOrder(deviation);
}

long long DifferenceCount(Deviation deviation, long long n_rate_samples, long long m) {
  if (m < 1) return 0;
  const int d = DifferenceOrder(deviation);
  if (IsOverlapping(deviation)) return n_rate_samples + 1 - d * m;
  return n_rate_samples / m - d + 1;
}

std::vector<double> DeviationVariances(const Eigen::VectorXd& phase, Deviation deviation,
                                       const std::vector<long long>& m) {
  const Eigen::Index n_phase = phase.size();
  const long long n = n_phase - 1;
  const int d = DifferenceOrder(deviation);
  const double c = d == 2 ? 2.0 : 6.0;
  std::vector<double> sums(m.size(), 0.0);
  const double* x = phase.data();
  if (IsOverlapping(deviation)) {
    // One sweep over blocks of start indices; for each block every factor adds its terms.
    long long max_count = 0;
    for (long long mk : m) max_count = std::max(max_count, DifferenceCount(deviation, n, mk));
    for (Eigen::Index b = 0; b < max_count; b += kBlock) {
      for (size_t k = 0; k < m.size(); ++k) {
        const Eigen::Index end =
            std::min<Eigen::Index>(b + kBlock, DifferenceCount(deviation, n, m[k]));
        if (end <= b) continue;
        sums[k] += OverlappingBlockSum(x, d, m[k], b, end);
      }
    }
  } else {
    for (size_t k = 0; k < m.size(); ++k)
      sums[k] = NonOverlappingSum(x, d, m[k], DifferenceCount(deviation, n, m[k]));
  }
  std::vector<double> variance(m.size());
  for (size_t k = 0; k < m.size(); ++k) {
    const double mm = static_cast<double>(m[k]);
    variance[k] =
        sums[k] / (c * mm * mm * static_cast<double>(DifferenceCount(deviation, n, m[k])));
  }
  return variance;
}

}  // namespace fogpipe::allan
