// What a run measures, per refinement iteration and in total. Field names are
// the keys of stats.json (see docs/results.md); times in seconds, sizes in
// bytes.
#pragma once

#include "core/config/effects.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace hrad {

/// One refiner's share of an iteration's refinement stage.
struct RefinerStats {
  std::uint64_t tasks = 0;
  std::uint64_t takes = 0;    ///< scheduler take() calls that returned tasks
  std::uint64_t submits = 0;  ///< scheduler submit() calls
  double busy_s = 0;          ///< time spent refining blocks
  double idle_s = 0;          ///< time spent waiting for tasks
  double lock_wait_s = 0;     ///< time waiting on the element and link lock pools
  std::uint64_t rays_cast = 0;
  // NUMA placement (core/parallel/pin_plan.h, core/parallel/node_arena.h):
  int node = 0;                    ///< NUMA node of the refiner's pin plan (0 when unpinned)
  std::string pus;                 ///< PUs it is bound to, "0-3" ("" when unpinned)
  std::string bound = "none";      ///< "none", "applied", "planned" (synthetic topology), "failed"
  std::uint64_t tasks_local = 0;   ///< tasks whose receiver's memory is on `node`
  std::uint64_t tasks_remote = 0;  ///< tasks whose receiver's memory is on another node
  /// CPU time of the refiner's thread over the stage (its own clock): below the
  /// stage's wall time when the thread waited for a core.
  double cpu_s = 0;
  std::uint64_t link_bytes = 0;  ///< bytes of the lists this refiner compacted (its link arena)
};

struct IterationStats {
  int iteration = 0;         ///< 1-based
  double refine_wall_s = 0;  ///< wall time of the refinement stage
  double refine_cpu_s = 0;   ///< busy time summed over refiners (paper, Figure 4)
  /// CPU time of the refiners' threads summed (their own clocks, whole stage).
  double refine_thread_cpu_s = 0;
  /// refine_thread_cpu_s per task, in nanoseconds (0 without tasks): the per-task
  /// cost to compare between thread counts.
  double task_cpu_ns = 0;
  /// Wall time of the propagation: prepare_s + sweeps_s (and the bookkeeping between).
  double propagate_wall_s = 0;
  /// The propagation's preparation: open fractions, push weights and row sums of the
  /// new link set (rays cast for them included).
  double prepare_s = 0;
  /// Parts of prepare_s: the open fractions of the new leaves (in the first iteration
  /// with cluster_members = exposed, the members' exposures too), the push weights, and
  /// the row sums' pass, which builds the gather matrix the sweeps then use.
  double open_s = 0, push_weights_s = 0, row_sums_s = 0;
  double sweeps_s = 0;  ///< the gather and push-pull sweeps
  /// The refinement stage's serial edges: from the stage's start until its last refiner
  /// entered its loop (starting the team, solver and progress threads), and from the
  /// last refiner leaving its loop until the stage returned, less the link compaction.
  double stage_start_s = 0, stage_end_s = 0;
  std::uint64_t links_created = 0;  ///< links created in this iteration (not re-accepted ones)
  std::uint64_t links = 0;          ///< links alive at the end of the iteration
  std::uint64_t elements = 0;       ///< elements (clusters + surfaces) alive at the end
  std::map<std::string, std::uint64_t> bytes;  ///< by structure: "elements", "links", ...
  std::uint64_t peak_rss_bytes = 0;
  std::uint64_t tasks = 0;                    ///< tasks executed by refiners
  std::uint64_t scheduler_ops = 0;            ///< take + submit calls on the scheduler
  std::map<std::string, double> lock_wait_s;  ///< by lock class: "scheduler", "element", "link"
  double idle_s = 0;                          ///< refiner time spent waiting for tasks
  int peak_parallelism = 0;                   ///< most refiners busy at the same moment
  /// Time to build the initial tasks from the previous iteration's links (in
  /// parallel, before the stage; included in refine_wall_s) plus the refiners' time
  /// submitting them to the scheduler.
  double load_s = 0;
  double link_compact_s = 0;           ///< end of the stage: longest refiner's link compaction
  std::uint64_t steals = 0;            ///< tasks taken from another refiner's queue
  std::vector<RefinerStats> refiners;  ///< per refiner, by OpenMP thread number
  /// Bytes by NUMA node as the placement arenas count them (core/parallel/node_arena.h):
  /// elements and links together, and each alone.
  std::vector<std::uint64_t> bytes_per_node;
  std::vector<std::uint64_t> element_bytes_per_node;
  std::vector<std::uint64_t> link_bytes_per_node;
  /// The arenas' bookkeeping checked against the OS (core/solver/numa_report.h): pages
  /// sampled, pages the OS puts on the node the arenas count them on, pages the OS
  /// could not place. Not done (checked false) on a topology that is not this machine's.
  struct PlacementCheck {
    bool checked = false;
    std::uint64_t pages = 0, agree = 0, unknown = 0;
  } placement_check;
  /// Tasks whose receiver was on the refiner's node / all tasks (NaN: no tasks).
  double local_access_ratio = 0;
  std::uint64_t rays_cast = 0;
  std::uint64_t rays_skipped = 0;  ///< visibility queries answered without rays
  /// Links the oracle wanted refined that min_area kept whole (core/solver/refiner.h),
  /// and their share of the accepted links' estimated error.
  std::uint64_t min_area_held = 0;
  double min_area_held_error = 0;
  int gather_sweeps = 0;
  double max_change = 0;  ///< relative radiosity change of the last sweep
  /// The contraction the accelerated sweeps assumed (core/solver/propagation.h); 0 when
  /// every sweep was plain.
  double contraction = 0;
  /// Leaf row sums (total transport gathered, see core/solver/row_sums.h), uncorrected.
  double row_sum_min = 0, row_sum_max = 0, row_sum_mean = 0;
  double row_sum_within_band = 0;       ///< open-area share within 1 +- kRowSumBand
  std::uint64_t row_sum_corrected = 0;  ///< leaves whose gathered irradiance was rescaled
  /// Elements whose rows of the propagation's gather matrix were kept from the last
  /// iteration's (their links and their sources' areas unchanged;
  /// core/solver/propagation.h).
  std::uint64_t gather_rows_kept = 0;
  /// Open fractions (core/transport/open_fraction.h): rays cast for them this iteration (also in
  /// rays_cast) and the open share of the leaves' area (1 - closed in by contacts).
  std::uint64_t open_rays = 0;
  double open_area_fraction = 1;
  /// Cluster members' exposures (core/transport/cluster_exposure.h): rays cast for them
  /// (first iteration only; also in rays_cast) and their area-weighted mean (1 when not
  /// computed).
  std::uint64_t exposure_rays = 0;
  double mean_exposure = 1;
};

