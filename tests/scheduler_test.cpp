// Every registered scheduler, driven by the stage driver refinement runs on
// (core/stage/run_stage.h), on a synthetic task tree whose task ids are encoded in the
// receiver pointer bits (never dereferenced).
#include "schedulers/scheduler.h"
#include "core/stage/run_stage.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

namespace hrad {
namespace {

Task task_for(std::uint32_t id, float priority = 0) {
  Task t;
  t.receiver = std::bit_cast<Element*>(static_cast<std::uintptr_t>(id));
  t.priority = priority;
  return t;
}
std::uint32_t id_of(const Task& t) {
  return static_cast<std::uint32_t>(std::bit_cast<std::uintptr_t>(t.receiver));
}

// A random tree in breadth-first numbering: the children of node i are the ids
// [first[i], first[i] + count[i]). Fan-out 0..4 per node, about `target` nodes in all.
struct Tree {
  std::uint32_t roots = 0;
  std::vector<std::uint32_t> first, count;
  [[nodiscard]] std::size_t size() const { return first.size(); }
};

Tree make_tree(std::uint32_t roots, std::uint32_t target, int max_depth, std::uint32_t seed) {
  Tree t;
  t.roots = roots;
  std::vector<int> depth(roots, 0);
  std::mt19937 rng(seed);
  std::uint32_t total = roots;
  for (std::uint32_t i = 0; i < total; ++i) {
    std::uint32_t fan = depth[i] < max_depth ? rng() % 5 : 0;
    fan = std::min(fan, target - total);
    t.first.push_back(total);
    t.count.push_back(fan);
    for (std::uint32_t k = 0; k < fan; ++k) depth.push_back(depth[i] + 1);
    total += fan;
  }
  return t;
}

float priority_of(std::uint32_t id) { return static_cast<float>((id * 2654435761u) % 1024); }

// Tree expansion as a stage body (core/stage/stage_body.h): each task counts its run
// and creates its children; the stage driver (core/stage/run_stage.h) that refinement
// runs on does the rest, so what is tested here is what a solve runs.
struct TreeBody {
  const Tree& tree;
  std::vector<std::atomic<std::uint32_t>>& runs;
  std::atomic<std::uint64_t> executed{0};
  std::atomic<int> begun{0};
  std::vector<std::size_t> largest;  // per worker: the largest block it was handed

