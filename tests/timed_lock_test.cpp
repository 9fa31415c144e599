// timed_lock and LockPool's wait counters (core/parallel/timed_lock.h, core/parallel/lock_pool.h): an
// acquisition that finds the mutex free adds exactly nothing; one that has to wait adds
// its wait (more than 0, at most the time the call took) and counts one contention, on
// the waiting worker's counter only.
#include "core/parallel/timed_lock.h"
#include "core/base/clock.h"
#include "core/parallel/lock_pool.h"
#include "tests/contend.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

namespace hrad {
namespace {

using namespace std::chrono_literals;

TEST(TimedLock, UncontendedAddsNothing) {
  std::mutex m;
  double wait_s = 0.5;  // added to, never overwritten
  std::uint64_t contended = 7;
  {
    const auto lock = timed_lock(m, wait_s, &contended);
    EXPECT_TRUE(lock.owns_lock());
  }
  EXPECT_EQ(wait_s, 0.5);  // exact: not even a clock read
  EXPECT_EQ(contended, 7u);
}

TEST(TimedLock, ContendedAddsTheWaitAndCountsIt) {
  std::mutex m;
  double wait_s = 0.5;
  std::uint64_t contended = 7;
  bool owned = false;
  const double call_s = contend(m, [&] { owned = timed_lock(m, wait_s, &contended).owns_lock(); });
  EXPECT_TRUE(owned);
  EXPECT_EQ(contended, 8u);
  EXPECT_GT(wait_s, 0.5);
  // The wait is within the call (clock reads of one steady clock: no tolerance).
  EXPECT_LE(wait_s - 0.5, call_s);
}

TEST(LockPool, WaitsAreChargedToTheWaitingWorker) {
  LockPool pool(1, 3);  // one lock: every address shares it
  int x = 0, y = 0;
  pool.lock(&x, 0).unlock();  // free: nothing recorded
  EXPECT_EQ(pool.wait_seconds(), 0.0);
  EXPECT_EQ(pool.contended(), 0u);

  std::unique_lock<std::mutex> taken = pool.try_lock(&y);
  ASSERT_TRUE(taken.owns_lock());
  std::mutex& shared = *taken.release();  // contend() holds it from here
  shared.unlock();
  contend(shared, [&] { pool.lock(&x, 2).unlock(); });
  EXPECT_EQ(pool.contended(), 1u);
  EXPECT_GT(pool.wait_seconds(2), 0.0);
  EXPECT_EQ(pool.wait_seconds(0), 0.0);
  EXPECT_EQ(pool.wait_seconds(1), 0.0);
  EXPECT_EQ(pool.wait_seconds(), pool.wait_seconds(2));
}

}  // namespace
}  // namespace hrad