/// The figures of a run that come from its iterations: sums, the last iteration's
/// sizes and the largest parallelism. The one place they are summed: the solver's
/// totals (stats.json) and the experiments' runs.csv both take them from here.
struct IterationTotals {
  double refine_wall_s = 0, refine_cpu_s = 0, refine_thread_cpu_s = 0;
  double propagate_wall_s = 0, idle_s = 0;
  double prepare_s = 0, sweeps_s = 0;                     ///< parts of propagate_wall_s
  double open_s = 0, push_weights_s = 0, row_sums_s = 0;  ///< parts of prepare_s
  double load_s = 0, link_compact_s = 0;                  ///< parts of refine_wall_s
  double stage_start_s = 0, stage_end_s = 0;              ///< parts of refine_wall_s
  std::map<std::string, double> lock_wait_s;              ///< by lock class
  std::uint64_t tasks = 0, links_created = 0, scheduler_ops = 0, steals = 0;
  std::uint64_t rays_cast = 0, rays_skipped = 0;
  int peak_parallelism = 0;  ///< the largest of any iteration
  int gather_sweeps = 0;
  /// Tasks whose receiver was on the refiner's node over all tasks placed (NaN: none).
  double local_access_ratio = 0;
  /// refine_thread_cpu_s per task, in nanoseconds (0 without tasks).
  double task_cpu_ns = 0;
  /// The last iteration's: links, elements and bytes by structure (0 / empty: none).
  std::uint64_t links = 0, elements = 0;
  std::map<std::string, std::uint64_t> bytes;
};
IterationTotals sum_iterations(const std::vector<IterationStats>& iterations);

/// A run's totals: what comes from its iterations (sum_iterations, so summed in one
/// place) and what only the run knows.
struct RunTotals : IterationTotals {
  double wall_s = 0;
  /// Before the iterations (not in wall_s): the solver's setup (topology, ray scene,
  /// hierarchy, effects), and, when the caller reports it, the scene's loading.
  double setup_s = 0;
  double scene_load_s = 0;
  std::uint64_t peak_rss_bytes = 0;
  int iterations_run = 0;  ///< refinement iterations run (fewer than asked when stopped early)
};

struct RunStats {
  std::vector<IterationStats> iterations;
  RunTotals totals;
  std::vector<std::string> warnings;
  Effects effects;  ///< what the scene needed and what was skipped (core/config/effects.h)
};

/// Peak resident set size of this process so far (from getrusage), in bytes.
std::uint64_t peak_rss_bytes();
/// Resident set size of this process now (/proc/self/statm), in bytes; 0 when unknown.
std::uint64_t current_rss_bytes();

/// The memory a phase of a run took, for checks against max_memory_gb: construct before
/// the phase, call grown() after it. The growth of the resident set, or, when the phase
/// raised the process's peak (a transient, freed again), the peak over the resident set
/// at the start. Growth only: what other runs of the same process hold is not counted.
class MemoryGrowth {
 public:
  MemoryGrowth() : rss_(current_rss_bytes()), peak_(peak_rss_bytes()) {}
  [[nodiscard]] std::uint64_t grown() const {
    const std::uint64_t now = current_rss_bytes(), peak = peak_rss_bytes();
    std::uint64_t g = now > rss_ ? now - rss_ : 0;
    if (peak > peak_ && peak > rss_) g = std::max(g, peak - rss_);
    return g;
  }

 private:
  std::uint64_t rss_, peak_;
};

/// "" or a warning that a refiner of this stage waited for a core while it had work:
/// its thread's CPU time over the stage (cpu_s) is below 80% of the wall time it spent
/// refining blocks (busy_s; idle time does not count, an idle refiner sleeps). Then
/// more threads were runnable than cores (other processes, or a CPU set that puts two
/// refiners on one core), and its timings measure that sharing. Only for runs of two
/// or more refiners, and refiners busy 50 ms or more.
std::string descheduled_refiner_warning(const IterationStats& is);

}  // namespace hrad