  void begin(int, int) { begun.fetch_add(1, std::memory_order_relaxed); }
  void process(int, const Task& t, std::vector<Task>& out) {
    const std::uint32_t id = id_of(t);
    if (id >= tree.size()) return;  // counted as missing below
    runs[id].fetch_add(1, std::memory_order_relaxed);
    executed.fetch_add(1, std::memory_order_relaxed);
    for (std::uint32_t c = 0; c < tree.count[id]; ++c) {
      const std::uint32_t child = tree.first[id] + c;
      out.push_back(task_for(child, priority_of(child)));
    }
  }
  std::uint64_t end_block(int w, std::size_t n) {
    auto& l = largest[static_cast<std::size_t>(w)];
    l = std::max(l, n);
    return 0;
  }
  std::uint64_t bytes_held(int) { return 0; }
  void end_loop(int) {}
  void finish(int) {}
};

struct RunResult {
  std::uint64_t executed = 0;
  std::size_t largest_take = 0;
  int team_size = 0;
  bool timed_out = false;
};

RunResult run_tree(IScheduler& s, const Tree& tree, int threads, int block_size,
                   std::vector<std::atomic<std::uint32_t>>& runs) {
  std::vector<Task> initial;
  for (std::uint32_t r = 0; r < tree.roots; ++r) initial.push_back(task_for(r, priority_of(r)));
  TreeBody body{tree, runs};
  body.largest.assign(static_cast<std::size_t>(threads), 0);
  StageConfig config;
  config.threads = threads;
  config.block_size = block_size;
  config.time_limit_s = 60;  // a lost task keeps the stage from ending: fail, not hang
  const StageCounters c = run_stage(s, initial, config, body);
  return {body.executed.load(), *std::max_element(body.largest.begin(), body.largest.end()),
          body.begun.load(), c.timed_out};
}

// A thread outside the team submits roots while two workers take and expand tasks
// (IScheduler allows submit() from a thread that is no worker; the stage driver never
// does it, so this is the scheduler's contract alone, with its own loop). The last
// `foreign_roots` roots go through that thread, one by one; it holds one unit of
// `pending` until its last submit. For `stealing` these go through its inbox, never
// onto a deque another thread owns.
std::uint64_t run_tree_fed_from_outside(IScheduler& s, const Tree& tree,
                                        std::uint32_t foreign_roots,
                                        std::vector<std::atomic<std::uint32_t>>& runs) {
  const std::uint32_t loaded = tree.roots - foreign_roots;
  std::vector<Task> initial;
  for (std::uint32_t r = 0; r < loaded; ++r) initial.push_back(task_for(r, priority_of(r)));
  std::atomic<std::int64_t> pending{static_cast<std::int64_t>(loaded + 1)};
  std::atomic<std::uint64_t> executed{0};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  s.submit(0, initial);
  std::thread foreign([&] {
    for (std::uint32_t r = loaded; r < tree.roots; ++r) {
      std::this_thread::sleep_for(std::chrono::microseconds(300));
      pending.fetch_add(1, std::memory_order_acq_rel);
      s.submit(0, std::vector<Task>{task_for(r, priority_of(r))});
    }
    pending.fetch_sub(1, std::memory_order_acq_rel);
  });
#pragma omp parallel num_threads(2)
  {
    const int w = omp_get_thread_num();
    std::vector<Task> block(7), out;
    for (;;) {
      const std::size_t n = s.take(w, block);
      if (n == 0) {
        if (pending.load(std::memory_order_acquire) == 0) break;
        if (std::chrono::steady_clock::now() > deadline) break;  // a lost task: fail, not hang
        std::this_thread::yield();
        continue;
      }
      for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t id = id_of(block[i]);
        if (id >= tree.size()) continue;
        runs[id].fetch_add(1, std::memory_order_relaxed);
        executed.fetch_add(1, std::memory_order_relaxed);
        for (std::uint32_t c = 0; c < tree.count[id]; ++c)
          out.push_back(task_for(tree.first[id] + c, priority_of(tree.first[id] + c)));
      }
      pending.fetch_add(static_cast<std::int64_t>(out.size()) - static_cast<std::int64_t>(n),
                        std::memory_order_acq_rel);
      if (!out.empty()) s.submit(w, out);
      out.clear();
    }
  }
  foreign.join();
  return executed.load();
}

using TreeParam = std::tuple<std::string, int, int>;  // scheduler, threads, block size

class SchedTree : public ::testing::TestWithParam<TreeParam> {};

TEST_P(SchedTree, EveryTaskRunsExactlyOnce) {
  const auto& [name, threads, block_size] = GetParam();
  static const Tree tree = make_tree(16, 50000, 24, 12345);
  ASSERT_GE(tree.size(), 40000u);

  auto s = make_scheduler(name, SchedulerConfig{threads, block_size});
  std::vector<std::atomic<std::uint32_t>> runs(tree.size());
  const auto t0 = std::chrono::steady_clock::now();
  const RunResult r = run_tree(*s, tree, threads, block_size, runs);
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(r.team_size, threads);
  EXPECT_EQ(r.executed, tree.size());
  std::size_t wrong = 0;
  for (std::size_t id = 0; id < tree.size(); ++id)
    if (runs[id].load() != 1) ++wrong;
  EXPECT_EQ(wrong, 0u) << "tasks not run exactly once";
  EXPECT_GE(r.largest_take, 1u);
  EXPECT_LE(r.largest_take, max_block(block_size));  // the driver's buffer

  const SchedulerCounters c = s->counters();
  EXPECT_GE(c.takes * static_cast<std::uint64_t>(max_block(block_size)), tree.size());
  EXPECT_LE(c.takes, tree.size());
  EXPECT_GE(c.submits, 1u);
  EXPECT_LE(c.steals, tree.size());
  if (threads == 1) {
    EXPECT_EQ(c.steals, 0u);
    EXPECT_EQ(c.lock_wait_s, 0.0);  // one thread: never contended, so never timed
  }
  // The waits are the team's, each within the run: at most threads x its wall time
  // (the forced-contention case of the counter is tests/timed_lock_test.cpp). No
  // tolerance: both are read from the one steady clock.
  EXPECT_LE(c.lock_wait_s, threads * wall_s);
}

std::vector<TreeParam> all_tree_params() {
  std::vector<TreeParam> p;
  for (const std::string& name : scheduler_names())
    for (int threads : {1, 2, 4, 8})
      for (int block : {0, 1, 7, 100}) p.emplace_back(name, threads, block);  // 0: guided
  return p;
}

INSTANTIATE_TEST_SUITE_P(Sched, SchedTree, ::testing::ValuesIn(all_tree_params()),
                         [](const ::testing::TestParamInfo<TreeParam>& info) {
                           return std::get<0>(info.param) + "_t" +
                                  std::to_string(std::get<1>(info.param)) + "_b" +
                                  std::to_string(std::get<2>(info.param));
                         });

// A thread outside the team submits roots while two refiners run (for `stealing` these
// go through its inbox, never onto a deque another thread owns).
class SchedForeign : public ::testing::TestWithParam<std::string> {};

TEST_P(SchedForeign, SubmitsFromOutsideTheTeamRunExactlyOnce) {
  static const Tree tree = make_tree(24, 20000, 24, 777);
  auto s = make_scheduler(GetParam(), SchedulerConfig{2, 7});
  std::vector<std::atomic<std::uint32_t>> runs(tree.size());
  EXPECT_EQ(run_tree_fed_from_outside(*s, tree, 8, runs), tree.size());
  std::size_t wrong = 0;
  for (std::size_t id = 0; id < tree.size(); ++id)
    if (runs[id].load() != 1) ++wrong;
  EXPECT_EQ(wrong, 0u) << "tasks not run exactly once";
}

INSTANTIATE_TEST_SUITE_P(Sched, SchedForeign, ::testing::ValuesIn(scheduler_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

// Peak parallelism, as the stage driver counts it: with 2 workers and tasks that each
// spin ~50 us, both are busy at the same moment at some point. An attempt lasts ~20 ms,
// several scheduler time slices, so a briefly busy machine cannot hide the second worker.
struct SpinBody {
  void begin(int, int) {}
  void process(int, const Task&, std::vector<Task>&) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(50);
    while (std::chrono::steady_clock::now() < until) {
    }
  }
  std::uint64_t end_block(int, std::size_t) { return 0; }
  std::uint64_t bytes_held(int) { return 0; }
  void end_loop(int) {}
  void finish(int) {}
};

int peak_busy_once(const std::string& name) {
  constexpr int kTasks = 400;
  auto s = make_scheduler(name, SchedulerConfig{2, 1});
  std::vector<Task> initial;
  for (std::uint32_t i = 0; i < kTasks; ++i) initial.push_back(task_for(i));
  SpinBody body;
  StageConfig config;
  config.threads = 2;
  config.time_limit_s = 60;
  return run_stage(*s, initial, config, body).peak_parallelism;
}

class SchedPeak : public ::testing::TestWithParam<std::string> {};

TEST_P(SchedPeak, TwoRefinersRunAtOnce) {
  int best = 0;
  for (int attempt = 0; attempt < 10 && best < 2; ++attempt)
    best = std::max(best, peak_busy_once(GetParam()));
  EXPECT_GT(best, 1);
}

INSTANTIATE_TEST_SUITE_P(Sched, SchedPeak, ::testing::ValuesIn(scheduler_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

// Single-threaded order checks --------------------------------------------------------

std::vector<std::uint32_t> take_all_ids(IScheduler& s, std::size_t out_size = 1) {
  std::vector<std::uint32_t> ids;
  std::vector<Task> block(out_size);
  while (std::size_t n = s.take(0, block))
    for (std::size_t i = 0; i < n; ++i) ids.push_back(id_of(block[i]));
  return ids;
}

TEST(SchedOrder, PriorityHandsOutLargestFirstTiesInSubmissionOrder) {
  auto s = make_scheduler("priority", SchedulerConfig{1, 1});
  const std::vector<float> prio = {3, 1, 4, 1, 5, 9, 2, 6};
  std::vector<Task> tasks;
  for (std::uint32_t i = 0; i < prio.size(); ++i) tasks.push_back(task_for(i, prio[i]));
  s->submit(0, tasks);
  // 9(5) 6(7) 5(4) 4(2) 3(0) 2(6) 1(1) 1(3)
  EXPECT_EQ(take_all_ids(*s), (std::vector<std::uint32_t>{5, 7, 4, 2, 0, 6, 1, 3}));
}

TEST(SchedOrder, FifoInSubmissionOrderStackNewestFirst) {
  for (const char* name : {"fifo", "stack"}) {
    auto s = make_scheduler(name, SchedulerConfig{1, 1});
    std::vector<Task> a = {task_for(0), task_for(1), task_for(2)};
    std::vector<Task> b = {task_for(3), task_for(4)};
    s->submit(0, a);
    s->submit(0, b);
    const std::vector<std::uint32_t> got = take_all_ids(*s);
    if (std::string(name) == "fifo")
      EXPECT_EQ(got, (std::vector<std::uint32_t>{0, 1, 2, 3, 4}));
    else
      EXPECT_EQ(got, (std::vector<std::uint32_t>{4, 3, 2, 1, 0}));
  }
}

TEST(SchedOrder, BlockedHandsOutExactlyStacksOrder) {
  // Random batches and takes, interleaved: `blocked` (a stack of chunks) and `stack`
  // (a stack of tasks) must agree take by take, at several block sizes.
  for (int block : {1, 2, 3, 10}) {
    auto stack = make_scheduler("stack", SchedulerConfig{1, block});
    auto blocked = make_scheduler("blocked", SchedulerConfig{1, block});
    std::mt19937 rng(static_cast<std::uint32_t>(block));
    std::uint32_t next = 0;
    std::vector<Task> batch, a(16), b(16);
    for (int step = 0; step < 500; ++step) {
      if (rng() % 2 == 0) {
        batch.clear();
        for (std::uint32_t k = rng() % 6; k > 0; --k) batch.push_back(task_for(next++));
        stack->submit(0, batch);
        blocked->submit(0, batch);
      } else {
        const std::size_t want = 1 + rng() % 16;
        const std::size_t na = stack->take(0, std::span<Task>(a.data(), want));
        const std::size_t nb = blocked->take(0, std::span<Task>(b.data(), want));
        ASSERT_EQ(na, nb) << "block " << block << " step " << step;
        for (std::size_t i = 0; i < na; ++i) ASSERT_EQ(id_of(a[i]), id_of(b[i]));
      }
    }
    EXPECT_EQ(take_all_ids(*stack, 16), take_all_ids(*blocked, 16));
  }
}

TEST(SchedBlocked, AtMostBlockSizePerTake) {
  auto s = make_scheduler("blocked", SchedulerConfig{1, 5});
  std::uint32_t next = 0;
  for (std::size_t chunk : {7u, 1u, 15u}) {
    std::vector<Task> batch;
    for (std::size_t k = 0; k < chunk; ++k) batch.push_back(task_for(next++));
    s->submit(0, batch);
  }
  std::vector<Task> out(100);
  std::vector<std::size_t> sizes;
  while (std::size_t n = s->take(0, out)) sizes.push_back(n);
  EXPECT_EQ(sizes, (std::vector<std::size_t>{5, 5, 5, 5, 3}));  // takes span chunks
  std::vector<Task> small(2);
  EXPECT_EQ(s->take(0, small), 0u);
  const SchedulerCounters c = s->counters();
  EXPECT_EQ(c.takes, 5u);
  EXPECT_EQ(c.submits, 3u);
  EXPECT_EQ(c.empty_takes, 2u);
  EXPECT_EQ(c.lock_wait_s, 0.0);  // one thread: never contended
}

// The block size caps a take even when the caller's buffer is larger (the driver's
// buffer is exactly the block size, so the tree test above cannot see this).
class SchedCap : public ::testing::TestWithParam<std::string> {};

TEST_P(SchedCap, TakeHandsOutAtMostTheBlockSize) {
  for (int block : {1, 3, 7}) {
    auto s = make_scheduler(GetParam(), SchedulerConfig{1, block});
    std::vector<Task> batch;
    for (std::uint32_t i = 0; i < 40; ++i) batch.push_back(task_for(i));
    s->submit(0, batch);
    std::vector<Task> out(static_cast<std::size_t>(block) + 5);
    std::size_t total = 0;
    while (const std::size_t n = s->take(0, out)) {
      EXPECT_LE(n, static_cast<std::size_t>(block)) << "block " << block;
      total += n;
    }
    EXPECT_EQ(total, batch.size());
  }
}

INSTANTIATE_TEST_SUITE_P(Sched, SchedCap, ::testing::ValuesIn(scheduler_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

TEST(SchedGuided, BlockIsHalfTheShareBetweenOneAndTheCap) {
  EXPECT_EQ(guided_block(0, 4), 1u);
  EXPECT_EQ(guided_block(1, 4), 1u);
  EXPECT_EQ(guided_block(8, 4), 1u);
  EXPECT_EQ(guided_block(9, 4), 2u);  // ceil(9 / 8)
  EXPECT_EQ(guided_block(1000, 2), 250u);
  EXPECT_EQ(guided_block(1000, 1), 500u);
  EXPECT_EQ(guided_block(100000, 16), kGuidedMaxBlock);
  EXPECT_EQ(guided_block(100, 0), 50u);  // threads < 1 counts as one
  EXPECT_EQ(max_block(0), kGuidedMaxBlock);
  EXPECT_EQ(max_block(10), 10u);
}

// With block_size 0 every central pool hands out guided blocks: ceil(held / 2T) of the
// tasks it holds at each take, so the takes shrink as the pool drains.
class SchedGuidedPool : public ::testing::TestWithParam<std::string> {};

TEST_P(SchedGuidedPool, TakesShrinkWithThePool) {
  auto s = make_scheduler(GetParam(), SchedulerConfig{2, 0});
  std::vector<Task> batch;
  for (std::uint32_t i = 0; i < 1000; ++i) batch.push_back(task_for(i));
  s->submit(0, batch);
  std::vector<Task> out(kGuidedMaxBlock);
  std::vector<std::size_t> sizes;
  while (const std::size_t n = s->take(0, out)) sizes.push_back(n);
  std::vector<std::size_t> expected;
  for (std::size_t held = 1000; held > 0;) {
    expected.push_back(guided_block(held, 2));
    held -= expected.back();
  }
  EXPECT_EQ(sizes, expected);
  EXPECT_EQ(sizes.front(), 250u);
  EXPECT_EQ(sizes.back(), 1u);
}

INSTANTIATE_TEST_SUITE_P(Sched, SchedGuidedPool,
                         ::testing::Values("stack", "fifo", "priority", "blocked", "locality"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

TEST(SchedGuidedPool, CappedAtTheGuidedMaximum) {
  auto s = make_scheduler("blocked", SchedulerConfig{1, 0});
  std::vector<Task> batch;
  for (std::uint32_t i = 0; i < 5000; ++i) batch.push_back(task_for(i));
  s->submit(0, batch);
  std::vector<Task> out(4096);
  EXPECT_EQ(s->take(0, out), kGuidedMaxBlock);
}

// Guided stealing: the owner pops half its deque (newest first), a thief half the rest.
TEST(SchedStealing, GuidedOwnerPopsHalfThiefStealsHalf) {
  auto s = make_scheduler("stealing", SchedulerConfig{2, 0});
  std::vector<Task> out(kGuidedMaxBlock);
  s->submit(0, std::vector<Task>{task_for(0)});
  ASSERT_EQ(s->take(0, out), 1u);  // worker 0 owns deque 0
  std::vector<Task> kids;
  for (std::uint32_t i = 1; i <= 40; ++i) kids.push_back(task_for(i));
  s->submit(0, kids);
  ASSERT_EQ(s->take(0, out), 20u);  // the newest half: 40..21
  EXPECT_EQ(id_of(out[0]), 40u);
  ASSERT_EQ(s->take(1, out), 10u);  // the oldest half of the rest: 1..10
  EXPECT_EQ(id_of(out[0]), 1u);
  EXPECT_EQ(s->counters().steals, 10u);
}

TEST(SchedBlocked, TakeNeverExceedsTheCallersBuffer) {
  auto s = make_scheduler("blocked", SchedulerConfig{1, 100});
  std::vector<Task> batch;
  for (std::uint32_t i = 0; i < 10; ++i) batch.push_back(task_for(i));
  s->submit(0, batch);
  std::vector<Task> out(3);
  EXPECT_EQ(s->take(0, out), 3u);
  EXPECT_EQ(id_of(out[0]), 9u);
}

TEST(SchedStealing, ThiefTakesOldestHalfUpToBlockSize) {
  // One thread playing both workers in turn (allowed: never at the same time).
  auto s = make_scheduler("stealing", SchedulerConfig{2, 8});
  s->submit(0, std::vector<Task>{task_for(1)});  // no owner yet: the caller becomes 0
  std::vector<Task> out(8);
  ASSERT_EQ(s->take(0, out), 1u);  // worker 0 pops it from deque 0
  EXPECT_EQ(id_of(out[0]), 1u);
  std::vector<Task> kids;
  for (std::uint32_t i = 100; i < 110; ++i) kids.push_back(task_for(i));
  s->submit(0, kids);  // onto deque 0

  ASSERT_EQ(s->take(1, out), 5u);  // worker 1 steals the oldest half: 100..104
  for (std::uint32_t i = 0; i < 5; ++i) EXPECT_EQ(id_of(out[i]), 100 + i);
  ASSERT_EQ(s->take(0, out), 5u);  // the owner pops the newest: 109..105
  for (std::uint32_t i = 0; i < 5; ++i) EXPECT_EQ(id_of(out[i]), 109 - i);
  EXPECT_EQ(s->take(0, out), 0u);
  EXPECT_EQ(s->take(1, out), 0u);

  const SchedulerCounters c = s->counters();
  EXPECT_EQ(c.steals, 5u);
  EXPECT_EQ(c.takes, 3u);
  EXPECT_EQ(c.empty_takes, 2u);
  EXPECT_EQ(c.submits, 2u);
  EXPECT_EQ(c.lock_wait_s, 0.0);
}

TEST(SchedStealing, StealsAtMostBlockSize) {
  auto s = make_scheduler("stealing", SchedulerConfig{3, 2});
  std::vector<Task> out(10);
  s->submit(2, std::vector<Task>{task_for(0)});
  ASSERT_EQ(s->take(2, out), 1u);  // worker 2 owns deque 2
  std::vector<Task> kids;
  for (std::uint32_t i = 1; i <= 9; ++i) kids.push_back(task_for(i));
  s->submit(2, kids);
  EXPECT_EQ(s->take(0, out), 2u);  // half would be 5; the block caps it at 2
  EXPECT_EQ(s->take(1, out), 2u);
  EXPECT_EQ(s->counters().steals, 4u);
}

// take_own (used while initial tasks are left to load) never takes another worker's
// tasks; take then does, and every task still comes out once.
TEST(SchedOwn, TakeOwnLeavesOtherWorkersTasksAlone) {
  for (const char* name : {"blocked", "stealing"}) {
    auto s = make_scheduler(name, SchedulerConfig{2, 4});
    std::vector<Task> mine;
    for (std::uint32_t i = 1; i <= 6; ++i) mine.push_back(task_for(i));
    s->submit(0, mine);  // worker 0's own queue (stealing: the caller becomes worker 0)
    std::vector<Task> out(8);
    EXPECT_EQ(s->take_own(1, out), 0u) << name;
    std::vector<std::uint32_t> seen;
    const std::size_t stolen = s->take(1, out);
    EXPECT_GT(stolen, 0u) << name;
    for (std::size_t i = 0; i < stolen; ++i) seen.push_back(id_of(out[i]));
    for (std::size_t n; (n = s->take_own(0, out)) > 0;)
      for (std::size_t i = 0; i < n; ++i) seen.push_back(id_of(out[i]));
    std::sort(seen.begin(), seen.end());
    EXPECT_EQ(seen, (std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6})) << name;
    EXPECT_EQ(s->counters().steals, stolen) << name;
  }
  // A central pool has no queue of its own: take_own is take.
  auto stack = make_scheduler("stack", SchedulerConfig{2, 4});
  stack->submit(0, std::vector<Task>{task_for(7)});
  std::vector<Task> out(4);
  ASSERT_EQ(stack->take_own(1, out), 1u);
  EXPECT_EQ(id_of(out[0]), 7u);
}

// The driver's visit between two blocks, submit_and_take, gives exactly what submit
// followed by take (take_own when own_only) gives, for every scheduler: the same tasks
// in the same order, the same counters. `blocked` does both under one lock acquisition.
TEST(SchedSubmitAndTake, SameAsSubmitThenTake) {
  for (const std::string& name : scheduler_names())
    for (int block : {3, 0}) {  // fixed, guided
      SCOPED_TRACE(name + " block " + std::to_string(block));
      auto a = make_scheduler(name, SchedulerConfig{2, block});
      auto b = make_scheduler(name, SchedulerConfig{2, block});
      std::vector<Task> roots;
      for (std::uint32_t i = 0; i < 8; ++i) roots.push_back(task_for(i));
      a->submit(0, roots);
      b->submit(0, roots);
      std::mt19937 rng(5);
      std::uint32_t next = 100;
      std::vector<Task> out_a(max_block(block)), out_b(max_block(block));
      for (int step = 0; step < 200; ++step) {
        const int worker = step % 2;
        const bool own_only = (rng() % 4) == 0;
        std::vector<Task> kids;
        for (std::uint32_t k = rng() % 4; k > 0; --k) kids.push_back(task_for(next++));
        a->submit(worker, kids);
        const std::size_t na = own_only ? a->take_own(worker, out_a) : a->take(worker, out_a);
        const std::size_t nb = b->submit_and_take(worker, kids, out_b, own_only);
        ASSERT_EQ(na, nb) << "step " << step;
        for (std::size_t i = 0; i < na; ++i)
          ASSERT_EQ(id_of(out_a[i]), id_of(out_b[i])) << "step " << step;
      }
      const SchedulerCounters ca = a->counters(), cb = b->counters();
      EXPECT_EQ(ca.takes, cb.takes);
      EXPECT_EQ(ca.empty_takes, cb.empty_takes);
      EXPECT_EQ(ca.steals, cb.steals);
      EXPECT_EQ(ca.submits, cb.submits);
    }
}

TEST(SchedRegistry, KnowsTheFiveSchedulers) {
  const std::vector<std::string> names = scheduler_names();
  for (const char* n : {"stack", "fifo", "priority", "stealing", "blocked", "locality"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  for (const std::string& n : names) {
    auto s = make_scheduler(n, SchedulerConfig{2, 3});
    EXPECT_EQ(std::string(s->name()), n);
  }
}

TEST(SchedRegistry, UnknownNameThrowsListingNames) {
  try {
    (void)make_scheduler("no-such-scheduler", SchedulerConfig{});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no-such-scheduler"), std::string::npos) << what;
    for (const std::string& n : scheduler_names())
      EXPECT_NE(what.find(n), std::string::npos) << n << " missing from: " << what;
  }
}

}  // namespace
}  // namespace hrad
