// The simulator's cost model: what the scheduler and the refinement loop cost beyond
// the recorded task durations, per operation, in nanoseconds.
//
// | field          | meaning (time a processor spends; "held" = the lock is held)           |
// |----------------|-------------------------------------------------------------------------|
// | take_op_ns     | central lock held per take() (also an empty take)                       |
// | take_task_ns   | central lock held per task taken                                        |
// | submit_op_ns   | central lock held per submit()                                          |
// | submit_task_ns | central lock held per task submitted (0 for `blocked`: O(1) submit)     |
// | copy_task_ns   | per task submitted, outside the lock (`blocked` copies before locking)  |
// | local_op_ns    | `stealing`: the owner's pop or push of a block on its own deque         |
// | local_task_ns  | `stealing`: per task popped or pushed by the owner                      |
// | steal_op_ns    | `stealing`: per steal (scan, victim choice), on the victim's deque      |
// | steal_task_ns  | `stealing`: per stolen task (one CAS each), on the victim's deque       |
// | block_ns       | per block, outside the scheduler (storing the block's links, counters)  |
// | task_ns        | per task, outside its recorded duration (loop bookkeeping)              |
// | start_ns       | per iteration, before the first take (starting the refiner threads)     |
// | slowdown       | task durations are multiplied by this when 2 or more processors run     |
// | slowdown_per_proc | and by 1 + this × (P − 1) at P processors (shared caches, memory)    |
// | handoff_ns     | central lock passes to another processor than its last holder: the      |
// |                | lock's line and the lines it guards move (held longer when uncontended; |
// |                | the lock is idle this long between release and grant when contended)    |
// | handoff_waiter_ns | a contended hand-off is longer by this per further waiter: each     |
// |                | spinner's CAS takes the lock's line once before the next holder gets it |
// | outside_serial_share | the serial share s of the stage's time outside the task loop: |
// |                | N measured at 1 thread takes N × (s + (1 − s) / P) (simulator.h); 0..1   |
//
// Contention: the central lock (blocked's per-processor stacks are under it too) has one
// holder at a time; each stealing deque is a resource of its own (owner operations and
// steals on it are serialised, different deques proceed in parallel). Waiting is first
// come, first served. Only the central lock pays hand-offs: a processor that finds it
// held waits for the release plus handoff_ns + handoff_waiter_ns × (w − 1), w = the
// processors waiting when it passes (estimated by those queued ahead when it asked, at
// least 1), so a saturated lock at T processors (T − 1 waiting at each release) passes
// once per hold + handoff_ns + (T − 2) × handoff_waiter_ns: a convoy. One that finds the
// lock free but last held by another processor holds it handoff_ns longer.
// `hrad simulate --calibrate-locks` measures both on the machine at hand.
#pragma once

#include "schedulers/scheduler.h"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace hrad::sim {

/// The scheduling policies the simulator replays (schedulers/ has the real ones).
enum class Policy { kStack, kFifo, kPriority, kBlocked, kStealing };

/// A scheduler's policy by the scheduler's name (policy_names()). Any other name throws
/// std::invalid_argument listing the simulated names and the registered schedulers
/// that have no model (saying so when `name` is one of them).
Policy policy_from_name(const std::string& name);
const char* policy_name(Policy p);
std::vector<std::string> policy_names();

/// The registered schedulers deliberately not modelled (cost_model.cpp says why).
/// Every name in scheduler_names() is in policy_names() or here (simulate_test).
std::vector<std::string> unmodelled_schedulers();

struct CostModel {
  double take_op_ns = 0;
  double take_task_ns = 0;
  double submit_op_ns = 0;
  double submit_task_ns = 0;
  double copy_task_ns = 0;
  double local_op_ns = 0;
  double local_task_ns = 0;
  double steal_op_ns = 0;
  double steal_task_ns = 0;
  double block_ns = 0;
  double task_ns = 0;
  double start_ns = 0;
  double slowdown = 1;
  double slowdown_per_proc = 0;
  double handoff_ns = 0;
  double handoff_waiter_ns = 0;
  /// The 16-core machine's, from its 1- and 2-thread runs (default_costs()).
  double outside_serial_share = 0.46;
};

/// Block size 0 (guided) is the schedulers' own formula, hrad::guided_block in
/// schedulers/scheduler.h: a central take hands out guided_block(pool, threads) of the
/// `pool` tasks held in all (blocked: every per-processor stack together); `stealing`'s
/// owner pops guided_block(deque, 1) and a thief takes half the victim's deque, at most
/// kGuidedMaxBlock.

/// Defaults from the scheduler microbenchmark on the development VM (the fit is in
/// cost_model.cpp): uncontended costs split into a per-operation and a per-task part.
/// block_ns is 0 here (`hrad simulate` estimates it from the trace); slowdown is 1;
/// the central lock's hand-offs are the 16-core machine's (costs-16core-44e96be.json).
CostModel default_costs(Policy policy);

/// Overrides fields of `costs` from a JSON object whose keys are the field names
/// above; an unknown key, a non-number or a value out of its bounds is an error naming
/// the file and key: times 0 to 1e12 ns, slowdown 1e-3 to 1e3, slowdown_per_proc 0 to
/// 1e3, outside_serial_share 0 to 1 (those of the flags that set the same costs).
void load_costs(const std::filesystem::path& file, CostModel& costs);

/// The model as one JSON object (the field names above).
std::string costs_to_json(const CostModel& costs);

}  // namespace hrad::sim
