// TeamBarrier (core/parallel/team_barrier.h): no thread leaves a round before every
// thread has reached it, and what each wrote before the barrier is seen after it, on
// both waiting paths (the spin, and the futex sleep after TeamBarrier::kSpinNs).
#include "core/parallel/team_barrier.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace hrad {
namespace {

// Each round every thread writes its slot, meets the others, checks every slot holds the
// round, and meets them again before the next round overwrites the slots. With `late`,
// thread 0 arrives 2 ms late every 8th round, so the others sleep.
int run_rounds(int threads, int rounds, bool late) {
  TeamBarrier barrier(threads);
  std::vector<int> slot(static_cast<std::size_t>(threads), -1);  // written between barriers
  std::atomic<int> wrong{0};
  std::vector<std::thread> team;
  for (int me = 0; me < threads; ++me)
    team.emplace_back([&, me] {
      for (int r = 0; r < rounds; ++r) {
        if (late && me == 0 && r % 8 == 0)
          std::this_thread::sleep_for(std::chrono::milliseconds(2));
        slot[static_cast<std::size_t>(me)] = r;
        barrier.wait();
        for (int v : slot)
          if (v != r) wrong.fetch_add(1);
        barrier.wait();
      }
    });
  for (std::thread& t : team) t.join();
  return wrong.load();
}

TEST(TeamBarrier, EveryThreadSeesEveryWriteOfItsRound) { EXPECT_EQ(run_rounds(4, 1000, false), 0); }

TEST(TeamBarrier, SleepersAreWokenByTheLastArrival) { EXPECT_EQ(run_rounds(3, 64, true), 0); }

TEST(TeamBarrier, OneThreadNeverWaits) {
  TeamBarrier barrier(1);
  for (int i = 0; i < 1000; ++i) barrier.wait();
  EXPECT_EQ(barrier.count(), 1);
  EXPECT_EQ(TeamBarrier(0).count(), 1);  // a team has at least one thread
}

}  // namespace
}  // namespace hrad
