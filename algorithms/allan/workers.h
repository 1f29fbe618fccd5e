// Index-by-index work sharing for the allan kernels (internal to algorithms/allan): algorithms/ has
// no thread pool of its own (common/for_each.h), so the passes that AllanOptions::threads splits
// start their own threads, as few as the work allows.
#pragma once

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace fogpipe::allan::internal {

/// Runs body(i) for every i in [0, count) on up to `threads` threads (the caller's among them),
/// each taking the next index in turn; one thread runs them in order. Bodies write only their own
/// results, so the results do not depend on the schedule.
template <typename Body>
void ShareAmongThreads(int threads, long long count, const Body& body) {
  const long long workers = std::min<long long>(std::max(threads, 1), count);
  if (workers <= 1) {
    for (long long i = 0; i < count; ++i) body(i);
    return;
  }
  std::atomic<long long> next{0};
  auto work = [&] {
    for (long long i = next++; i < count; i = next++) body(i);
  };
  std::vector<std::thread> pool;
  for (long long t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

}  // namespace fogpipe::allan::internal
