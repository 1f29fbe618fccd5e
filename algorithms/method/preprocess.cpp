#include "algorithms/method/preprocess.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

namespace fogpipe::method {
namespace {

// 1 / Phi^-1(3/4): scales the MAD to the standard deviation of Gaussian noise.
constexpr double kMadToSigma = 1.482602218505602;

double MedianInPlace(std::vector<double>* values) {
  const std::size_t n = values->size();
  auto mid = values->begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(values->begin(), mid, values->end());
  const double upper = *mid;
  if (n % 2 == 1) return upper;
  const double lower = *std::max_element(values->begin(), mid);
  return 0.5 * (lower + upper);
}

/// Moves sorted[pos] to its place among the other, sorted, values.
void Resort(std::vector<double>* sorted, std::size_t pos) {
  std::vector<double>& s = *sorted;
  while (pos > 0 && s[pos - 1] > s[pos]) {
    std::swap(s[pos - 1], s[pos]);
    --pos;
  }
  while (pos + 1 < s.size() && s[pos + 1] < s[pos]) {
    std::swap(s[pos + 1], s[pos]);
    ++pos;
  }
}

/// Runs body(begin, end, part) over `parts` contiguous ranges covering [0, n), through for_each
/// when it is set.
void InParts(Eigen::Index n, int parts, const ForEach& for_each,
             const std::function<void(Eigen::Index, Eigen::Index, int)>& body) {
  auto bound = [&](int p) { return n * p / parts; };
  auto one = [&](int p) { body(bound(p), bound(p + 1), p); };
  if (for_each && parts > 1) {
    for_each(parts, one);
  } else {
    for (int p = 0; p < parts; ++p) one(p);
  }
}

/// median[k] = the median of x over [k - h, k + h] clipped to the record, for k in [begin, end).
/// The full windows are slid: the sample that leaves is replaced by the one that enters in a
/// sorted copy of the window (O(h) per sample instead of a selection over 2 h + 1 values). A
/// median is a value of the window's multiset, however it is found, and the leaving value is
/// matched bit for bit (signed zeros), so the medians equal MedianInPlace's on each window and do
/// not depend on where a range starts (a zero median may differ in its sign, which no comparison
/// of the rule sees).
void LocalMediansOf(const Eigen::VectorXd& x, Eigen::Index h, Eigen::Index begin, Eigen::Index end,
                    Eigen::VectorXd* median) {
  const Eigen::Index n = x.size();
  std::vector<double> window;
  auto clipped = [&](Eigen::Index k) {
    const Eigen::Index lo = std::max<Eigen::Index>(0, k - h);
    const Eigen::Index hi = std::min<Eigen::Index>(n - 1, k + h);
    window.assign(x.data() + lo, x.data() + hi + 1);
    (*median)[k] = MedianInPlace(&window);
  };
  // Full windows are those of k in [h, n - h).
  const Eigen::Index full_begin = std::max(begin, h), full_end = std::min(end, n - h);
  if (full_begin >= full_end) {
    for (Eigen::Index k = begin; k < end; ++k) clipped(k);
    return;
  }
  for (Eigen::Index k = begin; k < full_begin; ++k) clipped(k);
  for (Eigen::Index k = full_end; k < end; ++k) clipped(k);
  const Eigen::Index width = 2 * h + 1;
  std::vector<double> sorted(x.data() + full_begin - h, x.data() + full_begin - h + width);
  std::sort(sorted.begin(), sorted.end());
  (*median)[full_begin] = sorted[static_cast<std::size_t>(h)];
  for (Eigen::Index k = full_begin + 1; k < full_end; ++k) {
    const double leaving = x[k - h - 1];
    auto it = std::lower_bound(sorted.begin(), sorted.end(), leaving);
    while (std::signbit(*it) != std::signbit(leaving)) ++it;  // -0.0 == +0.0 in the ordering
    *it = x[k + h];
    Resort(&sorted, static_cast<std::size_t>(it - sorted.begin()));
    (*median)[k] = sorted[static_cast<std::size_t>(h)];
  }
}

void ReplaceOutliers(const PreprocessOptions& options, long long offset, Eigen::VectorXd* x,
                     std::vector<long long>* indices) {
  const Eigen::Index n = x->size();
  // Local medians of the original values (replacements are written afterwards, so the result does
  // not depend on the scan order).
  Eigen::VectorXd median(n);
  const Eigen::Index h = options.hampel_half_window;
  const int parts = PartsForPass(n, options.for_each);
  InParts(n, parts, options.for_each, [&](Eigen::Index begin, Eigen::Index end, int) {
    LocalMediansOf(*x, h, begin, end, &median);
  });
  // The scale blocks start at multiples of `block`; the last one absorbs a tail shorter than half
  // a block so that no scale rests on a handful of samples: there are as many blocks as the
  // fewest m with m block > n - block / 2. Each part takes a contiguous run of whole blocks.
  const Eigen::Index block = options.hampel_scale_block;
  const Eigen::Index num_blocks = std::max<Eigen::Index>(1, (n - block / 2 + block) / block);
  const int block_parts = static_cast<int>(std::min<Eigen::Index>(parts, num_blocks));
  std::vector<std::vector<long long>> found(static_cast<std::size_t>(block_parts));
  InParts(num_blocks, block_parts, options.for_each,
          [&](Eigen::Index first, Eigen::Index last, int part) {
            std::vector<double> deviation;
            for (Eigen::Index b = first; b < last; ++b) {
              const Eigen::Index start = b * block;
              const Eigen::Index end = b + 1 == num_blocks ? n : start + block;
              deviation.resize(static_cast<std::size_t>(end - start));
              for (Eigen::Index k = start; k < end; ++k)
                deviation[k - start] = std::abs((*x)[k] - median[k]);
              const double limit =
                  options.hampel_threshold * kMadToSigma * MedianInPlace(&deviation);
              for (Eigen::Index k = start; k < end; ++k) {
                if (limit > 0.0 && std::abs((*x)[k] - median[k]) > limit) {
                  (*x)[k] = median[k];
                  found[part].push_back(k + offset);
                }
              }
            }
          });
  for (const std::vector<long long>& f : found) indices->insert(indices->end(), f.begin(), f.end());
}

}  // namespace

bool PreprocessOptions::IsValid(std::string* error) const {
  auto fail = [error](const char* text) {
    if (error) *error = text;
    return false;
  };
  if (!(drop_start_s >= 0.0)) return fail("drop_start_s must be >= 0");
  if (hampel_half_window < 1) return fail("hampel_half_window must be >= 1");
  if (hampel_scale_block < 10) return fail("hampel_scale_block must be >= 10");
  if (!(hampel_threshold > 0.0)) return fail("hampel_threshold must be > 0");
  if (!std::isfinite(window_s)) return fail("window_s must be finite");
  if (min_samples < 8) return fail("min_samples must be >= 8");
  return true;
}

std::string PreprocessingNote(long long dropped_samples, long long outliers) {
  return "raw = the preprocessed signal (" + std::to_string(dropped_samples) +
         " samples dropped at the start, " + std::to_string(outliers) +
         " outliers replaced by the local median, mean removed); `fogpipe allan` analyses the "
         "recording as stored, so its terms differ by this preprocessing";
}

Preprocessed Preprocess(const Eigen::VectorXd& x, double sample_rate_hz,
                        const PreprocessOptions& options) {
  Preprocessed out;
  std::string error;
  if (!options.IsValid(&error)) {
    out.summary.message = error;
    return out;
  }
  if (!(sample_rate_hz > 0.0) || !std::isfinite(sample_rate_hz)) {
    out.summary.message = "sample rate must be finite and > 0";
    return out;
  }
  const long long drop = std::llround(options.drop_start_s * sample_rate_hz);
  const long long kept = static_cast<long long>(x.size()) - drop;
  if (kept < options.min_samples) {
    std::ostringstream message;
    message << "too few samples: " << x.size() << " recorded, " << drop << " dropped at the start, "
            << std::max(0LL, kept) << " left, at least " << options.min_samples << " needed";
    out.summary.termination = Termination::kInsufficientData;
    out.summary.message = message.str();
    return out;
  }
  out.summary.dropped_samples = drop;
  Eigen::VectorXd y = x.tail(kept);
  if (!y.allFinite()) {
    out.summary.termination = Termination::kNumericalFailure;
    Eigen::Index k = 0;
    while (std::isfinite(y[k])) ++k;
    out.summary.message = "non-finite sample (NaN or Inf) at index " + std::to_string(k + drop);
    return out;
  }
  {
    std::ostringstream rule;
    rule << "hampel: |x - median of " << (2 * options.hampel_half_window + 1)
         << " centred samples| > " << options.hampel_threshold << " * 1.4826 * median |x - median| "
         << "over blocks of " << options.hampel_scale_block << " samples; replaced by the median";
    out.outlier_rule = options.remove_outliers ? rule.str() : "none";
  }
  if (options.remove_outliers) ReplaceOutliers(options, drop, &y, &out.outlier_indices);
  out.summary.outliers = static_cast<long long>(out.outlier_indices.size());

  // Stationarity check on non-overlapping windows (Fig. 2 of the paper).
  long long window =
      options.window_s > 0.0 ? std::llround(options.window_s * sample_rate_hz) : kept / 20;
  window = std::clamp<long long>(window, 1, kept);
  const long long windows = kept / window;
  out.window_samples = window;
  out.window_mean.resize(windows);
  out.window_variance.resize(windows);
  for (long long w = 0; w < windows; ++w) {
    const auto segment = y.segment(w * window, window);
    const double mean = segment.mean();
    out.window_mean[w] = mean;
    out.window_variance[w] = (segment.array() - mean).square().mean();
  }

  // Constant before the mean is removed: the test is exact (a mean-removed constant can keep
  // rounding-level values that look like noise).
  if (y.maxCoeff() == y.minCoeff()) {
    out.summary.termination = Termination::kNumericalFailure;
    out.summary.message = "constant signal: every kept sample is the same, nothing to analyse";
    return out;
  }
  out.mean_removed = y.mean();
  y.array() -= out.mean_removed;
  out.signal = std::move(y);
  out.summary.termination = Termination::kSuccess;
  return out;
}

}  // namespace fogpipe::method
