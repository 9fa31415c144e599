// SpinMutex: the central schedulers' lock, for critical sections of well under a few
// microseconds taken by up to a few dozen cores.
//
// std::mutex, with timed_lock's spin of try_lock calls before it, collapsed on a
// 16-core machine: every try_lock is a compare-and-swap, which takes the lock's cache
// line from its holder while the holder works; after the spin the waiters sleep in the
// kernel, and from then on every hand-off is a futex wake-up, a few microseconds during
// which nobody holds the lock (a convoy). `blocked` at block size 10 managed about one
// acquisition per 2.7 µs at 16 threads, and its later iterations ran slower than on one
// thread.
//
// This lock is Drepper's three-state futex mutex ("Futexes are tricky", 2011, mutex 3)
// with a read-only spin in front of the sleep:
//  - state 0 free, 1 held, 2 held and a thread may sleep on it;
//  - a waiter spins on a relaxed *load* (the line stays shared in every waiter's cache
//    until the holder's release writes it), with exponential pause back-off so that the
//    waiters do not all write the line at once when it is released;
//  - after kSpinNs of spinning it marks the lock 2 and sleeps (std::atomic::wait, a
//    futex on Linux): on a loaded machine, where the holder may have lost its core, the
//    waiters stop competing with it;
//  - unlock() stores 0 and wakes one sleeper only when the state was 2, so the
//    uncontended and the spinning hand-offs cost no system call.
// Not fair: a spinning newcomer may overtake a sleeper. The schedulers' sections are
// short and frequent, where throughput matters more than order.
#pragma once

#include "core/base/clock.h"
#include "core/parallel/timed_lock.h"

#include <atomic>
#include <cstdint>

namespace hrad {

class SpinMutex {
 public:
  /// How long a waiter spins before it sleeps.
  static constexpr double kSpinNs = 20'000;

  SpinMutex() = default;
  SpinMutex(const SpinMutex&) = delete;
  SpinMutex& operator=(const SpinMutex&) = delete;

  bool try_lock() noexcept {
    std::uint32_t expected = 0;
    return state_.load(std::memory_order_relaxed) == 0 &&
           state_.compare_exchange_strong(expected, 1, std::memory_order_acquire,
                                          std::memory_order_relaxed);
  }
  void lock() noexcept {
    if (!try_lock()) lock_contended();
  }
  void unlock() noexcept {
    if (state_.exchange(0, std::memory_order_release) == 2) state_.notify_one();
  }

  /// lock() after a failed try_lock(): the read-only spin, then the sleep.
  void lock_contended() noexcept {
    if (spin_until(kSpinNs, [this] { return try_lock(); })) return;
    // Sleep: whoever takes the lock from here on holds it as 2, so its unlock wakes
    // the next sleeper (possibly none: a harmless system call).
    while (state_.exchange(2, std::memory_order_acquire) != 0)
      state_.wait(2, std::memory_order_relaxed);
  }

 private:
  std::atomic<std::uint32_t> state_{0};
};

/// timed_lock for a SpinMutex: the wait (only when contended) is added to `wait_s`.
inline std::unique_lock<SpinMutex> timed_lock(SpinMutex& m, double& wait_s) {
  if (m.try_lock()) return std::unique_lock(m, std::adopt_lock);
  const auto t0 = Clock::now();
  m.lock_contended();
  wait_s += seconds_since(t0);
  return std::unique_lock(m, std::adopt_lock);
}

}  // namespace hrad
