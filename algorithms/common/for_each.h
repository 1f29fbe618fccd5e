// The parallel-loop hook of the algorithms: algorithms/ has no threads of its own (Eigen only), so
// the stages that can run work concurrently (EMD's envelope pass, the method's components and
// Allan tables, the sweep's orders, compare's trials) take a ForEach. The pipeline passes
// graph::TbbForEach (a tbb::parallel_for); an empty or serial one runs everything in order.
#pragma once

#include <algorithm>
#include <functional>

namespace fogpipe {

/// Runs body(i) for every i in [0, n), possibly concurrently. Callers make every body write only
/// its own slot, so their results do not depend on the schedule.
using ForEach = std::function<void(int n, const std::function<void(int)>& body)>;

/// How many contiguous parts a pass over n samples is cut into to run through for_each (the EMD's
/// sifts, the preprocessing): at most 16, of at least 65536 samples each (512 KiB of doubles, far
/// more work than scheduling a task); 1 when for_each is empty or n is below two parts' worth.
inline int PartsForPass(long long n, const ForEach& for_each) {
  constexpr long long kMinPartSamples = 1 << 16;
  constexpr long long kMaxParts = 16;
  if (!for_each) return 1;
  return static_cast<int>(std::clamp(n / kMinPartSamples, 1LL, kMaxParts));
}

}  // namespace fogpipe
