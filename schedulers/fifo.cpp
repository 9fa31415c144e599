// `fifo`: a central first-in first-out pool under one lock: breadth-first
// refinement, the largest working set of the central schedulers.
//
// | parameter  | type | default | meaning                          |
// |------------|------|---------|----------------------------------|
// | block_size | int  | 0       | tasks per take(); 0: guided      |
#include "schedulers/central_pool.h"

#include <deque>

namespace hrad {
namespace {

struct FifoTasks {
  std::deque<Task> q;
  void push(const Task& t) { q.push_back(t); }
  Task pop() {
    Task t = q.front();
    q.pop_front();
    return t;
  }
  [[nodiscard]] bool empty() const { return q.empty(); }
};

const bool registered =
    register_scheduler("fifo", [](const SchedulerConfig& c, const PluginParams&) {
      return std::make_unique<CentralPool<FifoTasks>>(c, "fifo");
    });

}  // namespace
}  // namespace hrad
