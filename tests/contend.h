// contend(): runs a call on a second thread while this one holds a lock, for the tests
// of timed lock acquisition (tests/timed_lock_test.cpp, tests/spin_mutex_test.cpp).
#pragma once

#include "core/base/clock.h"

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

namespace hrad {

/// Runs `wait_for_it` on a second thread while this one holds `m`, and lets go 50 ms
/// after the other thread is about to lock (past any spin: a waiter sleeps by then).
/// Returns the wall seconds its call took.
template <class Mutex, class F>
double contend(Mutex& m, F&& wait_for_it) {
  std::unique_lock held(m);
  std::atomic<bool> started{false};
  double call_s = 0;
  std::thread t([&] {
    started.store(true);
    const auto t0 = Clock::now();
    wait_for_it();
    call_s = seconds_since(t0);
  });
  while (!started.load()) std::this_thread::yield();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  held.unlock();
  t.join();
  return call_s;
}

}  // namespace hrad
