// `locality`: the paper's blocked central pool, split into one pool per NUMA node.
// A task goes to the pool of the node its receiver's memory is on (Element::home_node,
// as the arenas count it, core/parallel/node_arena.h); a refiner takes a block from its own
// node's pool first and only when that is empty from the others, starting with the
// next node up, so receivers (the elements a task writes links to and subdivides)
// tend to be refined by a refiner on their node.
//
// | parameter   | type      | default | meaning                                           |
// |-------------|-----------|---------|---------------------------------------------------|
// | block_size  | int       | 0       | at most this many tasks per take(); 0: guided     |
// | numa_nodes  | int       | 1       | pools (SchedulerConfig::numa_nodes)               |
// | worker_node | int list  | all 0   | the node each refiner runs on (from the pin plan) |
// | pool_order  | enum      | submitted | batch order inside each pool (pool_order.h)     |
//
// Each pool is a ChunkStack (schedulers/chunk_stack.h) under its own lock: a submit
// splits the batch by receiver node outside any lock, then moves one chunk per node
// under that node's lock (O(1)); a take copies out at most one block. Order inside a
// pool is `stack`'s (depth-first). With one node it is `blocked` with one more
// indirection. Tasks a refiner takes from another node's pool count as `steals`.
// With block_size 0 a take hands out guided_block(tasks in the pool, refiners) tasks
// (scheduler.h). Each pool's lock is a SpinMutex (core/parallel/spin_mutex.h); the
// take, submit and steal counts are kept per refiner, on lines of their own.
//
// With numa_nodes == 1 the receiver is never dereferenced (the scheduler tests use
// fake receiver pointers).
#include "core/hierarchy/element.h"
#include "core/parallel/spin_mutex.h"
#include "schedulers/chunk_stack.h"
#include "schedulers/pool_order.h"
#include "schedulers/scheduler.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

namespace hrad {
namespace {

// This thread's per-node buffers for its next submit (shared by all instances: only
// memory, never holds tasks between calls).
std::vector<std::vector<Task>>& thread_buffers(std::size_t nodes) {
  thread_local std::vector<std::vector<Task>> buffers;
  if (buffers.size() < nodes) buffers.resize(nodes);
  return buffers;
}

class LocalityScheduler final : public IScheduler {
 public:
  explicit LocalityScheduler(const SchedulerConfig& config)
      : block_size_(static_cast<std::size_t>(config.block_size)),
        threads_(std::max(config.threads, 1)),
        counts_(static_cast<std::size_t>(threads_)),
        nodes_(static_cast<std::size_t>(std::max(config.numa_nodes, 1))),
        pools_(nodes_),
        worker_node_(config.worker_node),
        order_(config.pool_order) {
    for (int& n : worker_node_)
      if (n < 0 || static_cast<std::size_t>(n) >= nodes_) n = 0;
  }

  std::size_t take(int worker, std::span<Task> out) override {
    return take_from(worker, out, nodes_);
  }
  /// Only the refiner's own node's pool.
  std::size_t take_own(int worker, std::span<Task> out) override {
    return take_from(worker, out, 1);
  }

  void submit(int worker, std::span<const Task> tasks) override {
    if (tasks.empty()) return;
    std::vector<std::vector<Task>>& buf = thread_buffers(nodes_);
    if (nodes_ == 1) {
      buf[0].assign(tasks.begin(), tasks.end());
    } else {
      for (std::size_t i = 0; i < nodes_; ++i) buf[i].clear();
      for (const Task& t : tasks)  // the copy, outside the locks
        buf[std::min<std::size_t>(t.receiver->home_node, nodes_ - 1)].push_back(t);
    }
    for (std::size_t i = 0; i < nodes_; ++i) {
      if (buf[i].empty()) continue;
      order_batch(buf[i], order_);  // pool_order, outside the lock
      Pool& p = pools_[i];
      std::unique_lock lock = timed_lock(p.mutex, p.lock_wait_s);
      p.stack.push(buf[i]);  // O(1): moves the buffer, not the tasks
      p.hint.store(p.stack.size(), std::memory_order_relaxed);
    }
    count(worker).submits.add(1);
  }

  [[nodiscard]] SchedulerCounters counters() const override {
    SchedulerCounters c;
    for (const Counts& k : counts_) {
      c.takes += k.takes.get();
      c.empty_takes += k.empty_takes.get();
      c.submits += k.submits.get();
      c.steals += k.steals.get();
    }
    for (const Pool& p : pools_) {
      std::lock_guard lock(p.mutex);
      c.lock_wait_s += p.lock_wait_s;
    }
    return c;
  }
  [[nodiscard]] const char* name() const override { return "locality"; }

 private:
  std::size_t take_from(int worker, std::span<Task> out, std::size_t pools) {
    const std::size_t home = node_of_worker(worker);
    std::vector<Task> discard;  // an oversized emptied buffer, freed after unlocking
    std::size_t n = 0;
    for (std::size_t k = 0; k < pools && n == 0; ++k) {
      Pool& p = pools_[(home + k) % nodes_];
      if (p.hint.load(std::memory_order_relaxed) == 0) continue;  // skip the lock when empty
      std::unique_lock lock = timed_lock(p.mutex, p.lock_wait_s);
      n = p.stack.pop(out, std::min(out.size(), take_size(block_size_, p.stack.size(), threads_)),
                      discard);
      p.hint.store(p.stack.size(), std::memory_order_relaxed);
      if (k > 0) count(worker).steals.add(n);
    }
    Counts& c = count(worker);
    (n > 0 ? c.takes : c.empty_takes).add(1);
    return n;
  }

  // A count written by one refiner (any thread submitting as it: the initial load may
  // come from outside the team, so the add is atomic), read by counters().
  class Count {
   public:
    void add(std::uint64_t n) { v_.fetch_add(n, std::memory_order_relaxed); }
    [[nodiscard]] std::uint64_t get() const { return v_.load(std::memory_order_relaxed); }

   private:
    std::atomic<std::uint64_t> v_{0};
  };
  struct alignas(64) Counts {
    Count takes, empty_takes, submits, steals;
  };
  Counts& count(int worker) { return counts_[static_cast<std::size_t>(worker) % counts_.size()]; }

  struct alignas(64) Pool {
    mutable SpinMutex mutex;
    ChunkStack stack;                  // guarded by mutex
    double lock_wait_s = 0;            // guarded by mutex
    std::atomic<std::size_t> hint{0};  // stack.size() as of the last locked operation
  };

  [[nodiscard]] std::size_t node_of_worker(int worker) const {
    const auto w = static_cast<std::size_t>(worker);
    return w < worker_node_.size() ? static_cast<std::size_t>(worker_node_[w]) : 0;
  }

  const std::size_t block_size_;  // 0: guided
  const int threads_;
  std::vector<Counts> counts_;  // per refiner
  const std::size_t nodes_;
  std::vector<Pool> pools_;
  std::vector<int> worker_node_;
  const PoolOrder order_;
};

const bool registered =
    register_scheduler("locality", [](const SchedulerConfig& c, const PluginParams&) {
      return std::make_unique<LocalityScheduler>(c);
    });

}  // namespace
}  // namespace hrad
