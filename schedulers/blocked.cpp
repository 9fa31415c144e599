// `blocked`: the paper's scheduler (Sillion & Hasenfratz 2000, §3.5). One central pool
// under one lock; a refiner takes a block of tasks at once, buffers the tasks it creates
// in a private table (the driver's `out` vector) and submits them in one locked
// operation after the block.
//
// | parameter  | type | default | meaning                                                  |
// |------------|------|---------|----------------------------------------------------------|
// | block_size | int  | 0       | at most this many tasks per take(); 0: guided (below)    |
//
// Block size. With a fixed block the pool's lock is visited once per block_size tasks,
// whatever they cost. The later iterations re-evaluate about a million kept links at
// 65-400 ns each, so a block of 10 is a few microseconds of work per visit: on a
// 16-core machine the lock was busy all the time, and those iterations ran slower on 16
// refiners than on one. The default (block_size 0) is guided self-scheduling
// (Polychronopoulos & Kuck 1987; guided_block in scheduler.h): each take hands out
// ceil(P / 2T) tasks of the P the pool holds, T refiners, at most kGuidedMaxBlock: large
// blocks while the pool is large, single tasks when it is nearly empty. A fixed
// block_size (Fig. 7's 1, 10, 100, ...) keeps the paper's behaviour.
//
// What differs from `stack` with the same block size is the cost under the lock, not the
// order. The pool is made of stacks of *chunks*, one chunk per submit():
//  - submit() copies the batch into a chunk buffer *before* taking the lock; under the
//    lock it only moves that buffer onto a chunk stack and picks up a recycled buffer
//    for the thread's next submit: O(1) under the lock whatever the batch size.
//  - take() copies up to a block of tasks out of chunks under the lock (O(block), never
//    more); an emptied chunk's buffer goes to a spare list for reuse.
// Buffers circulate pool -> spare list -> a thread's spare (thread_local) -> pool, so in
// steady state no allocation happens, under the lock or outside it.
//
// Order: the central pool keeps one chunk stack per refiner, all under the one lock. A
// chunk goes on its submitter's stack; a refiner takes from its own stack (LIFO over
// chunks, newest first inside a chunk: exactly `stack`'s depth-first order, and with
// one refiner exactly `stack`), and only when its own is empty from the oldest chunk of
// the next non-empty stack (counted as steals; take_own never does). With a single
// LIFO shared by all, each refiner took the children the other had just created, on
// elements the other had just built: every such task's data came from the other core's
// cache. Measured on the office at 2 threads, block 10, CPU per task rose 27 % over 1
// thread that way, and 1-5 % with this order (iteration 1, medians of 5 alternating
// pairs). The stacks' bookkeeping lives apart from the lock's cache line.
//
// The chunk stack itself is schedulers/chunk_stack.h (shared with `locality`).
//
// The lock is a SpinMutex (core/parallel/spin_mutex.h: waiters spin on a read, then
// sleep), not std::mutex, whose waiters' try_lock spin wrote the lock's line while its
// holder worked and whose sleeping waiters turned every hand-off into a futex wake-up.
// Lock waits are timed only when the lock is contended.
//
// submit_and_take() does a refiner's submit and its next take under one acquisition:
// the driver calls it between two blocks, so a block costs one visit to the pool
// instead of two. The lock's line moves between the cores at most once per block: on
// builtin:lab at 2 threads, block 10, the two visits made CPU per task 11 % higher than
// at 1 thread (1 % at block 100, with ten times fewer visits).
#include "core/parallel/spin_mutex.h"
#include "schedulers/chunk_stack.h"
#include "schedulers/pool_order.h"
#include "schedulers/scheduler.h"

#include <algorithm>
#include <mutex>
#include <vector>

namespace hrad {
namespace {

// This thread's buffer for its next submit (shared by all BlockedSchedulers: it is only
// memory, never holds tasks between calls).
std::vector<Task>& thread_spare() {
  thread_local std::vector<Task> spare;
  return spare;
}

class BlockedScheduler final : public IScheduler {
 public:
  explicit BlockedScheduler(const SchedulerConfig& config)
      : block_size_(static_cast<std::size_t>(config.block_size)),
        threads_(std::max(config.threads, 1)),
        order_(config.pool_order),
        stacks_(static_cast<std::size_t>(std::max(config.threads, 1))) {}

