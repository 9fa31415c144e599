#include "experiments/harness/task_cost.h"

#include "core/options_io.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>

namespace hrad::experiment {

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
}  // namespace

void TaskCostTable::add(const std::string& scene, const SolverOptions& options, double task_cpu_ns) {
  if (!(task_cpu_ns > 0)) return;
  SolverOptions key = options;
  key.threads = 1;
  costs_[scene + " " + options_to_json(key).dump()][options.threads].push_back(task_cpu_ns);
}

std::vector<std::string> TaskCostTable::warnings(double ratio) const {
  std::vector<std::string> out;
  for (const auto& [key, by_threads] : costs_) {
    const auto one = by_threads.find(1);
    if (one == by_threads.end()) continue;
    const double base = median(one->second);
    const std::string scene = key.substr(0, key.find(' '));
    const nlohmann::json o = nlohmann::json::parse(key.substr(key.find(' ') + 1));
    for (const auto& [threads, v] : by_threads) {
      if (threads == 1) continue;
      const double m = median(v);
      if (m > ratio * base)
        out.push_back(fmt::format(
            "{} ({} block {}): CPU per task at {} threads is {:.2f}x that at 1 thread ({:.0f} vs "
            "{:.0f} ns, medians): the speed-up includes that extra work",
            scene, o.value("scheduler", std::string("?")), o.value("block_size", 0), threads,
            m / base, m, base));
    }
  }
  return out;
}

}  // namespace hrad::experiment
