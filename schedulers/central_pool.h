// CentralPool<Container>: one pool of tasks under one lock, the shape shared by the
// central schedulers (stack, fifo, priority, blocked). The Container decides the
// order; the pool hands out up to block_size tasks per take(), or with block_size 0 the
// guided block (guided_block in scheduler.h: ceil(held / 2 threads), at most
// kGuidedMaxBlock).
//
// The lock is a SpinMutex (core/parallel/spin_mutex.h). Lock waits are timed only when
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
    std::size_t n = 0;
    {
      std::unique_lock lock = acquire();
      const std::size_t want =
          std::min(out.size(), block_size_ > 0 ? block_size_ : guided_block(held_, threads_));
      while (n < want && !tasks_.empty()) out[n++] = tasks_.pop();
      held_ -= n;
      if (n > 0)
        ++counters_.takes;
      else
        ++counters_.empty_takes;
    }
    return n;
  }

  void submit(int /*worker*/, std::span<const Task> tasks) override {
    if (tasks.empty()) return;
    std::vector<Task> sorted;  // pool_order: sorted outside the lock
    if (order_ != PoolOrder::Submitted) {
      sorted.assign(tasks.begin(), tasks.end());
      order_batch(sorted, order_);
      tasks = sorted;
    }
    std::unique_lock lock = acquire();
    for (const Task& t : tasks) tasks_.push(t);
    held_ += tasks.size();
    ++counters_.submits;
  }

  [[nodiscard]] SchedulerCounters counters() const override {
    std::lock_guard lock(mutex_);
    return counters_;
  }
  [[nodiscard]] const char* name() const override { return name_; }

 private:
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
