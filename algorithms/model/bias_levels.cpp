#include "algorithms/model/bias_levels.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include "algorithms/common/units.h"
#include "algorithms/filters/random_walk_kalman.h"

namespace fogpipe::model {
namespace {

// The sample in [lo, hi] where a step best splits x[begin, end) (exact two-segment least squares).
long RefineStep(const Eigen::VectorXd& x, long begin, long end, long lo, long hi) {
  double total = 0;
  for (long i = begin; i < end; ++i) total += x[i];
  double left_sum = 0;
  for (long i = begin; i < lo; ++i) left_sum += x[i];
  const double length = static_cast<double>(end - begin);
  long best = lo;
  double best_gain = -1;
  for (long c = lo; c <= hi; ++c) {
    if (c > lo) left_sum += x[c - 1];
    const double left = static_cast<double>(c - begin);
    if (left <= 0 || left >= length) continue;
    const double deviation = left_sum - left / length * total;
    const double gain = deviation * deviation * length / (left * (length - left));
    if (gain > best_gain) {
      best_gain = gain;
      best = c;
    }
  }
  return best;
}

// The most steps a dense design of `num_samples` samples may hold under options.max_design_bytes
// (8 bytes per sample and step; no limit when it is 0).
long MaxDesignSteps(long num_samples, const LevelsOptions& options) {
  if (!(options.max_design_bytes > 0)) return std::numeric_limits<long>::max();
  return static_cast<long>(
      std::floor(options.max_design_bytes / (8.0 * static_cast<double>(num_samples))));
}

}  // namespace

bool LevelsOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* message) {
    if (error) *error = message;
    return false;
  };
  if (!(block_s > 0)) return fail("block_s must be > 0");
  if (!(variance_ratio >= 0)) return fail("variance_ratio must be >= 0");
  if (!(penalty_per_step > 0)) return fail("penalty_per_step must be > 0");
  if (!(walk_penalty_per_step >= 0)) return fail("walk_penalty_per_step must be >= 0");
  if (!(min_segment_s >= block_s)) return fail("min_segment_s must be >= block_s");
  if (!(max_design_bytes >= 0)) return fail("max_design_bytes must be >= 0");
  return true;
}

namespace {

// Optimal partitioning of block means y by PELT (Killick, Fearnhead & Eckley 2012): minimises
// sum over segments of RSS / variance + penalty per change point; segments at least min_length
// blocks. Returns the change points (block indices where a new level starts), ascending.
std::vector<long> Pelt(const std::vector<double>& prefix, const std::vector<double>& prefix_sq,
                       long m, long min_length, double variance, double penalty) {
  const auto cost = [&](long s, long t) {
    const double sum = prefix[t] - prefix[s];
    return (prefix_sq[t] - prefix_sq[s] - sum * sum / static_cast<double>(t - s)) / variance;
  };
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> best(m + 1, inf);
  std::vector<long> last(m + 1, 0);
  best[0] = -penalty;
  std::vector<long> candidates = {0};
  for (long t = min_length; t <= m; ++t) {
    double value = inf;
    long argmin = 0;
    for (long s : candidates) {
      if (t - s < min_length || best[s] == inf) continue;
      const double trial = best[s] + cost(s, t) + penalty;
      if (trial < value) {
        value = trial;
        argmin = s;
      }
    }
    best[t] = value;
    last[t] = argmin;
    // Prune: s can never be optimal again once F(s) + C(s, t) > F(t) (cost is additive).
    std::vector<long> kept;
    for (long s : candidates)
      if (t - s < min_length || best[s] == inf || best[s] + cost(s, t) <= value) kept.push_back(s);
    if (t + min_length <= m) kept.push_back(t);
    candidates.swap(kept);
  }
  std::vector<long> changes;
  for (long t = last[m]; t > 0; t = last[t]) changes.push_back(t);
  std::reverse(changes.begin(), changes.end());
  return changes;
}

// b var(means of batches of b) / sigma2 over the whole batches of x, at least 1: the long-run to
// short-run variance ratio at the batch scale (batch means; Law & Kelton).
double BatchMeansVarianceRatio(const Eigen::VectorXd& x, long batch, double sigma2) {
  const long count = x.size() / batch;
  if (count < 2) return 1.0;
  Eigen::VectorXd means(count);
  for (long i = 0; i < count; ++i) means[i] = x.segment(i * batch, batch).mean();
  const double variance = (means.array() - means.mean()).square().sum() / (count - 1);
  return std::max(1.0, batch * variance / std::max(sigma2, 1e-300));
}

}  // namespace

