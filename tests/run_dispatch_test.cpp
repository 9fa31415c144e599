// Rank 0's bookkeeping of an MPI sweep (experiments/harness/run_dispatch.h), without
// MPI: runs go out in run order to whoever is ready, a silent busy worker is taken for
// dead and its run re-queued once, a run lost twice is given up, and a late result of
// a worker taken for dead is recorded once only.
#include "experiments/harness/run_dispatch.h"

#include <gtest/gtest.h>

namespace hrad::experiment {
namespace {

std::vector<RunId> runs(int n) {
  std::vector<RunId> r;
  for (int i = 0; i < n; ++i) r.push_back({i, 0});
  return r;
}

TEST(RunDispatch, HandsRunsOutInOrderToWhoeverIsReady) {
  RunDispatch d(runs(3), {1, 2}, 10, 0);
  EXPECT_EQ(d.ready(2, 0), (RunId{0, 0}));
  EXPECT_EQ(d.ready(1, 0), (RunId{1, 0}));
  EXPECT_TRUE(d.finished(2, {0, 0}, 1));
  EXPECT_EQ(d.ready(2, 1), (RunId{2, 0}));  // worker 1's slow run holds nobody up
  EXPECT_TRUE(d.finished(2, {2, 0}, 2));
  EXPECT_EQ(d.ready(2, 2), std::nullopt);
  EXPECT_FALSE(d.over());
  EXPECT_TRUE(d.finished(1, {1, 0}, 3));
  EXPECT_EQ(d.ready(1, 3), std::nullopt);
  EXPECT_TRUE(d.over());
  EXPECT_TRUE(d.given_up().empty());
}

TEST(RunDispatch, HeartbeatsKeepABusyWorkerAlive) {
  RunDispatch d(runs(1), {1}, 5, 0);
  ASSERT_TRUE(d.ready(1, 0));
  for (double t = 1; t < 20; t += 1) {
    d.heard(1, t);
    EXPECT_TRUE(d.check(t + 0.5).empty()) << t;
  }
  EXPECT_EQ(d.running(1), (RunId{0, 0}));
}

TEST(RunDispatch, ASilentWorkersRunGoesToAnotherOnce) {
  RunDispatch d(runs(2), {1, 2}, 5, 0);
  ASSERT_EQ(d.ready(1, 0), (RunId{0, 0}));
  ASSERT_EQ(d.ready(2, 0), (RunId{1, 0}));
  d.heard(2, 4);
  EXPECT_TRUE(d.check(4.9).empty());
  const auto losses = d.check(6);
  ASSERT_EQ(losses.size(), 1u);
  EXPECT_EQ(losses[0].worker, 1);
  EXPECT_EQ(losses[0].run, (RunId{0, 0}));
  EXPECT_TRUE(losses[0].requeued);
  EXPECT_TRUE(d.dead(1));
  EXPECT_TRUE(d.finished(2, {1, 0}, 7));
  EXPECT_EQ(d.ready(2, 7), (RunId{0, 0}));  // the lost run, re-queued
  EXPECT_TRUE(d.finished(2, {0, 0}, 8));
  EXPECT_EQ(d.ready(2, 8), std::nullopt);
  EXPECT_TRUE(d.over());
  EXPECT_TRUE(d.given_up().empty());
}

TEST(RunDispatch, ARunLostTwiceIsGivenUp) {
  RunDispatch d(runs(1), {1, 2}, 5, 0);
  ASSERT_EQ(d.ready(1, 0), (RunId{0, 0}));
  EXPECT_EQ(d.ready(2, 0), std::nullopt);  // waits
  d.heard(2, 5);
  ASSERT_EQ(d.check(6).size(), 1u);
  const auto again = d.assign_waiting(6);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0], (std::pair<int, RunId>{2, {0, 0}}));
  const auto second = d.check(12);
  ASSERT_EQ(second.size(), 1u);
  EXPECT_FALSE(second[0].requeued);
  EXPECT_EQ(d.given_up(), std::vector<RunId>{(RunId{0, 0})});
  EXPECT_TRUE(d.over());
  EXPECT_TRUE(d.live_workers().empty());
}

TEST(RunDispatch, ALateResultIsRecordedOnce) {
  RunDispatch d(runs(2), {1, 2}, 5, 0);
  ASSERT_EQ(d.ready(1, 0), (RunId{0, 0}));
  ASSERT_EQ(d.ready(2, 0), (RunId{1, 0}));
  d.heard(2, 5);
  ASSERT_EQ(d.check(6).size(), 1u);  // worker 1 taken for dead, run 0 re-queued
  EXPECT_TRUE(d.finished(2, {1, 0}, 7));
  ASSERT_EQ(d.ready(2, 7), (RunId{0, 0}));  // run 0 again, on worker 2
  // Worker 1 was only slow: its result is the first, worker 2's the duplicate.
  EXPECT_TRUE(d.finished(1, {0, 0}, 8));
  EXPECT_FALSE(d.dead(1));
  EXPECT_FALSE(d.finished(2, {0, 0}, 9));
  EXPECT_EQ(d.ready(1, 9), std::nullopt);
  EXPECT_EQ(d.ready(2, 9), std::nullopt);
  EXPECT_TRUE(d.over());
}

TEST(RunDispatch, AWorkerThatNeverStartsIsLostAndTheOthersGoOn) {
  RunDispatch d(runs(1), {1, 2}, 5, 0);
  ASSERT_EQ(d.ready(2, 1), (RunId{0, 0}));
  d.heard(2, 5);
  const auto losses = d.check(5.5);
  ASSERT_EQ(losses.size(), 1u);
  EXPECT_EQ(losses[0].worker, 1);
  EXPECT_EQ(losses[0].run, std::nullopt);
  EXPECT_FALSE(d.stranded());
  EXPECT_TRUE(d.finished(2, {0, 0}, 6));
  EXPECT_EQ(d.ready(2, 6), std::nullopt);
  EXPECT_TRUE(d.over());
}

TEST(RunDispatch, NoWorkerLeftIsStranded) {
  RunDispatch d(runs(3), {1}, 5, 0);
  ASSERT_TRUE(d.ready(1, 0));
  ASSERT_EQ(d.check(6).size(), 1u);
  EXPECT_FALSE(d.over());
  EXPECT_TRUE(d.stranded());
}

TEST(RunDispatch, RejectsABadTimeoutAndUnknownRanks) {
  EXPECT_THROW(RunDispatch(runs(1), {1}, 0, 0), std::invalid_argument);
  RunDispatch d(runs(1), {1}, 5, 0);
  EXPECT_THROW(d.heard(7, 0), std::logic_error);
}

}  // namespace
}  // namespace hrad::experiment
