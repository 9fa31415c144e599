// `blocked`: the paper's scheduler (Sillion & Hasenfratz 2000, §3.5). One central pool
// under one lock; a refiner takes a block of up to block_size tasks at once, buffers the
// tasks it creates in a private table (the driver's `out` vector) and submits them in one
// locked operation after the block.
//
// | parameter  | type | default | meaning                                        |
// |------------|------|---------|------------------------------------------------|
// | block_size | int  | 1       | at most this many tasks per take()             |
//
// What differs from `stack` with the same block size is the cost under the lock, not the
// order. The pool is a stack of *chunks*, one per submit():
//  - submit() copies the batch into a chunk buffer *before* taking the lock; under the
//    lock it only moves that buffer onto the chunk stack and picks up a recycled buffer
//    for the thread's next submit: O(1) under the lock whatever the batch size.
//  - take() copies up to block_size tasks out of the top chunks under the lock (O(block),
//    never more); an emptied chunk's buffer goes to a spare list for reuse.
// Buffers circulate pool -> spare list -> a thread's spare (thread_local) -> pool, so in
// steady state no allocation happens, under the lock or outside it.
//
// Order: LIFO over chunks and newest first inside a chunk, i.e. exactly the order of
// `stack`: depth-first, like the recursion. A take may span chunks.
//
// The chunk stack itself is schedulers/chunk_stack.h (shared with `locality`).
//
// Lock waits are timed only when the lock is contended (try_lock first), as in
// CentralPool.
#include "core/timed_lock.h"
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
      : block_size_(static_cast<std::size_t>(config.block_size)), order_(config.pool_order) {}

  std::size_t take(int /*worker*/, std::span<Task> out) override {
    const std::size_t want = std::min(out.size(), block_size_);
    std::vector<Task> discard;  // an oversized emptied buffer, freed after unlocking
    std::size_t n = 0;
    {
      std::unique_lock lock = acquire();
      n = chunks_.pop(out, want, discard);
      if (n > 0) ++counters_.takes; else ++counters_.empty_takes;
    }
    return n;
  }

  void submit(int /*worker*/, std::span<const Task> tasks) override {
    if (tasks.empty()) return;
    std::vector<Task>& spare = thread_spare();
    spare.assign(tasks.begin(), tasks.end());  // the copy, outside the lock
    order_batch(spare, order_);
    std::unique_lock lock = acquire();
    chunks_.push(spare);  // O(1): moves the buffer in, a recycled one out
    ++counters_.submits;
  }

  [[nodiscard]] SchedulerCounters counters() const override {
    std::lock_guard lock(mutex_);
    return counters_;
  }
  [[nodiscard]] const char* name() const override { return "blocked"; }

 private:
  // counters_ is only written under mutex_, so the wait can be added to it.
  std::unique_lock<std::mutex> acquire() { return timed_lock(mutex_, counters_.lock_wait_s); }

  const std::size_t block_size_;
  const PoolOrder order_;
  mutable std::mutex mutex_;
  ChunkStack chunks_;                      // guarded by mutex_
  SchedulerCounters counters_;             // guarded by mutex_
};

const bool registered = register_scheduler("blocked", [](const SchedulerConfig& c) {
  return std::make_unique<BlockedScheduler>(c);
});

}  // namespace
}  // namespace hrad
