// Refiner: the refinement rule of one iteration, run as a stage body by the stage
// driver (core/stage/run_stage.h, which owns the team of refiners, termination,
// accounting, tracing and pinning). For each candidate link the rule classifies and
// estimates the pair, asks the oracle, and either accepts the link (stored at its
// receiver after the block) or replaces it by tasks to or from the children of the
// element to refine. When every refiner is done, each compacts the link lists it
// started.
#pragma once

#include "core/base/uninitialized_allocator.h"
#include "core/hierarchy/element.h"
#include "core/parallel/lock_pool.h"
#include "core/parallel/pin_plan.h"
#include "core/parallel/trace.h"
#include "core/stage/run_stage.h"
#include "core/transport/transport.h"
#include "oracles/oracle.h"
#include "schedulers/scheduler.h"

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace hrad {

class Hierarchy;

/// How many levels below its input polygon the oracle may refine a surface whatever
/// min_area says, once the solver has seen min_area stop it (RefineLimits::oracle_levels):
/// 256 pieces of a quadrilateral.
inline constexpr int kOracleLevels = 4;

struct RefineLimits {
  double eps_power = 0;  ///< oracle threshold in power units
  /// Absolute: surfaces smaller than this are not split, but for the oracle's requests
  /// on surfaces less than oracle_levels below their input polygon.
  double min_area = 0;
  /// The stage stops (RefineCounters::over_memory) when the refiners' element and link
  /// arenas hold more than this many bytes; 0: no limit.
  std::uint64_t max_bytes = 0;
  /// Emitted power over total area: what a receiver's irradiance is compared with
  /// (OracleThresholds::mean_irradiance); 0: thresholds are not scaled.
  double mean_irradiance = 0;
  /// Where the oracle's decision on a link with a cluster end depended on its
  /// visibility estimate (it would decide otherwise at V = 0, 1/2 or 1), an accepted
  /// link's visibility is estimated again from rays independent of the ones decided on
  /// (decision_rays = independent; a surface pair always is). With shared rays the
  /// accepted links are those whose rays happened to find the pair more open, and their
  /// estimates are biased high; the link set is the same either way, since the decision
  /// always reads the first rays.
  bool independent_estimates = false;
  /// min_area is a share of the whole scene's area; where most of it lies elsewhere (a
  /// room beside a 200 x 200 ground plane: min_area 4 units^2, each wall 1), it kept a
  /// part of the scene from being refined at all. The solver sets kOracleLevels here
  /// after an iteration in which min_area stopped a noticeable share of what the oracle
  /// asked for (RefineCounters::held_error); 0 until then: min_area holds everywhere.
  int oracle_levels = 0;
  /// Rays of a decision that depends on the visibility estimate (the oracles weigh an
  /// occluded link with a cluster end more): 4 rays found a partly hidden pair wholly
  /// open too often, and the link was kept where it should have been opened (0: the
  /// transport's visibility_rays).
  int decision_visibility_rays = 0;
  /// The oracles' colour channel weights (OracleThresholds::channel_weight,
  /// channel_weights in oracles/oracle.h).
  Rgb channel_weight = Rgb::Ones();
};

/// A stage's initial tasks: reload_links fills every field of every task in parallel,
/// so growing the list writes nothing (core/base/uninitialized_allocator.h).
using TaskList = std::vector<Task, UninitializedAllocator<Task>>;

/// What one refinement stage did. The driver's figures are inherited
/// (StageWorkerCounters: tasks, busy, idle, load and CPU time, takes, submits, binding;
/// its finish_s is the time to compact the stage's link lists,
/// core/hierarchy/link_list.h); in the total they are summed over refiners, finish_s
/// the longest, and bound / bind_warning unused. The rule's own follow.
struct RefineCounters : StageWorkerCounters {
  std::uint64_t links_created = 0;  ///< accepted links that were not links before
  std::uint64_t links_kept = 0;     ///< links reloaded and accepted again
  std::uint64_t culled = 0;         ///< pairs that cannot exchange light
  /// The oracle's error estimates summed over the links it judged and that were
  /// accepted, and over those it wanted refined but that min_area kept (an end that
  /// could be subdivided but is no larger than min_area, the other end unsplittable).
  double accepted_error = 0, held_error = 0;
  std::uint64_t held_links = 0;  ///< links min_area kept from being refined
  std::uint64_t rays_cast = 0;
  std::uint64_t rays_skipped = 0;             ///< rays not cast thanks to culling
  int peak_parallelism = 0;                   ///< most refiners busy at once
  double stage_start_s = 0, stage_end_s = 0;  ///< StageCounters' (the total's only)
  std::uint64_t link_bytes = 0;  ///< bytes in the refiner's link arena after compaction
  /// Tasks whose receiver's memory (Element::home_node) is on this refiner's node,
  /// and on another node (see set_binding).
  std::uint64_t tasks_local = 0, tasks_remote = 0;
  /// The stage stopped because its arenas passed RefineLimits::max_bytes (it is then
  /// unfinished); `arena_bytes` is what they held when that was seen.
  bool over_memory = false;
  std::uint64_t arena_bytes = 0;
  /// Per refiner (the fields above, one entry per worker; peak_parallelism unused).
  std::vector<RefineCounters> per_worker;
  /// One record per task when tracing was asked for (unordered).
  std::vector<TraceRecord> trace;
};

/// How far a refinement stage has come, as RefineProgressFn sees it.
struct RefineProgress {
  std::uint64_t tasks = 0;    ///< tasks examined so far, over all refiners
  std::uint64_t pending = 0;  ///< tasks known and not yet examined (queued or still to load)
  std::uint64_t links = 0;    ///< links accepted so far (created or kept)
  double elapsed_s = 0;       ///< since the stage started
};
using RefineProgressFn = std::function<void(const RefineProgress&)>;

class Refiner {
 public:
  Refiner(Hierarchy& hierarchy, const Transport& transport, const IOracle& oracle,
          RefineLimits limits, LockPool& element_locks, LockPool& link_locks);

  /// Binds refiner i (and the solver thread) as `plan` says at the start of every
  /// run(), through `topology`, and gives each refiner's thread its previous CPU set
  /// back when the stage ends; counts tasks as local when the receiver's
  /// home_node is the refiner's plan node. Both must outlive the Refiner; without a
  /// call, refiners are unbound and on node 0.
  void set_binding(const Topology* topology, const PinPlan* plan) {
    topology_ = topology;
    plan_ = plan;
  }

  /// The oracle's threshold (RefineLimits::eps_power) for the next stages; between
  /// stages only.
  void set_eps_power(double eps_power) { limits_.eps_power = eps_power; }
  void set_oracle_levels(int levels) { limits_.oracle_levels = levels; }

  /// While a stage runs, calls `fn` about every `interval_ms` from a thread of its
  /// own (never two calls at once, never after run() returns): refiners publish their
  /// counts once per block, so the figures lag by at most a block each. Without a
  /// call (or with an empty `fn`) no such thread runs and refiners publish nothing.
  void set_progress(RefineProgressFn fn, int interval_ms = 100) {
    progress_ = std::move(fn);
    progress_interval_ms_ = interval_ms;
  }

  /// Runs one refinement stage from `initial` tasks to completion. No element may
  /// hold links when it starts (the first stage, or after reload_links): each list is
  /// compacted by the refiner that stored its first link in the stage, so a list that
  /// already held links would keep staging blocks that the next stage reuses.
  /// With `trace_iteration` > 0, records every task (core/parallel/trace.h) under that
  /// iteration number.
  /// `initial` is read (and its trace ids set) in place; the caller keeps it.
  RefineCounters run(IScheduler& scheduler, std::span<Task> initial, int threads, int block_size,
                     int trace_iteration = 0);

  /// Tasks for the next iteration: every stored link, removed from its receiver
  /// (call between stages only; `elements` must be all of the hierarchy's, and the
  /// link memory is handed out again, see Hierarchy::release_links). Reloaded tasks
  /// carry their F and visibility. Built on `threads` threads, in the same order for
  /// any thread count: elements in the given order, each one's links in list order.
  /// `tasks` is resized to the link count and overwritten: pass the previous
  /// iteration's vector, so that its memory (and its pages) are reused. A task's
  /// priority is its link's reflected power with the oracles' `channel_weight`.
  static void reload_links(Hierarchy& hierarchy, const std::vector<Element*>& elements, int threads,
                           TaskList& tasks, const Rgb& channel_weight = Rgb::Ones());

 private:
  struct Worker;
  struct Body;
  struct Step;
  // One task: classify, estimate and judge the pair (open_pair or judge), then store
  // its link or split one end into child tasks.
  void process(const Task& task, Worker& w, std::vector<Task>& out);
  Step open_pair(PairClass pc, const Task& task, Worker& w, LinkEstimate& est);
  Step judge(const Task& task, Worker& w, LinkEstimate& est);
  void store_links(Worker& w, bool wait);
  [[nodiscard]] bool splittable(const Element& e) const;
  /// A surface less than RefineLimits::oracle_levels below its input polygon: one the
  /// oracle may split whatever its area.
  [[nodiscard]] bool oracle_may_split(const Element& e) const;
  /// A surface that could be subdivided but that min_area keeps whole (no larger than
  /// min_area, oracle_levels or more below its polygon).
  [[nodiscard]] bool held_by_min_area(const Element& e) const;

  Hierarchy& hierarchy_;
  const Transport& transport_;
  const IOracle& oracle_;
  RefineLimits limits_;
  LockPool& element_locks_;
  LockPool& link_locks_;
  const Topology* topology_ = nullptr;
  const PinPlan* plan_ = nullptr;
  RefineProgressFn progress_;
  int progress_interval_ms_ = 100;
};

}  // namespace hrad
