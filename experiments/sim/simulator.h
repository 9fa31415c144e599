// Discrete-event replay of a recorded refinement (TaskGraph) on `procs` simulated
// processors under one scheduling policy and a CostModel.
//
// Each processor loops as the stage driver (core/stage/run_stage.h) does: take up to
// block_size tasks (0: guided, guided_block in schedulers/scheduler.h), run them (recorded
// durations × the slowdown), spend block_ns, then submit the tasks the block created in
// one operation; those become available when the submit releases the lock (or the
// deque). The central pools (`blocked`, `stack`, `fifo`, `priority`) submit and take
// the next block under one acquisition (IScheduler::submit_and_take); `stealing`
// pushes onto its deque, then takes. Lock-like resources (the
// central lock, each stealing deque) are granted first come, first served, one holder at
// a time; an operation's effect on the queue is applied in grant order, which equals
// request order, so the queues are always consistent with the simulated clock. The
// central lock also pays hand-offs (cost_model.h: handoff_ns, handoff_waiter_ns).
//
// Idle processors do not spin: a submit of k tasks wakes min(idle, ceil((size - B)/B))
// of them (the submitter takes the next block itself), in the order they went idle; a
// woken processor that finds nothing pays an empty take and waits again. This
// understates the lock traffic of the real spinning refiners when many are idle.
//
// Order: stack takes the newest tasks; blocked keeps one stack per processor under its
// one lock, a processor takes its own newest and, when its own is empty, the oldest of
// the next non-empty stack (schedulers/blocked.cpp); fifo the oldest; priority is
// approximated by fifo order (the trace has no oracle errors; coarse links, which carry
// the largest errors, are the oldest) with its own costs; stealing pops the owner's
// newest, and a thief takes the oldest min(block, ceil(n/2)) tasks of the first
// non-empty victim in a round-robin scan from a per-processor pseudo-random start.
// The initial tasks of each iteration are loaded by the processors themselves, a chunk
// of load_chunk at a time, by one that finds nothing of its own to take (while chunks
// are left, blocked and stealing do not steal: IScheduler::take_own, as the refiners
// do, core/solver/refiner.h; the load's submit is that processor's time); iterations are
// separated by a barrier.
//
// Outside the task loop (SimConfig::outside, from the traced run's stats.json): the
// stage's refine_wall_s also holds building the tasks from the previous iteration's links
// (Refiner::reload_links) and loading them into the pool, the stage's start (the OpenMP
// team, the solver thread) and end, and the link compaction of its finish. Measured at 1
// thread as N, it takes N × (s + (1 − s) / P) at P processors (Amdahl), s =
// CostModel::outside_serial_share: the task vector's growth and copy in reload_links, its
// serial prefix sum and the release of the link lists, the team's start and the wait for
// the slowest compaction stay serial; the parallel fill, the chunked loads and each
// refiner's compaction of the lists it started spread over the processors.
#pragma once

#include "core/stage/run_stage.h"
#include "experiments/sim/cost_model.h"
#include "experiments/sim/task_graph.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace hrad::sim {

/// One iteration's stage time outside the task loop, measured at 1 thread, ns (the
/// traced run's stats.json: load_s, link_compact_s, stage_start_s + stage_end_s).
struct OutsideLoop {
  double load_ns = 0;     ///< reload_links + loading the tasks into the pool
  double compact_ns = 0;  ///< link compaction (the stage's finish)
  double edges_ns = 0;    ///< the stage's start and end
  [[nodiscard]] double total_ns() const { return load_ns + compact_ns + edges_ns; }
};

struct SimConfig {
  Policy policy = Policy::kStack;
  int procs = 1;
  int block_size = 1;  ///< 0: guided (cost_model.h)
  CostModel costs;
  int load_chunk =
      static_cast<int>(kStageLoadChunk);  ///< initial tasks per load (core/stage/run_stage.h)
  bool keep_executions = false;           ///< fill IterationResult::executions (tests)
  /// Per iteration (in the graph's order), the time outside the task loop at 1 thread;
  /// empty or shorter: none for the iterations without an entry.
  std::vector<OutsideLoop> outside;
};

/// Time shares summed over processors, in ns; busy + overhead + lock_wait + idle +
/// outside = procs × time for every iteration.
struct IterationResult {
  int iteration = 0;
  double time_ns = 0;       ///< refinement time of the iteration (barrier to barrier)
  double busy_ns = 0;       ///< running tasks
  double overhead_ns = 0;   ///< holding locks, queue operations, copies, block_ns
  double lock_wait_ns = 0;  ///< waiting for a lock or deque held by another processor
  double idle_ns = 0;       ///< nothing to do
  double outside_ns = 0;    ///< procs × the stage's time outside the task loop (SimConfig)
  std::uint64_t tasks = 0, takes = 0, empty_takes = 0, submits = 0, steals = 0;
  std::vector<std::uint32_t> executions;  ///< per task, times run (keep_executions)
};

struct SimResult {
  std::vector<IterationResult> iterations;
  [[nodiscard]] double time_ns() const;
  [[nodiscard]] IterationResult totals() const;  ///< sums (iteration = 0)
};

/// `progress(fraction)` is called now and then (may be empty). Throws
/// std::invalid_argument for procs < 1 or block_size < 0, std::logic_error if the
/// replay stalls (a bug).
SimResult simulate(const TaskGraph& graph, const SimConfig& config,
                   const std::function<void(double)>& progress = {});

}  // namespace hrad::sim
