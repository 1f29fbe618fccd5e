// Centred moving average with its window chosen by generalised cross-validation (Craven & Wahba
// 1979), without the truth.
//
// yhat_i = mean of x_j over |j - i| <= h and 0 <= j < N (window w = 2h + 1 samples, truncated at
// the ends). It is a linear smoother yhat = S y with S_ii = 1 / (samples in the window of i), so
// tr S = sum_i 1 / count_i (N / w away from the ends) and
//   GCV(h) = N ||y - yhat||^2 / (N - tr S)^2,
// each evaluation O(N) from one prefix sum. Search over h: a log grid, then golden section
// (search.h) on rounded h.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/common/status.h"

namespace fogpipe::filters {

/// The moving average of half-width h (window 2h + 1, truncated at the ends). O(N).
Eigen::VectorXd CentredMovingAverage(const Eigen::VectorXd& x, Eigen::Index half_width);

struct MovingAverageOptions {
  /// Half-width h, samples; 0 (default) = by GCV.
  Eigen::Index half_width = 0;
  /// GCV search: h from 1 to max_fraction x N, grid_points log-spaced, then golden section.
  double max_fraction = 0.25;
  int grid_points = 24;

  bool IsValid(std::string* error) const;
};

struct MovingAverageResult {
  Eigen::VectorXd output;        ///< filtered x, units of x
  Eigen::Index half_width = 0;   ///< h used; the window is 2h + 1 samples
  double gcv = 0.0;              ///< GCV score at h, (units of x)^2 (NaN when given)
  double trace = 0.0;            ///< tr S at h
  bool at_upper_bound = false;   ///< GCV chose the widest window of its grid
  Termination termination = Termination::kInvalidOptions;
  std::string message;
};

/// GCV of the moving average from one prefix sum. Exposed for tests.
class MovingAverageGcv {
 public:
  explicit MovingAverageGcv(const Eigen::VectorXd& x);
  /// GCV(h), (units of x)^2; *trace (optional): tr S.
  double Score(Eigen::Index half_width, double* trace = nullptr) const;

 private:
  const Eigen::VectorXd& x_;
  std::vector<double> prefix_;  // prefix_[i] = sum of (x_j - mean) for j < i
  double mean_ = 0.0;
};

MovingAverageResult MovingAverage(const Eigen::VectorXd& x, const MovingAverageOptions& options);

}  // namespace fogpipe::filters
