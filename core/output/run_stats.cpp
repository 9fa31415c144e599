#include "core/output/run_stats.h"

#include "core/base/interrupt.h"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>

#include <algorithm>
#include <cmath>

namespace hrad {

std::uint64_t peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<std::uint64_t>(u.ru_maxrss) * 1024u;  // Linux reports KiB
}

std::uint64_t current_rss_bytes() { return resident_bytes(); }

IterationTotals sum_iterations(const std::vector<IterationStats>& iterations) {
  IterationTotals t;
  std::uint64_t local = 0, located = 0;
  for (const IterationStats& it : iterations) {
    t.refine_wall_s += it.refine_wall_s;
    t.refine_cpu_s += it.refine_cpu_s;
    t.refine_thread_cpu_s += it.refine_thread_cpu_s;
    t.propagate_wall_s += it.propagate_wall_s;
    t.prepare_s += it.prepare_s;
    t.open_s += it.open_s;
    t.push_weights_s += it.push_weights_s;
    t.row_sums_s += it.row_sums_s;
    t.sweeps_s += it.sweeps_s;
    t.load_s += it.load_s;
    t.link_compact_s += it.link_compact_s;
    t.stage_start_s += it.stage_start_s;
    t.stage_end_s += it.stage_end_s;
    t.idle_s += it.idle_s;
    for (const auto& [cls, s] : it.lock_wait_s) t.lock_wait_s[cls] += s;
    t.tasks += it.tasks;
    t.links_created += it.links_created;
    t.scheduler_ops += it.scheduler_ops;
    t.steals += it.steals;
    t.rays_cast += it.rays_cast;
    t.rays_skipped += it.rays_skipped;
    t.peak_parallelism = std::max(t.peak_parallelism, it.peak_parallelism);
    t.gather_sweeps += it.gather_sweeps;
    for (const RefinerStats& rs : it.refiners) {
      local += rs.tasks_local;
      located += rs.tasks_local + rs.tasks_remote;
    }
  }
  t.local_access_ratio =
      located == 0 ? std::nan("") : static_cast<double>(local) / static_cast<double>(located);
  t.task_cpu_ns = t.tasks > 0 ? 1e9 * t.refine_thread_cpu_s / static_cast<double>(t.tasks) : 0.0;
  if (!iterations.empty()) {
    t.links = iterations.back().links;
    t.elements = iterations.back().elements;
    t.bytes = iterations.back().bytes;
  }
  return t;
}

std::string descheduled_refiner_warning(const IterationStats& is) {
  if (is.refiners.size() < 2) return "";
  for (std::size_t i = 0; i < is.refiners.size(); ++i) {
    const RefinerStats& r = is.refiners[i];
    if (r.busy_s > 0.05 && r.cpu_s < 0.8 * r.busy_s)
      return fmt::format(
          "iteration {}: refiner {} ran on a CPU for {:.0f}% of the time it was refining "
          "({:.3f} of {:.3f} s): threads waited for a core (more runnable threads than "
          "cores?), so its timings measure the sharing",
          is.iteration, i, 100 * r.cpu_s / r.busy_s, r.cpu_s, r.busy_s);
  }
  return "";
}

}  // namespace hrad
