// NUMA report: what a run's placement study reads in stats.json — each refiner's
// planned node and PUs and whether the binding was applied, its tasks whose
// receiver lived on its own node versus another (Element::home_node, counted from
// the arenas), the iteration's local-access ratio, and element and link bytes per
// node; plus the warnings a placement deserves (a plan that wraps around, bindings
// that failed or were only planned on a synthetic topology).
#pragma once

#include "core/config/options.h"
#include "core/hierarchy/hierarchy.h"
#include "core/output/run_stats.h"
#include "core/parallel/pin_plan.h"
#include "core/solver/refiner.h"

#include <string>
#include <vector>

namespace hrad {

/// Warnings about the plan and the arenas' memory binding, once per run.
void add_placement_warnings(const PinPlan& plan, const TopologyInfo& topology,
                            const Hierarchy& hierarchy, const SolverOptions& options,
                            std::vector<std::string>& warnings);

/// Pages per arena whose node the placement check asks the OS for.
inline constexpr std::size_t kPlacementCheckPages = 32;

/// Fills the NUMA fields of `is` (its refiners must already be there, one per
/// worker of `rc.per_worker`); adds a warning when a refiner's binding failed.
/// On this machine's topology, also checks up to kPlacementCheckPages pages of every
/// arena against the OS (hwloc_get_area_memlocation, through `topology`) and warns
/// when a page is not on the node the arena counts it on: then the local and remote
/// counts, which come from the arenas' bookkeeping, are estimates.
void record_numa_stats(IterationStats& is, const RefineCounters& rc, const PinPlan& plan,
                       const Hierarchy& hierarchy, const Topology& topology,
                       std::vector<std::string>& warnings);

}  // namespace hrad
