#include "algorithms/filters/moving_average.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "algorithms/filters/search.h"

namespace fogpipe::filters {
namespace {

/// Prefix sums of x - mean (the mean removed keeps the partial sums small).
std::vector<double> PrefixSums(const Eigen::VectorXd& x, double mean) {
  std::vector<double> prefix(x.size() + 1, 0.0);
  for (Eigen::Index i = 0; i < x.size(); ++i) prefix[i + 1] = prefix[i] + (x[i] - mean);
  return prefix;
}

/// The window of sample i, [*lo, *hi): 2h + 1 samples centred on i, truncated at the ends.
void Window(Eigen::Index i, Eigen::Index h, Eigen::Index n, Eigen::Index* lo, Eigen::Index* hi) {
  *lo = std::max<Eigen::Index>(0, i - h);
  *hi = std::min<Eigen::Index>(n, i + h + 1);
}

/// Calls out(i, window sum of x - mean, count) for every i.
template <typename Out>
void ForEachWindow(const std::vector<double>& prefix, Eigen::Index h, Out out) {
  const auto n = static_cast<Eigen::Index>(prefix.size()) - 1;
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Index lo = 0, hi = 0;
    Window(i, h, n, &lo, &hi);
    out(i, prefix[hi] - prefix[lo], static_cast<double>(hi - lo));
  }
}

}  // namespace

Eigen::VectorXd CentredMovingAverage(const Eigen::VectorXd& x, Eigen::Index half_width) {
  const double mean = x.size() > 0 ? x.mean() : 0.0;
  const std::vector<double> prefix = PrefixSums(x, mean);
  Eigen::VectorXd y(x.size());
  ForEachWindow(prefix, half_width,
                [&](Eigen::Index i, double sum, double count) { y[i] = mean + sum / count; });
  return y;
}

bool MovingAverageOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* what) {
    if (error) *error = what;
    return false;
  };
  if (half_width < 0) return fail("moving average half_width must be >= 0 (0: by GCV)");
  if (!(max_fraction > 0.0 && max_fraction <= 0.5))
    return fail("moving average max_fraction must be in (0, 0.5]");
  if (grid_points < 3) return fail("moving average grid_points must be >= 3");
  return true;
}

MovingAverageGcv::MovingAverageGcv(const Eigen::VectorXd& x) : x_(x), mean_(x.mean()) {
  prefix_ = PrefixSums(x, mean_);
}

double MovingAverageGcv::Score(Eigen::Index half_width, double* trace) const {
  const Eigen::Index n = x_.size(), h = half_width;
  // Samples [interior_begin, interior_end) have the whole window of 2h + 1: there the residuals
  // are summed in four interleaved partial sums (the additions of one running sum would wait on
  // each other) and tr S gains (count) / (2h + 1) in one step. The truncated ends go one by one.
  const Eigen::Index interior_begin = std::min(h, n);
  const Eigen::Index interior_end = std::max(interior_begin, n - h);
  double rss = 0.0, tr = 0.0;
  auto one = [&](Eigen::Index i) {
    Eigen::Index lo = 0, hi = 0;
    Window(i, h, n, &lo, &hi);
    const double count = static_cast<double>(hi - lo);
    const double r = (x_[i] - mean_) - (prefix_[hi] - prefix_[lo]) / count;
    rss += r * r;
    tr += 1.0 / count;
  };
  for (Eigen::Index i = 0; i < interior_begin; ++i) one(i);
  const double width = static_cast<double>(2 * h + 1);
  const double* p = prefix_.data();
  const double* x = x_.data();
  double partial[4] = {0.0, 0.0, 0.0, 0.0};
  Eigen::Index i = interior_begin;
  for (; i + 4 <= interior_end; i += 4) {
    for (int l = 0; l < 4; ++l) {
      const double r = (x[i + l] - mean_) - (p[i + l + h + 1] - p[i + l - h]) / width;
      partial[l] += r * r;
    }
  }
  for (; i < interior_end; ++i) {
    const double r = (x[i] - mean_) - (p[i + h + 1] - p[i - h]) / width;
    partial[0] += r * r;
  }
  rss += (partial[0] + partial[1]) + (partial[2] + partial[3]);
  tr += static_cast<double>(interior_end - interior_begin) / width;
  for (Eigen::Index k = interior_end; k < n; ++k) one(k);
  if (trace) *trace = tr;
  const double nn = static_cast<double>(n);
  return nn * rss / ((nn - tr) * (nn - tr));
}

MovingAverageResult MovingAverage(const Eigen::VectorXd& x, const MovingAverageOptions& options) {
  MovingAverageResult out;
  if (!options.IsValid(&out.message)) return out;
  const Eigen::Index n = x.size();
  if (n < 8) {
    out.termination = Termination::kInsufficientData;
    out.message = "moving average: fewer than 8 samples";
    return out;
  }
  out.gcv = std::numeric_limits<double>::quiet_NaN();
  out.half_width = options.half_width;
  if (out.half_width == 0) {
    const MovingAverageGcv gcv(x);
    const double hi = std::max(2.0, options.max_fraction * static_cast<double>(n));
    // The search asks for the same integer half-width many times where h is small.
    std::map<long long, double> scores;
    auto score = [&](double h) {
      const long long w = std::llround(h);
      const auto known = scores.find(w);
      if (known != scores.end()) return known->second;
      return scores[w] = gcv.Score(w);
    };
    const LogSearchResult best = MinimizeOnLogScale(score, 1.0, hi, options.grid_points, 1e-3);
    out.half_width = std::llround(best.argument);
    out.gcv = gcv.Score(out.half_width, &out.trace);
    out.at_upper_bound = best.at_upper_bound;
  }
  out.output = CentredMovingAverage(x, out.half_width);
  out.termination = out.output.allFinite() ? Termination::kSuccess : Termination::kNumericalFailure;
  if (!HasResult(out.termination)) out.message = "moving average: non-finite output";
  return out;
}

}  // namespace fogpipe::filters