LevelsSegmentation SegmentLevels(const Eigen::VectorXd& x, double fs,
                                 const LevelsOptions& options) {
  LevelsSegmentation result;
  const long n = x.size();
  const long block = std::max(1L, static_cast<long>(std::lround(options.block_s * fs)));
  const long m = n / block;
  const long min_length =
      std::max(1L, static_cast<long>(std::lround(options.min_segment_s * fs / block)));
  result.num_blocks = static_cast<int>(m);
  if (m < 4 * min_length) return result;
  std::vector<double> means(m), prefix(m + 1, 0.0), prefix_sq(m + 1, 0.0);
  for (long b = 0; b < m; ++b) {
    means[b] = x.segment(b * block, block).mean();
    prefix[b + 1] = prefix[b] + means[b];
    prefix_sq[b + 1] = prefix_sq[b] + means[b] * means[b];
  }
  // Short-run variance of a block mean from first differences, robustly (median of squares over
  // its chi-square(1) value 0.4549, halved for the difference): jumps are a few outliers there.
  std::vector<double> squares(m - 1);
  for (long b = 1; b < m; ++b)
    squares[b - 1] = (means[b] - means[b - 1]) * (means[b] - means[b - 1]);
  const double mean_square =
      std::accumulate(squares.begin(), squares.end(), 0.0) / static_cast<double>(squares.size());
  std::nth_element(squares.begin(), squares.begin() + squares.size() / 2, squares.end());
  double sigma2 = squares[squares.size() / 2] / (2 * 0.4549);
  // Block means on a lattice (the rate of a coarse angle counter: a block's mean is its angle
  // count over the block, and most neighbours share it) have a median difference of zero or of
  // rounding, however much they vary: then the mean square, which the few jumps inflate (a
  // conservative variance), stands in for the median's.
  if (!(sigma2 > 1e-6 * 0.5 * mean_square)) sigma2 = 0.5 * mean_square;
  sigma2 = std::max(sigma2, 1e-300);
  result.short_run_variance = sigma2;
  // The levels are searched with the block means' variance sigma2 lambda, lambda the variance
  // ratio of batch means of lambda_batch_s of the residual left by the levels found so far
  // (fixed point from lambda = 1; header comment): a correlated wander (Gauss-Markov, bias
  // instability) keeps its colour within any segment and raises lambda, white noise around
  // true levels does not.
  double lambda = options.variance_ratio > 0 ? options.variance_ratio : 1.0;
  std::vector<long> changes;
  const long batch =
      std::max(2L, static_cast<long>(std::lround(options.lambda_batch_s * fs / block)));
  Eigen::VectorXd residual(m);
  double used = lambda;  // the lambda of `changes`
  for (int iteration = 0; iteration < options.lambda_iterations; ++iteration) {
    used = lambda;
    result.penalty = options.penalty_per_step * std::log(m / lambda);
    changes = Pelt(prefix, prefix_sq, m, min_length, sigma2 * lambda, result.penalty);
    long start = 0;
    for (size_t s = 0; s <= changes.size(); ++s) {
      const long stop = s < changes.size() ? changes[s] : m;
      const double level = (prefix[stop] - prefix[start]) / (stop - start);
      for (long b = start; b < stop; ++b) residual[b] = means[b] - level;
      start = stop;
    }
    if (options.variance_ratio > 0) break;
    const double next = BatchMeansVarianceRatio(residual, batch, sigma2);
    if (std::abs(next - lambda) <= 0.05 * lambda) break;
    lambda = next;
  }
  lambda = used;
  result.long_run_variance_ratio = lambda;
  // -2 ln L drop of the steps (profile, known variance sigma2 lambda).
  const double rss0 = prefix_sq[m] - prefix[m] * prefix[m] / m;
  double rss = 0;
  long start = 0;
  for (size_t s = 0; s <= changes.size(); ++s) {
    const long stop = s < changes.size() ? changes[s] : m;
    const double sum = prefix[stop] - prefix[start];
    rss += prefix_sq[stop] - prefix_sq[start] - sum * sum / (stop - start);
    start = stop;
  }
  result.gain = (rss0 - rss) / (sigma2 * lambda);
  // More steps than a dense fit of this record can hold (options.max_design_bytes): none kept,
  // and the segmentation says so.
  if (const long limit = MaxDesignSteps(n, options); static_cast<long>(changes.size()) > limit) {
    result.too_many_steps = static_cast<int>(changes.size());
    result.max_design_steps = limit;
    changes.clear();
    result.gain = 0;
  }
  // Levels beside a random walk (header comment): the steps stand only if they still gain their
  // penalty once a random walk, its variance fitted, is allowed in both models.
  if (!changes.empty()) {
    // `residual` holds the block means less the levels of `changes` (the loop above). Each side
    // is the -2 ln L of a local-level model (Harvey 1989) with the known white noise
    // sigma2 lambda, minimised over the walk's variance q >= 0.
    const auto beside_walk = [&](const Eigen::VectorXd& y) {
      return filters::MinimizeRandomWalkMinusTwoLogLikelihood(y, sigma2 * lambda)
          .minus_two_log_likelihood;
    };
    result.gain_beside_walk =
        beside_walk(Eigen::Map<const Eigen::VectorXd>(means.data(), m)) - beside_walk(residual);
    const double walk_penalty = options.walk_penalty_per_step * std::log(m / lambda);
    const bool keep = result.gain_beside_walk > walk_penalty * static_cast<double>(changes.size());
    if (!keep) {
      changes.clear();
      result.gain = 0;
    }
  }
  // Refine each step to the sample between its neighbours.
  for (size_t s = 0; s < changes.size(); ++s) {
    const long begin = (s == 0 ? 0 : changes[s - 1]) * block;
    const long end = s + 1 < changes.size() ? changes[s + 1] * block : n;
    const long lo = std::max(begin + 1, (changes[s] - 1) * block);
    const long hi = std::min(end - 1, (changes[s] + 1) * block);
    result.step_index.push_back(RefineStep(x, begin, end, lo, hi));
  }
  return result;
}

