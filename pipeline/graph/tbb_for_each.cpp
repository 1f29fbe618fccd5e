#include "pipeline/graph/tbb_for_each.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_group.h>

#include <utility>

namespace fogpipe::graph {

void TbbForEach(int n, const std::function<void(int)>& body) {
  tbb::parallel_for(
      tbb::blocked_range<int>(0, n, 1),
      [&](const tbb::blocked_range<int>& r) {
        for (int i = r.begin(); i != r.end(); ++i) body(i);
      },
      tbb::simple_partitioner());
}

namespace {

class TbbTaskGroup : public TaskGroup {
 public:
  // Waited for here, so that destroying the tbb::task_group (whose destructor may throw when
  // tasks are still running) cannot throw.
  ~TbbTaskGroup() override {
    try {
      group_->wait();
    } catch (...) {
    }
  }
  void Run(std::function<void()> task) override { group_->run(std::move(task)); }
  void Wait() override { group_->wait(); }

 private:
  // Isolated: a group is often first used from a task of another group (the streamed EMD's chain
  // starts the next component's task in that component's group), and a bound context would make
  // it that group's child, so that a cancellation there would skip tasks here and the groups'
  // destruction order would matter. Each group's failure is its own and rethrown by its Wait.
  tbb::task_group_context context_{
      tbb::task_group_context::isolated,
      tbb::task_group_context::default_traits | tbb::task_group_context::concurrent_wait};
  std::unique_ptr<tbb::task_group> group_ = std::make_unique<tbb::task_group>(context_);
};

}  // namespace

std::unique_ptr<TaskGroup> MakeTbbTaskGroup() { return std::make_unique<TbbTaskGroup>(); }

}  // namespace fogpipe::graph
