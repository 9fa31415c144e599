// IScheduler: the only thing the refinement loop knows about task order.
//
// A task is a candidate link r <- s. Refiners (worker ids 0..threads-1) take up to
// a block of tasks, refine them, and submit the tasks they created in one call.
// The stage driver (core/stage/run_stage.h) owns termination: it counts tasks submitted
// but not finished, so a scheduler only has to hand out what it holds.
//
// Contract for every scheduler:
//  - every task submitted is returned by take() or take_own() exactly once;
//  - take() never blocks: it returns 0 when it has nothing for this worker now;
//  - take(), take_own() and submit() may be called concurrently from any workers (the
//    refiners load the initial tasks through submit() as themselves), and submit()
//    also from a thread that is no refiner (as any worker);
//  - a scheduler may use `worker` to keep per-worker queues or locality.
#pragma once

#include "core/base/enum_names.h"
#include "core/base/plugin_params.h"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace hrad {

struct Element;

struct Task {
  Element* receiver = nullptr;
  Element* source = nullptr;
  float form_factor = 0;  ///< cached from the link when `evaluated`
  float visibility = 1;
  float priority = 0;           ///< oracle error estimate (largest first for `priority`)
  bool evaluated = false;       ///< true for links reloaded from the previous iteration
  std::uint16_t decided_q = 0;  ///< reloaded links: Link::decided_q (in what was padding)
  std::uint64_t id = 0;  ///< trace id (see core/parallel/trace.h); set by the refinement driver
};
static_assert(sizeof(Task) == 40, "tasks are copied in and out of every pool");

/// How a central pool orders each submitted batch before it enters the pool
/// (schedulers/pool_order.h): as submitted, by receiver address, or by the receiver's
/// input polygon (its subtree of the hierarchy), then address.
enum class PoolOrder { Submitted, Address, Subtree };
inline constexpr EnumName<PoolOrder> kPoolOrderNames[] = {
    {PoolOrder::Submitted, "submitted", "as submitted"},
    {PoolOrder::Address, "address", "by receiver address"},
    {PoolOrder::Subtree, "subtree", "by the receiver's input polygon, then address"},
};
constexpr std::span<const EnumName<PoolOrder>> enum_names(PoolOrder) { return kPoolOrderNames; }

/// Most tasks a take() hands out with the guided block size (block_size 0).
inline constexpr std::size_t kGuidedMaxBlock = 1024;

/// The guided block size (guided self-scheduling, Polychronopoulos & Kuck 1987): a take
/// hands out ceil(pool / (2 threads)) tasks, at least 1 and at most kGuidedMaxBlock, where
/// `pool` is the number of tasks the scheduler holds (for `stealing`, the deque taken
/// from). While the pool is large, each visit brings enough work (hundreds of cheap
/// re-evaluations) that the pool's lock is free most of the time at 16 refiners; as it
/// drains, blocks shrink so that the last tasks still spread over every refiner. The
/// factor 2 leaves each refiner's take at most half its fair share.
inline std::size_t guided_block(std::size_t pool, int threads) {
  const std::size_t share = 2 * static_cast<std::size_t>(threads < 1 ? 1 : threads);
  return std::clamp<std::size_t>((pool + share - 1) / share, 1, kGuidedMaxBlock);
}

/// The tasks a take hands out from a pool of `pool` tasks: `block_size`, or the guided
/// block when it is 0.
inline std::size_t take_size(std::size_t block_size, std::size_t pool, int threads) {
  return block_size > 0 ? block_size : guided_block(pool, threads);
}

/// The largest take a scheduler with this block_size makes (the caller's buffer size).
inline std::size_t max_block(int block_size) {
  return block_size > 0 ? static_cast<std::size_t>(block_size) : kGuidedMaxBlock;
}

