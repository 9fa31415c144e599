// timed_lock: acquire a mutex, adding the time spent waiting to `wait_s` when (and
// only when) it was contended, so lock instrumentation costs nothing uncontended.
// Used by the lock pools and by the central schedulers.
#pragma once

#include "core/base/clock.h"

#include <cstdint>
#include <mutex>

namespace hrad {

/// try_lock attempts before a contended timed_lock sleeps.
inline constexpr int kSpinTries = 256;

/// A hint to the CPU that this is a spin-wait loop.
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

/// Spins until done() returns true or about max_ns have passed; returns whether done()
/// did. Between two calls of done() it pauses 1, 2, 4, ... up to 32 times (exponential
/// back-off, so that the waiters of one cache line do not all read it at once when it
/// changes), and it reads the clock every 16 rounds. The waits of SpinMutex and
/// TeamBarrier spin this way before they sleep.
template <class Done>
bool spin_until(double max_ns, const Done& done) {
  const auto t0 = Clock::now();
  for (int round = 0;; ++round) {
    for (int i = 0; i < (1 << (round < 5 ? round : 5)); ++i) cpu_relax();
    if (done()) return true;
    if ((round & 15) == 15 && seconds_since(t0) * 1e9 > max_ns) return false;
  }
}

/// `wait_s` (and `contended`, counting contended acquisitions, when given) must only
/// be written by the caller's thread or under `m` itself.
inline std::unique_lock<std::mutex> timed_lock(std::mutex& m, double& wait_s,
                                               std::uint64_t* contended = nullptr) {
  std::unique_lock lock(m, std::try_to_lock);
  if (!lock.owns_lock()) {
    const auto t0 = Clock::now();
    // Critical sections here last well under a microsecond: spin briefly before
    // sleeping in the kernel, whose wake-up costs more than the section itself.
    for (int i = 0; i < kSpinTries && !lock.try_lock(); ++i) cpu_relax();
    if (!lock.owns_lock()) lock.lock();
    wait_s += seconds_since(t0);
    if (contended) ++*contended;
  }
  return lock;
}

}  // namespace hrad
