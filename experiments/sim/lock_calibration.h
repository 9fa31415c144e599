// Calibration of the simulator's lock hand-off costs (cost_model.h: handoff_ns,
// handoff_waiter_ns) on the machine at hand: `hrad simulate --calibrate-locks`.
//
// k threads (2 .. max) share one lock and a few lines it guards, as the central
// schedulers do (blocked's take writes the mutex word, its counters and a stack header).
// Each thread loops: lock; write the guarded lines; record the release time and its id;
// unlock; then private work of `work_ns` (a block's tasks), so that the releaser does not
// simply take the lock back. When the lock changes hands, the new holder measures the
// hand-off: from the previous holder's release to the end of its own writes of the
// guarded lines (their transfer included). With k threads and short private work,
// about k − 1 threads wait at each release, so the mean hand-off at k is the model's
// handoff_ns + handoff_waiter_ns × (k − 2), and a least-squares line over k gives both.
//
// Generic over the lock: any Lockable (lock, try_lock, unlock). std::mutex is measured
// and hrad::SpinMutex are measured the way the schedulers take them (TimedLock below).
#pragma once

#include "core/parallel/spin_mutex.h"
#include "core/parallel/timed_lock.h"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace hrad::sim {

/// A lock taken the way the schedulers take it, through its timed_lock overload:
/// std::mutex as core/parallel/timed_lock.h does (kSpinTries try_locks, then a sleeping
/// lock), hrad::SpinMutex as core/parallel/spin_mutex.h does (a try_lock, then the timed
/// read-only spin and the futex sleep). The wait timing is part of the measured cost, as
/// it is in the schedulers.
template <class Mutex>
class TimedLock {
 public:
  void lock() {
    double wait_s = 0;
    std::unique_lock l = timed_lock(m_, wait_s);
    l.release();
  }
  bool try_lock() { return m_.try_lock(); }
  void unlock() { m_.unlock(); }

 private:
  Mutex m_;
};

/// The central pools' lock before SpinMutex (revision 44e96be and earlier).
using TimedMutex = TimedLock<std::mutex>;
/// The central pools' lock since 1f17afa (schedulers/blocked.cpp, central_pool.h).
using TimedSpinMutex = TimedLock<SpinMutex>;

struct HandoffSample {
  int threads = 0;
  double handoff_ns = 0;      ///< mean release -> next holder's guarded writes done
  double change_share = 0;    ///< acquisitions by another thread than the last holder
  double ns_per_acquire = 0;  ///< wall time / acquisitions (the lock's cycle)
  std::uint64_t acquisitions = 0;
};

struct HandoffFit {
  double handoff_ns = 0;         ///< at 2 threads (one waiter)
  double handoff_waiter_ns = 0;  ///< per further waiter (0 when only 2 threads were run)
};

/// Least squares of sample.handoff_ns on (threads − 2).
HandoffFit fit_handoffs(const std::vector<HandoffSample>& samples);

/// Busy work of about `ns` nanoseconds, outside any lock.
void spin_for_ns(double ns);

/// The lock passed among `threads` threads for `duration_s` seconds.
template <class Lockable>
HandoffSample measure_handoffs(int threads, double duration_s, double work_ns) {
  using Clock = std::chrono::steady_clock;
  struct alignas(64) Line {
    std::uint64_t v[8];
  };
  struct Shared {
    Lockable lock;
    Line guarded[3];  // written by every holder (the lock's data)
    std::int64_t release_ns = 0;
    int last = -1;
  };
  Shared sh{};
  std::atomic<bool> go{false}, stop{false};
  struct alignas(64) Tally {
    double handoff_ns = 0;
    std::uint64_t changes = 0, acquisitions = 0;
  };
  std::vector<Tally> tally(static_cast<std::size_t>(threads));
  const auto epoch = Clock::now();
  const auto now_ns = [&] {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - epoch).count();
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      Tally& my = tally[static_cast<std::size_t>(t)];
      while (!go.load(std::memory_order_acquire)) cpu_relax();
      while (!stop.load(std::memory_order_relaxed)) {
        sh.lock.lock();
        for (Line& l : sh.guarded) ++l.v[0];
        if (sh.last != t && sh.last >= 0) {
          my.handoff_ns += static_cast<double>(now_ns() - sh.release_ns);
          ++my.changes;
        }
        ++my.acquisitions;
        sh.last = t;
        sh.release_ns = now_ns();
        sh.lock.unlock();
        spin_for_ns(work_ns);
      }
    });
  const auto start = Clock::now();
  go.store(true, std::memory_order_release);
  std::this_thread::sleep_for(std::chrono::duration<double>(duration_s));
  stop.store(true, std::memory_order_relaxed);
  for (std::thread& th : pool) th.join();
  const double wall_ns = std::chrono::duration<double, std::nano>(Clock::now() - start).count();
  HandoffSample s;
  s.threads = threads;
  std::uint64_t changes = 0;
  double sum = 0;
  for (const Tally& x : tally) {
    s.acquisitions += x.acquisitions;
    changes += x.changes;
    sum += x.handoff_ns;
  }
  s.handoff_ns = changes ? sum / static_cast<double>(changes) : 0;
  s.change_share =
      s.acquisitions ? static_cast<double>(changes) / static_cast<double>(s.acquisitions) : 0;
  s.ns_per_acquire = s.acquisitions ? wall_ns / static_cast<double>(s.acquisitions) : 0;
  return s;
}

/// The locks calibrate_locks() knows by name: "mutex" (TimedMutex) and "spin"
/// (TimedSpinMutex: hrad::SpinMutex, the schedulers' lock).
std::vector<std::string> calibration_lock_names();

/// measure_handoffs for threads 2 .. max_threads (capped at the hardware's threads) on
/// the named lock; throws std::invalid_argument for an unknown name.
std::vector<HandoffSample> calibrate_locks(const std::string& lock, int max_threads,
                                           double duration_s, double work_ns);

}  // namespace hrad::sim
