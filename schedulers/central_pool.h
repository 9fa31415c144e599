// CentralPool<Container>: one pool of tasks under one lock, the shape shared by the
// central schedulers (stack, fifo, priority, blocked). The Container decides the
// order; the pool hands out up to block_size tasks per take().
//
// Lock waits are timed only when the lock is contended (try_lock first), so the
// instrumentation costs nothing on the uncontended path.
#pragma once

#include "core/parallel/timed_lock.h"
#include "schedulers/pool_order.h"
#include "schedulers/scheduler.h"

#include <algorithm>
#include <mutex>
#include <vector>

namespace hrad {

/// Container concept: push(const Task&), bool empty(), Task pop(), size().
template <class Container>
class CentralPool : public IScheduler {
 public:
  CentralPool(const SchedulerConfig& config, const char* name)
      : block_size_(static_cast<std::size_t>(config.block_size)),
        order_(config.pool_order),
        name_(name) {}

  std::size_t take(int /*worker*/, std::span<Task> out) override {
    const std::size_t want = std::min(out.size(), block_size_);
    std::size_t n = 0;
    {
      std::unique_lock lock = acquire();
      while (n < want && !tasks_.empty()) out[n++] = tasks_.pop();
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
    ++counters_.submits;
  }

  [[nodiscard]] SchedulerCounters counters() const override {
    std::lock_guard lock(mutex_);
    return counters_;
  }
  [[nodiscard]] const char* name() const override { return name_; }

 private:
  // counters_ is only written under mutex_, so the wait can be added to it.
  std::unique_lock<std::mutex> acquire() { return timed_lock(mutex_, counters_.lock_wait_s); }

  mutable std::mutex mutex_;
  Container tasks_;
  SchedulerCounters counters_;
  std::size_t block_size_;
  PoolOrder order_;
  const char* name_;
};

}  // namespace hrad
