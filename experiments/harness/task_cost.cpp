#include "experiments/harness/task_cost.h"

#include "core/base/median.h"
#include "core/config/options_io.h"

#include <fmt/format.h>

namespace hrad::experiment {

void TaskCostTable::add(const std::string& scene, const SolverOptions& options,
                        double task_cpu_ns) {
  if (!(task_cpu_ns > 0)) return;
  SolverOptions one = options;
  one.threads = 1;
  Point& p = points_[scene + " " + options_to_json(one).dump()];
  p.scene = scene;
  p.options = one;
  p.by_threads[options.threads].push_back(task_cpu_ns);
}

std::vector<std::string> TaskCostTable::warnings(double ratio) const {
  std::vector<std::string> out;
  for (const auto& [key, p] : points_) {
    const auto one = p.by_threads.find(1);
    if (one == p.by_threads.end()) continue;
    const double base = median(one->second);
    for (const auto& [threads, v] : p.by_threads) {
      if (threads == 1) continue;
      const double m = median(v);
      if (m > ratio * base)
        out.push_back(fmt::format(
            "{} ({} block {}): CPU per task at {} threads is {:.2f}x that at 1 thread ({:.0f} vs "
            "{:.0f} ns, medians): the speed-up includes that extra work",
            p.scene, p.options.scheduler, p.options.block_size, threads, m / base, m, base));
    }
  }
  return out;
}

}  // namespace hrad::experiment
