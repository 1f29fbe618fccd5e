#include "pipeline/graph/tbb_for_each.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>

namespace fogpipe::graph {

void TbbForEach(int n, const std::function<void(int)>& body) {
  tbb::parallel_for(
      tbb::blocked_range<int>(0, n, 1),
      [&](const tbb::blocked_range<int>& r) {
        for (int i = r.begin(); i != r.end(); ++i) body(i);
      },
      tbb::simple_partitioner());
}

}  // namespace fogpipe::graph
