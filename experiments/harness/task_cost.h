// Per-task cost across thread counts: for every point of a sweep that was also run at
// 1 thread (same scene and options but `threads`), the median CPU time per task
// (RunTotals::task_cpu_ns) at each P > 1 against the median at 1. A ratio well above 1
// means P refiners do more work per task than one (data passed between cores, false
// sharing, a core shared by two threads), so speed-ups measure that, not the
// algorithm; the experiment summary warns above kTaskCostWarnRatio.
#pragma once

#include "core/config/options.h"

#include <map>
#include <string>
#include <vector>

namespace hrad::experiment {

inline constexpr double kTaskCostWarnRatio = 1.2;

class TaskCostTable {
 public:
  /// One finished run of `scene` with `options` (threads included) and its cost.
  void add(const std::string& scene, const SolverOptions& options, double task_cpu_ns);
  /// "builtin:office blocked ... : CPU per task at 2 threads is 1.27x that at 1
  /// thread (835 vs 658 ns, medians)", one line for each ratio above `ratio`.
  [[nodiscard]] std::vector<std::string> warnings(double ratio = kTaskCostWarnRatio) const;

 private:
  struct Point {
    std::string scene;
    SolverOptions options;                          ///< with threads = 1
    std::map<int, std::vector<double>> by_threads;  ///< threads -> CPU ns per task
  };
  // key: scene and every option but threads (as JSON)
  std::map<std::string, Point> points_;
};

}  // namespace hrad::experiment
