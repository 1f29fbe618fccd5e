#include "algorithms/allan/phase.h"

#include <cmath>

namespace fogpipe::allan {
namespace {

// Neumaier's improved Kahan summation: the rounding error of every addition is kept in `carry`.
struct NeumaierSum {
  double sum = 0.0;
  double carry = 0.0;
  void Add(double v) {
    const double t = sum + v;
    if (std::abs(sum) >= std::abs(v)) {
      carry += (sum - t) + v;
    } else {
      carry += (v - t) + sum;
    }
    sum = t;
  }
  double Value() const { return sum + carry; }
};

}  // namespace

Eigen::VectorXd MeanRemovedPhase(const Eigen::Ref<const Eigen::VectorXd>& rate) {
  const Eigen::Index n = rate.size();
  if (n == 0) return Eigen::VectorXd();
  NeumaierSum total;
  for (Eigen::Index i = 0; i < n; ++i) total.Add(rate[i]);
  const double mean = total.Value() / static_cast<double>(n);
  Eigen::VectorXd x(n + 1);
  x[0] = 0.0;
  NeumaierSum running;
  for (Eigen::Index i = 0; i < n; ++i) {
    running.Add(rate[i] - mean);
    x[i + 1] = running.Value();
  }
  return x;
}

}  // namespace fogpipe::allan
