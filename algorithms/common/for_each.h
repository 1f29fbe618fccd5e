// The parallel-loop hook of the algorithms: algorithms/ has no threads of its own (Eigen only), so
// the stages that can run work concurrently (EMD's envelope pass, the method's components and
// Allan tables, the sweep's orders, compare's trials) take a ForEach. The pipeline passes
// graph::TbbForEach (a tbb::parallel_for); an empty or serial one runs everything in order.
#pragma once

#include <functional>

namespace fogpipe {

/// Runs body(i) for every i in [0, n), possibly concurrently. Callers make every body write only
/// its own slot, so their results do not depend on the schedule.
using ForEach = std::function<void(int n, const std::function<void(int)>& body)>;

}  // namespace fogpipe
