// TeamBarrier: a reusable barrier for a fixed team of threads that stays fast when the
// team has the machine to itself and does not collapse when it does not.
//
// OpenMP's own barriers (libgomp) let a waiting thread spin for about 300,000 pause
// loops, some milliseconds, before it sleeps. When the machine is loaded, the thread
// everyone waits for may have lost its core, and the spinners keep the cores it could
// run on: on a loaded 2-core machine the propagation's sweeps, a few barriers each,
// took 2.3 s instead of 0.03 s. This barrier spins on a read for at most kSpinNs, then
// sleeps on a futex (std::atomic::wait), so a waiter gives its core back within
// microseconds.
//
// wait() returns once all `count` threads have called it; the barrier can be reused at
// once (generation counting). Every write before a thread's wait() happens before every
// read after any thread's return from the same wait().
#pragma once

#include "core/base/clock.h"
#include "core/parallel/timed_lock.h"

#include <atomic>
#include <cstdint>

namespace hrad {

class TeamBarrier {
 public:
  /// How long a waiter spins before it sleeps.
  static constexpr double kSpinNs = 50'000;

  explicit TeamBarrier(int count) : count_(count < 1 ? 1 : count) {}
  TeamBarrier(const TeamBarrier&) = delete;
  TeamBarrier& operator=(const TeamBarrier&) = delete;

  void wait() {
    const std::uint32_t gen = generation_.load(std::memory_order_acquire);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == count_) {
      arrived_.store(0, std::memory_order_relaxed);  // before the release below
      generation_.fetch_add(1, std::memory_order_release);
      generation_.notify_all();
      return;
    }
    if (spin_until(kSpinNs, [&] { return generation_.load(std::memory_order_acquire) != gen; }))
      return;
    while (generation_.load(std::memory_order_acquire) == gen)
      generation_.wait(gen, std::memory_order_acquire);
  }

  [[nodiscard]] int count() const { return count_; }

 private:
  const int count_;
  alignas(64) std::atomic<int> arrived_{0};
  alignas(64) std::atomic<std::uint32_t> generation_{0};
};

}  // namespace hrad