struct SchedulerConfig {
  int threads = 1;  ///< number of workers that will call take/submit
  /// At most this many tasks per take(); 0: the guided block size (guided_block).
  int block_size = 0;
  /// NUMA placement (used by `locality`): nodes the elements may live on, and the
  /// node each worker runs on (empty: every worker on node 0). With numa_nodes > 1
  /// a scheduler may read task.receiver->home_node.
  int numa_nodes = 1;
  std::vector<int> worker_node;
  /// Batch order of the central pools (stack, fifo, priority, blocked, locality).
  PoolOrder pool_order = PoolOrder::Submitted;
  /// The scheduler's own parameters (`--set scheduler.NAME.KEY=VALUE`), by KEY; the
  /// scheduler declares them when it registers and reads them in its factory.
  ParamValues params;
};

/// Counters a scheduler keeps; summed over workers.
struct SchedulerCounters {
  std::uint64_t takes = 0;  ///< take() calls that returned at least one task
  std::uint64_t empty_takes = 0;
  std::uint64_t submits = 0;
  std::uint64_t steals = 0;  ///< tasks taken from another worker's queue
  double lock_wait_s = 0;    ///< time spent waiting for the scheduler's lock(s)
};

/// Counts a take that returned n tasks (an empty take when n is 0).
inline void count_take(SchedulerCounters& c, std::size_t n) { ++(n > 0 ? c.takes : c.empty_takes); }

class IScheduler {
 public:
  virtual ~IScheduler() = default;
  /// Fills `out` with up to min(out.size(), block_size) tasks; returns how many.
  virtual std::size_t take(int worker, std::span<Task> out) = 0;
  /// The same, but never from another worker's queue or pool (no stealing): the
  /// driver takes this way while initial tasks are left to load, so that a refiner
  /// with nothing of its own loads fresh work rather than take the work another
  /// refiner just loaded (and the cache lines it holds). Central pools have no own
  /// queue: the default is take().
  virtual std::size_t take_own(int worker, std::span<Task> out) { return take(worker, out); }
  /// Adds tasks created by `worker` (or initial tasks, with worker 0).
  virtual void submit(int worker, std::span<const Task> tasks) = 0;
  /// submit(worker, tasks), then take(worker, out) (take_own when `own_only`): the
  /// driver's visit to the pool between two blocks. The result is the same as the two
  /// calls; a scheduler under one lock overrides it to take the lock once (`blocked`).
  virtual std::size_t submit_and_take(int worker, std::span<const Task> tasks, std::span<Task> out,
                                      bool own_only) {
    submit(worker, tasks);
    return own_only ? take_own(worker, out) : take(worker, out);
  }
  [[nodiscard]] virtual SchedulerCounters counters() const = 0;
  [[nodiscard]] virtual const char* name() const = 0;
};

/// Builds a scheduler from its configuration and its parameters (config.params, read
/// through `params`, which knows the declared defaults and ranges).
using SchedulerFactory =
    std::function<std::unique_ptr<IScheduler>(const SchedulerConfig&, const PluginParams& params)>;

/// Creates a scheduler by name; throws std::invalid_argument listing the known
/// names when `name` is unknown, and for a parameter in config.params that the
/// scheduler does not declare or did not read (PluginParams::report_unused).
std::unique_ptr<IScheduler> make_scheduler(const std::string& name, const SchedulerConfig& config);
std::vector<std::string> scheduler_names();
/// The parameters `name` declared (throws as make_scheduler for an unknown name).
std::span<const ParamSpec> scheduler_params(const std::string& name);

/// Throws make_scheduler's std::invalid_argument when `name` is not registered; checks
/// a name without building a scheduler.
void check_scheduler_name(const std::string& name);

/// Registration: each scheduler file defines one `static const bool registered =
/// register_scheduler("name", factory, {parameters});` — a new scheduler, with its own
/// parameters, is one new file.
bool register_scheduler(const std::string& name, SchedulerFactory factory,
                        std::vector<ParamSpec> params = {});

}  // namespace hrad
