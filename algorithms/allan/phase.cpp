#include "algorithms/allan/phase.h"

#include <cmath>

namespace fogpipe::allan {
namespace {

// Compensated running sum (Kahan-Babuska-Neumaier class): Knuth's branch-free TwoSum gives the
// exact rounding error of every addition, accumulated in `carry`; value = sum + carry is within
// one rounding of the exact running sum however long the series. Branch-free, so the only serial
// dependency is one addition per element.
struct CompensatedSum {
  double sum = 0.0;
  double carry = 0.0;
  void Add(double v) {
    const double t = sum + v;
    const double v_virtual = t - sum;
    carry += (sum - (t - v_virtual)) + (v - v_virtual);
    sum = t;
  }
  double Value() const { return sum + carry; }
};

}  // namespace

Eigen::VectorXd MeanRemovedPhase(const Eigen::Ref<const Eigen::VectorXd>& rate) {
  const Eigen::Index n = rate.size();
  if (n == 0) return Eigen::VectorXd();
  // Four interleaved compensated sums for the mean break the dependency chain.
  CompensatedSum part[4];
  Eigen::Index i = 0;
  for (; i + 4 <= n; i += 4)
    for (int k = 0; k < 4; ++k) part[k].Add(rate[i + k]);
  for (; i < n; ++i) part[0].Add(rate[i]);
  CompensatedSum total;
  for (const CompensatedSum& p : part) {
    total.Add(p.sum);
    total.Add(p.carry);
  }
  const double mean = total.Value() / static_cast<double>(n);
  Eigen::VectorXd x(n + 1);
  x[0] = 0.0;
  CompensatedSum running;
  for (Eigen::Index k = 0; k < n; ++k) {
    running.Add(rate[k] - mean);
    x[k + 1] = running.Value();
  }
  return x;
}

}  // namespace fogpipe::allan
