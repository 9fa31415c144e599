// The dependency DAG of a recorded refinement, rebuilt from a task trace
// (core/parallel/trace.h) for the simulator (experiments/sim/simulator.h).
//
// Within one iteration every task but the initial ones was created by exactly one
// parent, and the refiner submits a block's created tasks only after the whole block
// (core/stage/run_stage.h, for every scheduler), so a task becomes available when its
// parent's *block* ends; the simulator decides the blocks, the graph only knows who
// created whom. Iterations are separated by a barrier (propagation runs between them
// and is not in the trace), so each iteration is its own graph.
//
// Tasks are renumbered breadth-first so that a task's children are consecutive:
// children of task i are [first_child, first_child + children), in creation order,
// and the initial tasks are 0 .. roots - 1 in their submission order.
#pragma once

#include "core/parallel/trace.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hrad::sim {

struct SimTask {
  std::uint64_t duration_ns = 0;  ///< measured duration (block bit removed)
  std::uint32_t first_child = 0;  ///< index of the first child in the iteration's tasks
  std::uint32_t children = 0;
};

struct IterationGraph {
  int iteration = 0;                   ///< 1-based, as in the trace
  std::uint32_t roots = 0;             ///< initial tasks: indices 0 .. roots - 1
  std::vector<SimTask> tasks;          ///< breadth-first order (see the file comment)
  std::uint64_t work_ns = 0;           ///< sum of durations
  std::uint64_t critical_path_ns = 0;  ///< longest root-to-leaf sum of durations
  std::uint64_t measured_span_ns = 0;  ///< trace: latest task end (start + duration)
  std::uint64_t first_start_ns = 0;    ///< trace: earliest task start
  std::uint64_t blocks = 0;            ///< trace: records with the block-start bit
};

struct TaskGraph {
  std::vector<IterationGraph> iterations;  ///< ascending iteration number
  [[nodiscard]] std::uint64_t tasks() const;
  [[nodiscard]] std::uint64_t work_ns() const;
};

/// Builds the per-iteration DAGs. Throws std::runtime_error (prefixed by `what`, e.g.
/// the file name) when the records do not form a forest: a child id that is not in
/// the trace, a task created twice, a duplicate id, an iteration number of 0.
TaskGraph build_task_graph(const std::vector<TraceRecord>& records,
                           const std::string& what = "trace");

/// Time the trace shows between tasks of one worker in one iteration, in ns. Between
/// blocks: storing the block's links, submit, take, idle time. Inside a block: the
/// tracing's own clock reads and record. Both also absorb preemption and page faults,
/// which make the means much larger than the medians on a shared machine.
struct GapStats {
  double block_median = 0, block_mean = 0;  ///< before each block (but a worker's first)
  double task_median = 0, task_mean = 0;    ///< before each task inside a block
};
GapStats gap_stats(const std::vector<TraceRecord>& records);

/// gap_stats(records).block_median.
double median_block_gap_ns(const std::vector<TraceRecord>& records);

/// True when `id` names an initial task of its iteration (no creating worker).
inline bool is_initial_task(std::uint64_t id) { return (id >> 48) == 0; }

}  // namespace hrad::sim