  std::size_t take(int worker, std::span<Task> out) override {
    return take_from(worker, out, true);
  }
  std::size_t take_own(int worker, std::span<Task> out) override {
    return take_from(worker, out, false);
  }

  void submit(int worker, std::span<const Task> tasks) override {
    if (tasks.empty()) return;
    std::vector<Task>& spare = prepare(tasks);
    std::unique_lock lock = acquire();
    push_locked(worker, spare);
  }

  std::size_t submit_and_take(int worker, std::span<const Task> tasks, std::span<Task> out,
                              bool own_only) override {
    if (tasks.empty()) return own_only ? take_own(worker, out) : take(worker, out);
    std::vector<Task>& spare = prepare(tasks);
    std::vector<Task> discard;
    std::size_t n = 0;
    {
      std::unique_lock lock = acquire();
      push_locked(worker, spare);
      n = take_locked(worker, out, !own_only, discard);
    }
    return n;
  }

  [[nodiscard]] SchedulerCounters counters() const override {
    std::lock_guard lock(mutex_);
    return counters_;
  }
  [[nodiscard]] const char* name() const override { return "blocked"; }

 private:
  std::size_t take_from(int worker, std::span<Task> out, bool may_steal) {
    std::vector<Task> discard;  // an oversized emptied buffer, freed after unlocking
    std::size_t n = 0;
    {
      std::unique_lock lock = acquire();
      n = take_locked(worker, out, may_steal, discard);
    }
    return n;
  }

  // The batch copied into this thread's spare buffer and ordered: outside the lock.
  std::vector<Task>& prepare(std::span<const Task> tasks) {
    std::vector<Task>& spare = thread_spare();
    spare.assign(tasks.begin(), tasks.end());
    order_batch(spare, order_);
    return spare;
  }

  // Under mutex_: O(1), moves the buffer in and a recycled one out.
  void push_locked(int worker, std::vector<Task>& spare) {
    held_ += spare.size();
    stacks_[slot(worker)].push(spare);
    ++counters_.submits;
  }

  // Under mutex_: up to block_size tasks from the worker's own stack, else (when
  // `may_steal`) from the oldest chunk of the next non-empty one.
  std::size_t take_locked(int worker, std::span<Task> out, bool may_steal,
                          std::vector<Task>& discard) {
    const std::size_t want = std::min(out.size(), take_size(block_size_, held_, threads_));
    const std::size_t w = slot(worker);
    std::size_t n = stacks_[w].pop(out, want, discard);
    for (std::size_t k = 1; may_steal && n == 0 && k < stacks_.size(); ++k) {
      ChunkStack& other = stacks_[(w + k) % stacks_.size()];
      if (other.empty()) continue;
      n = other.pop_oldest(out, want, discard);
      counters_.steals += n;
    }
    held_ -= n;
    count_take(counters_, n);
    return n;
  }

  // counters_ is only written under mutex_, so the wait can be added to it.
  std::unique_lock<SpinMutex> acquire() { return timed_lock(mutex_, counters_.lock_wait_s); }
  [[nodiscard]] std::size_t slot(int worker) const {
    return static_cast<std::size_t>(worker) % stacks_.size();
  }

  const std::size_t block_size_;  // 0: guided
  const int threads_;
  const PoolOrder order_;
  alignas(64) mutable SpinMutex mutex_;
  // Guarded by mutex_, on lines of their own (the lock's line is written by every
  // acquisition and release; these only by the holder).
  alignas(64) std::vector<ChunkStack> stacks_;  // one per refiner
  std::size_t held_ = 0;                        // tasks in all stacks
  SchedulerCounters counters_;
};

const bool registered =
    register_scheduler("blocked", [](const SchedulerConfig& c, const PluginParams&) {
      return std::make_unique<BlockedScheduler>(c);
    });

}  // namespace
}  // namespace hrad
