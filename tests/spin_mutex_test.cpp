// SpinMutex (core/parallel/spin_mutex.h): mutual exclusion under contention on both of
// its waiting paths (the read-only spin, and the futex sleep after SpinMutex::kSpinNs),
// and its timed_lock: nothing added uncontended, the wait added when contended.
#include "core/parallel/spin_mutex.h"
#include "tests/contend.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace hrad {
namespace {

using namespace std::chrono_literals;

// `threads` threads each add 1 to a plain counter `rounds` times under the lock, holding
// it for `hold` each time; a lost update or a torn section shows as a wrong total or as
// two threads inside at once.
void hammer(int threads, int rounds, std::chrono::microseconds hold) {
  SpinMutex m;
  std::uint64_t counter = 0;  // guarded by m
  int inside = 0;             // guarded by m
  int overlaps = 0;           // guarded by m
  std::vector<std::thread> team;
  for (int t = 0; t < threads; ++t)
    team.emplace_back([&] {
      for (int i = 0; i < rounds; ++i) {
        const std::lock_guard lock(m);
        if (++inside != 1) ++overlaps;
        ++counter;
        if (hold.count() > 0) std::this_thread::sleep_for(hold);
        --inside;
      }
    });
  for (std::thread& t : team) t.join();
  EXPECT_EQ(counter, static_cast<std::uint64_t>(threads) * static_cast<std::uint64_t>(rounds));
  EXPECT_EQ(overlaps, 0);
}

TEST(SpinMutex, ShortSectionsAreExclusive) { hammer(4, 20000, 0us); }

// Sections longer than the spin: waiters go to sleep and must be woken by unlock().
TEST(SpinMutex, LongSectionsWakeTheSleepers) { hammer(4, 40, 200us); }

TEST(SpinMutex, TryLockFailsWhileHeld) {
  SpinMutex m;
  m.lock();
  bool got = true;
  std::thread t([&] { got = m.try_lock(); });
  t.join();
  EXPECT_FALSE(got);
  m.unlock();
  EXPECT_TRUE(m.try_lock());
  m.unlock();
}

TEST(SpinMutex, TimedLockAddsOnlyContendedWaits) {
  SpinMutex m;
  double wait_s = 0.25;
  { const auto lock = timed_lock(m, wait_s); }
  EXPECT_EQ(wait_s, 0.25);  // uncontended: nothing added, not even a clock read

  const double call_s = contend(m, [&] { const auto lock = timed_lock(m, wait_s); });
  EXPECT_GT(wait_s, 0.25);
  EXPECT_LE(wait_s - 0.25, call_s);
}

}  // namespace
}  // namespace hrad
