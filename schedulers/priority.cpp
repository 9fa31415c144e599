// `priority`: a central pool under one lock that hands out the task with the
// largest oracle error first (ties broken by submission order, so runs repeat).
//
// | parameter  | type | default | meaning                          |
// |------------|------|---------|----------------------------------|
// | block_size | int  | 0       | tasks per take(); 0: guided      |
#include "schedulers/central_pool.h"

#include <queue>

namespace hrad {
namespace {

struct Ranked {
  Task task;
  std::uint64_t order;
  bool operator<(const Ranked& o) const {
    if (task.priority != o.task.priority) return task.priority < o.task.priority;
    return order > o.order;  // earlier first among equals
  }
};

struct PriorityTasks {
  std::priority_queue<Ranked> heap;
  std::uint64_t next = 0;
  void push(const Task& t) { heap.push({t, next++}); }
  Task pop() {
    Task t = heap.top().task;
    heap.pop();
    return t;
  }
  [[nodiscard]] bool empty() const { return heap.empty(); }
};

const bool registered =
    register_scheduler("priority", [](const SchedulerConfig& c, const PluginParams&) {
      return std::make_unique<CentralPool<PriorityTasks>>(c, "priority");
    });

}  // namespace
}  // namespace hrad
