// LockPool: a fixed pool of mutexes indexed by a hash of an address (paper §3.4:
// "a pool of semaphores indexed by a hashing function", about twice the number of
// refiners). Two different elements may share a lock; that only costs waiting,
// never correctness, because every critical section touches one element.
//
// Waits are timed only when try_lock fails, and accumulated per worker without
// sharing cache lines, so the counters can stay on in every run.
#pragma once

#include "core/parallel/timed_lock.h"

#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace hrad {

class LockPool {
 public:
  LockPool(int locks, int workers)
      : locks_(static_cast<std::size_t>(std::max(locks, 1))),
        waits_(static_cast<std::size_t>(std::max(workers, 1))) {}

  /// Locks the mutex for `address` on behalf of `worker`; returns the held lock.
  std::unique_lock<std::mutex> lock(const void* address, int worker) {
    Wait& w = waits_[static_cast<std::size_t>(worker)];
    return timed_lock(locks_[index(address)].m, w.seconds, &w.count);
  }

  /// The mutex for `address` if it is free now; otherwise a lock that owns nothing.
  std::unique_lock<std::mutex> try_lock(const void* address) {
    return std::unique_lock(locks_[index(address)].m, std::try_to_lock);
  }

  [[nodiscard]] std::size_t size() const { return locks_.size(); }
  [[nodiscard]] double wait_seconds() const {
    double s = 0;
    for (const Wait& w : waits_) s += w.seconds;
    return s;
  }
  [[nodiscard]] double wait_seconds(int worker) const {
    return waits_[static_cast<std::size_t>(worker)].seconds;
  }
  [[nodiscard]] std::uint64_t contended() const {
    std::uint64_t n = 0;
    for (const Wait& w : waits_) n += w.count;
    return n;
  }
  void reset_counters() {
    for (Wait& w : waits_) w = Wait{};
  }

 private:
  [[nodiscard]] std::size_t index(const void* address) const {
    // Fibonacci hashing of the address; elements are >= 64 bytes apart, so drop
    // the low bits first.
    const auto a = reinterpret_cast<std::uintptr_t>(address) >> 6;
    return static_cast<std::size_t>((a * 0x9E3779B97F4A7C15ull) >> 32) % locks_.size();
  }
  struct alignas(64) Padded {
    std::mutex m;
  };
  struct alignas(64) Wait {
    double seconds = 0;
    std::uint64_t count = 0;
  };
  std::vector<Padded> locks_;
  std::vector<Wait> waits_;
};

}  // namespace hrad
