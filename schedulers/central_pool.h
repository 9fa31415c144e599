// CentralPool<Container>: one pool of tasks under one lock, the shape shared by the
// central schedulers (stack, fifo, priority, blocked). The Container decides the
// order; the pool hands out up to block_size tasks per take(), or with block_size 0 the
// guided block (guided_block in scheduler.h: ceil(held / 2 threads), at most
// kGuidedMaxBlock).
//
// submit_and_take (the driver's visit between two blocks) pushes and takes under one
// acquisition. The lock is a SpinMutex (core/parallel/spin_mutex.h). Lock waits are timed only when
// the lock is contended (try_lock first), so the instrumentation costs nothing on the
// uncontended path.
#pragma once

#include "core/parallel/spin_mutex.h"
#include "schedulers/pool_order.h"
#include "schedulers/scheduler.h"

#include <algorithm>
#include <mutex>
#include <vector>

namespace hrad {

/// Container concept: push(const Task&), bool empty(), Task pop().
template <class Container>
class CentralPool : public IScheduler {
 public:
  CentralPool(const SchedulerConfig& config, const char* name)
      : block_size_(static_cast<std::size_t>(config.block_size)),
        threads_(config.threads),
        order_(config.pool_order),
        name_(name) {}

  std::size_t take(int /*worker*/, std::span<Task> out) override {
    std::unique_lock lock = acquire();
    return take_locked(out);
  }

  void submit(int /*worker*/, std::span<const Task> tasks) override {
    if (tasks.empty()) return;
    std::vector<Task> sorted;  // pool_order: sorted outside the lock
    tasks = ordered(tasks, sorted);
    std::unique_lock lock = acquire();
    push_locked(tasks);
  }

  /// The driver's visit between two blocks: the submit and the next take under one
  /// acquisition of the lock (as `blocked`), so a block costs one hand-off of its line.
  std::size_t submit_and_take(int /*worker*/, std::span<const Task> tasks, std::span<Task> out,
                              bool /*own_only: one pool, nothing is another's*/) override {
    std::vector<Task> sorted;
    tasks = ordered(tasks, sorted);
    std::unique_lock lock = acquire();
    if (!tasks.empty()) push_locked(tasks);
    return take_locked(out);
  }

  [[nodiscard]] SchedulerCounters counters() const override {
    std::lock_guard lock(mutex_);
    return counters_;
  }
  [[nodiscard]] const char* name() const override { return name_; }

 private:
  // The batch in pool_order (sorted outside the lock, into `sorted`).
  std::span<const Task> ordered(std::span<const Task> tasks, std::vector<Task>& sorted) const {
    if (order_ == PoolOrder::Submitted || tasks.empty()) return tasks;
    sorted.assign(tasks.begin(), tasks.end());
    order_batch(sorted, order_);
    return sorted;
  }
  // Under mutex_.
  void push_locked(std::span<const Task> tasks) {
    for (const Task& t : tasks) tasks_.push(t);
    held_ += tasks.size();
    ++counters_.submits;
  }
  // Under mutex_: up to a block (fixed or guided) of tasks in the container's order.
  std::size_t take_locked(std::span<Task> out) {
    const std::size_t want = std::min(out.size(), take_size(block_size_, held_, threads_));
    std::size_t n = 0;
    while (n < want && !tasks_.empty()) out[n++] = tasks_.pop();
    held_ -= n;
    count_take(counters_, n);
    return n;
  }

  // counters_ is only written under mutex_, so the wait can be added to it.
  std::unique_lock<SpinMutex> acquire() { return timed_lock(mutex_, counters_.lock_wait_s); }

  alignas(64) mutable SpinMutex mutex_;
  // Guarded by mutex_, away from the lock's own line.
  alignas(64) Container tasks_;
  std::size_t held_ = 0;  // tasks in tasks_
  SchedulerCounters counters_;
  std::size_t block_size_;  // 0: guided
  int threads_;
  PoolOrder order_;
  const char* name_;
};

}  // namespace hrad
