// `stack`: a central LIFO pool under one lock. Depth-first like the recursive
// refinement of classic hierarchical radiosity, so its working set stays small.
//
// | parameter  | type | default | meaning                          |
// |------------|------|---------|----------------------------------|
// | block_size | int  | 0       | tasks per take(); 0: guided      |
#include "schedulers/central_pool.h"

#include <vector>

namespace hrad {
namespace {

struct LifoTasks {
  std::vector<Task> v;
  void push(const Task& t) { v.push_back(t); }
  Task pop() {
    Task t = v.back();
    v.pop_back();
    return t;
  }
  [[nodiscard]] bool empty() const { return v.empty(); }
};

const bool registered =
    register_scheduler("stack", [](const SchedulerConfig& c, const PluginParams&) {
      return std::make_unique<CentralPool<LifoTasks>>(c, "stack");
    });

}  // namespace
}  // namespace hrad
