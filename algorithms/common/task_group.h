// The task hook of the algorithms, beside ForEach (for_each.h): work started now and waited for
// later, so that a stage can run while the caller goes on (the streamed method fits each IMF's
// AR model while the EMD sifts the next one, method.h). algorithms/ has no threads of its own;
// the pipeline passes tasks on the oneTBB pool (graph::TbbTaskGroups), and without one every
// task runs at once, in the caller.
#pragma once

#include <functional>
#include <memory>

namespace fogpipe {

/// Tasks started with Run() and all finished by Wait(). Callers make every task write only its
/// own slot, so their results do not depend on the schedule.
class TaskGroup {
 public:
  virtual ~TaskGroup() = default;
  /// Starts `task` (possibly at once, in the caller). A running task of the group may start more.
  virtual void Run(std::function<void()> task) = 0;
  /// Returns when every task started so far, and every task they started, has finished;
  /// rethrows the first exception of one.
  virtual void Wait() = 0;
};

/// Makes a task group; empty: SerialTaskGroup.
using TaskGroupFactory = std::function<std::unique_ptr<TaskGroup>()>;

/// Runs every task at Run(), in the caller.
class SerialTaskGroup : public TaskGroup {
 public:
  void Run(std::function<void()> task) override { task(); }
  void Wait() override {}
};

/// factory(), or a SerialTaskGroup when factory is empty.
inline std::unique_ptr<TaskGroup> MakeTaskGroup(const TaskGroupFactory& factory) {
  if (factory) return factory();
  return std::make_unique<SerialTaskGroup>();
}

}  // namespace fogpipe
