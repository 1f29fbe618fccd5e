// The method::ForEach that the pipeline hands to algorithms/method: a oneTBB parallel loop.
// algorithms/ stays single-threaded; the pipeline decides how its per-component work runs.
#pragma once

#include <functional>
#include <memory>

#include "algorithms/common/task_group.h"

namespace fogpipe::graph {

/// Runs body(0) .. body(n - 1) on the TBB pool, one index per task (simple_partitioner: the
/// bodies are few and long). Each body must write only its own slot, so the result does not
/// depend on the schedule or the thread count.
void TbbForEach(int n, const std::function<void(int)>& body);

/// A fogpipe::TaskGroup on the TBB pool (tbb::task_group); waits for its tasks when destroyed.
std::unique_ptr<TaskGroup> MakeTbbTaskGroup();

}  // namespace fogpipe::graph
