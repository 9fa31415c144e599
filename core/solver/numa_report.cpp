#include "core/solver/numa_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hrad {
namespace {
void add_once(std::vector<std::string>& warnings, std::string w) {
  if (std::find(warnings.begin(), warnings.end(), w) == warnings.end())
    warnings.push_back(std::move(w));
}
}  // namespace

void add_placement_warnings(const PinPlan& plan, const TopologyInfo& topology,
                            const Hierarchy& hierarchy, const SolverOptions& options,
                            std::vector<std::string>& warnings) {
  if (plan.wrapped)
    add_once(warnings, fmt::format("pin {}: {} refiners but {} PUs: the plan wraps around and "
                                   "some refiners share a PU",
                                   options.pin, options.threads, topology.pus));
  else if (!topology.synthetic && topology.pus > 0 && options.threads > topology.pus)
    add_once(warnings, fmt::format("threads = {} on a machine with {} PUs: refiners share PUs, "
                                   "so times and speed-ups measure the sharing",
                                   options.threads, topology.pus));
  if (topology.synthetic && plan.policy != PinPolicy::None)
    add_once(warnings, fmt::format("pin {}: the topology is not this machine's ({}): bindings "
                                   "are planned and reported, not applied",
                                   options.pin, topology.description));
  const BindOutcome b = hierarchy.arena(0).binding();
  std::string why;
  if (hierarchy.arena(0).bind_failures(&why) > 0)
    add_once(warnings, fmt::format("placement {}: memory binding failed ({}); pages stay where "
                                   "they are first touched",
                                   options.placement, why));
  else if (b == BindOutcome::Planned)
    add_once(warnings, fmt::format("placement {}: the topology is not this machine's: memory "
                                   "binding is planned and counted, not applied",
                                   options.placement));
}

void record_numa_stats(IterationStats& is, const RefineCounters& rc, const PinPlan& plan,
                       const Hierarchy& hierarchy, const Topology& topology,
                       std::vector<std::string>& warnings) {
  std::uint64_t local = 0, remote = 0;
  for (std::size_t w = 0; w < rc.per_worker.size() && w < is.refiners.size(); ++w) {
    const RefineCounters& c = rc.per_worker[w];
    RefinerStats& r = is.refiners[w];
    if (w < plan.refiners.size()) {
      r.node = plan.refiners[w].node;
      r.pus = format_pu_list(plan.refiners[w].pus);
    }
    r.bound = c.bound;
    r.tasks_local = c.tasks_local;
    r.tasks_remote = c.tasks_remote;
    local += c.tasks_local;
    remote += c.tasks_remote;
    if (!c.bind_warning.empty())
      add_once(warnings, fmt::format("pin: refiner {}: {}", w, c.bind_warning));
  }
  is.local_access_ratio = local + remote > 0
                              ? static_cast<double>(local) / static_cast<double>(local + remote)
                              : std::numeric_limits<double>::quiet_NaN();
  is.element_bytes_per_node = hierarchy.element_bytes_per_node();
  is.link_bytes_per_node = hierarchy.link_bytes_per_node();
  is.bytes_per_node = is.element_bytes_per_node;
  add_bytes_per_node(is.bytes_per_node, is.link_bytes_per_node);

  if (topology.info().synthetic) return;  // the pages are not on that machine's nodes
  IterationStats::PlacementCheck& pc = is.placement_check;
  pc.checked = true;
  for (const auto& [page, node] : hierarchy.sample_pages(kPlacementCheckPages)) {
    ++pc.pages;
    const int os = topology.node_of_address(page);
    if (os < 0)
      ++pc.unknown;
    else if (os == node)
      ++pc.agree;
  }
  if (pc.agree + pc.unknown < pc.pages)
    add_once(warnings, fmt::format("placement: the OS has some arena pages on another node than "
                                   "the arenas count them on ({} of {} sampled pages in "
                                   "iteration {}); local and remote task counts are estimates",
                                   pc.pages - pc.agree - pc.unknown, pc.pages, is.iteration));
}

}  // namespace hrad