LevelsReading DescribeLevels(const std::vector<double>& levels,
                             const std::vector<double>& levels_se, double record_s) {
  LevelsReading reading;
  const size_t count = levels.size();
  reading.num_levels = static_cast<int>(count);
  if (count < 2) return reading;
  reading.mean_dwell_s = record_s / static_cast<double>(count);
  reading.gm_correlation_time_s = 0.5 * reading.mean_dwell_s;
  std::vector<double> sorted = levels;
  std::sort(sorted.begin(), sorted.end());
  size_t gap_at = 1;
  for (size_t i = 1; i < count; ++i)
    if (sorted[i] - sorted[i - 1] > sorted[gap_at] - sorted[gap_at - 1]) gap_at = i;
  const double threshold = 0.5 * (sorted[gap_at] + sorted[gap_at - 1]);
  double high = 0, low = 0;
  int num_high = 0, num_low = 0;
  for (double level : levels)
    (level > threshold ? (high += level, ++num_high) : (low += level, ++num_low));
  high /= std::max(num_high, 1);
  low /= std::max(num_low, 1);
  const double separation = high - low;
  bool two_level = num_high > 0 && num_low > 0;
  for (size_t i = 0; i < count && two_level; ++i) {
    const double centre = levels[i] > threshold ? high : low;
    const double se = i < levels_se.size() ? levels_se[i] : 0.0;
    two_level = std::abs(levels[i] - centre) <= 3.0 * se + 0.1 * separation;
    if (i > 0) two_level = two_level && ((levels[i] > threshold) != (levels[i - 1] > threshold));
  }
  char text[400];
  if (two_level && count >= 6) {
    reading.telegraph_like = true;
    reading.num_levels = 2;
    reading.half_separation_rad_s = 0.5 * separation;
    std::snprintf(text, sizeof(text),
                  "two alternating levels %.3g deg/h apart, %zu dwells of mean %.4g s: random "
                  "telegraph switching (the Gauss-Markov term of the same spectrum would be sigma "
                  "%.3g deg/h, Tc %.4g s)",
                  units::RadPerSecondToDegPerHour(separation), count, reading.mean_dwell_s,
                  units::RadPerSecondToDegPerHour(reading.half_separation_rad_s),
                  reading.gm_correlation_time_s);
  } else if (two_level) {
    reading.num_levels = 2;
    std::snprintf(text, sizeof(text),
                  "two alternating levels %.3g deg/h apart, but only %zu dwells (mean %.4g s): "
                  "too few switches to call it a random telegraph process",
                  units::RadPerSecondToDegPerHour(separation), count, reading.mean_dwell_s);
  } else {
    std::snprintf(text, sizeof(text),
                  "%zu levels, mean dwell %.4g s: not two alternating levels (not a random "
                  "telegraph process)",
                  count, reading.mean_dwell_s);
  }
  reading.text = text;
  return reading;
}

}  // namespace fogpipe::model
