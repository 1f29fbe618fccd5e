#include "pipeline/io/missing_samples.h"

#include <cmath>

namespace fogpipe::io {

bool BridgeNanRuns(Eigen::Ref<Eigen::VectorXd> x, long long max_gap, BridgeReport* report) {
  BridgeReport r;
  const long long n = x.size();
  bool all_bridged = true;
  long long i = 0;
  while (i < n) {
    if (std::isinf(x[i])) {
      if (r.infinite_samples++ == 0) r.first_infinite_index = i;
      ++i;
      continue;
    }
    if (!std::isnan(x[i])) {
      ++i;
      continue;
    }
    const long long start = i;
    while (i < n && std::isnan(x[i])) ++i;
    const long long length = i - start;
    ++r.runs;
    if (length > r.longest_run) {
      r.longest_run = length;
      r.longest_run_start = start;
    }
    const bool has_left = start > 0 && std::isfinite(x[start - 1]);
    const bool has_right = i < n && std::isfinite(x[i]);
    if (length > max_gap || (!has_left && !has_right)) {
      all_bridged = false;
      continue;
    }
    for (long long k = start; k < i; ++k) {
      if (has_left && has_right) {
        const double t = static_cast<double>(k - start + 1) / static_cast<double>(length + 1);
        x[k] = x[start - 1] + t * (x[i] - x[start - 1]);
      } else {
        x[k] = has_left ? x[start - 1] : x[i];
      }
    }
    r.bridged_samples += length;
  }
  if (report) *report = r;
  return all_bridged && r.infinite_samples == 0;
}

}  // namespace fogpipe::io
