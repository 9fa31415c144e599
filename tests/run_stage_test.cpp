// The stage driver (core/stage/run_stage.h) on synthetic bodies: what it promises the
// body (hook order, one thread per worker, finish after every worker's loop), its task
// ids and traces, its counters, the progress report, and the three ways a stage stops
// unfinished (memory limit, time limit). Exactly-once over every scheduler is
// tests/scheduler_test.cpp.
#include "core/stage/run_stage.h"
#include "schedulers/scheduler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace hrad {
namespace {

// Task k has children 2k+1 and 2k+2 while they are below `size` (a complete binary
// tree in heap numbering); the number rides in `priority`.
struct HeapBody {
  std::uint32_t size = 0;
  int threads = 1;
  std::vector<int> state;  // per worker: 0 before begin, 1 begun, 2 loop ended, 3 finished
  std::vector<std::thread::id> thread_of;
  std::vector<std::uint32_t> seen;  // per task number: times processed
  std::atomic<int> loops_ended{0};
  std::atomic<int> finished_early{0};  // finish() called before every end_loop
  std::vector<std::uint64_t> done;     // per worker: tasks processed
  std::atomic<int> misuse{0};          // a hook on the wrong thread or out of order
  std::uint64_t bytes_per_task = 0;    // what bytes_held() reports per task processed

  HeapBody(std::uint32_t n, int t)
      : size(n), threads(t), state(t, 0), thread_of(t), seen(n, 0), done(t, 0) {}

  void check(int w, int want_state) {
    if (state[w] != want_state || thread_of[w] != std::this_thread::get_id()) ++misuse;
  }
  void begin(int w, int) {
    if (state[w] != 0) ++misuse;
    state[w] = 1;
    thread_of[w] = std::this_thread::get_id();
  }
  void process(int w, const Task& t, std::vector<Task>& out) {
    check(w, 1);
    const auto k = static_cast<std::uint32_t>(t.priority);
    std::atomic_ref<std::uint32_t>(seen[k]).fetch_add(1, std::memory_order_relaxed);
    ++done[w];
    for (std::uint32_t c : {2 * k + 1, 2 * k + 2})
      if (c < size) {
        Task child;
        child.priority = static_cast<float>(c);
        out.push_back(child);
      }
  }
  std::uint64_t end_block(int w, std::size_t) {
    check(w, 1);
    return done[w];
  }
  std::uint64_t bytes_held(int w) { return done[w] * bytes_per_task; }
  void end_loop(int w) {
    check(w, 1);
    state[w] = 2;
    loops_ended.fetch_add(1);
  }
  void finish(int w) {
    check(w, 2);
    state[w] = 3;
    if (loops_ended.load() != threads) ++finished_early;
  }
};

std::vector<Task> roots() {
  Task t;
  t.priority = 0;
  return {t};
}

TEST(RunStage, EveryTaskOnceHooksInOrderOnTheWorkersThread) {
  for (const char* name : {"stack", "stealing", "blocked"})
    for (int threads : {1, 2, 3}) {
      SCOPED_TRACE(std::string(name) + " x" + std::to_string(threads));
      auto s = make_scheduler(name, SchedulerConfig{threads, 5});
      HeapBody body(20000, threads);
      StageConfig cfg;
      cfg.threads = threads;
      cfg.block_size = 5;
      cfg.time_limit_s = 60;
      std::vector<Task> initial = roots();
      const StageCounters c = run_stage(*s, initial, cfg, body);
      EXPECT_FALSE(c.timed_out);
      EXPECT_FALSE(c.over_memory);
      EXPECT_EQ(std::count(body.seen.begin(), body.seen.end(), 1u), 20000);
      EXPECT_EQ(body.misuse.load(), 0);
      EXPECT_EQ(body.finished_early.load(), 0);
      EXPECT_EQ(std::count(body.state.begin(), body.state.end(), 3), threads);
      // The counters: tasks per worker as the body saw them, summing to the tree.
      ASSERT_EQ(c.per_worker.size(), static_cast<std::size_t>(threads));
      std::uint64_t tasks = 0, takes = 0;
      for (int w = 0; w < threads; ++w) {
        EXPECT_EQ(c.per_worker[w].tasks, body.done[w]);
        EXPECT_GE(c.per_worker[w].cpu_s, 0.0);
        EXPECT_GE(c.per_worker[w].busy_s + c.per_worker[w].idle_s, 0.0);
        tasks += c.per_worker[w].tasks;
        takes += c.per_worker[w].takes;
      }
      EXPECT_EQ(tasks, 20000u);
      EXPECT_GE(takes * 5, tasks);  // at most a block per take
      EXPECT_LE(takes, tasks);
      EXPECT_GE(c.peak_parallelism, 1);
      EXPECT_LE(c.peak_parallelism, threads);
      EXPECT_TRUE(c.trace.empty());
    }
}

// With tracing, one record per task; the ids are the driver's scheme (initial tasks
// iteration << 40 | index, created ones (worker + 1) << 48 | iteration << 40 |
// sequence), and each record's children are exactly the records whose ids run from
// its first_child on.
TEST(RunStage, TraceRecordsEveryTaskWithItsChildren) {
  constexpr int kThreads = 2;
  constexpr std::uint32_t kSize = 3000;
  auto s = make_scheduler("stealing", SchedulerConfig{kThreads, 4});
  HeapBody body(kSize, kThreads);
  StageConfig cfg;
  cfg.threads = kThreads;
  cfg.block_size = 4;
  cfg.trace_iteration = 3;
  cfg.time_limit_s = 60;
  std::vector<Task> initial = roots();
  const StageCounters c = run_stage(*s, initial, cfg, body);
  EXPECT_EQ(initial[0].id, std::uint64_t{3} << 40);
  ASSERT_EQ(c.trace.size(), kSize);
  std::set<std::uint64_t> ids;
  for (const TraceRecord& r : c.trace) ids.insert(r.id);
  EXPECT_EQ(ids.size(), kSize);
  std::size_t children = 0, block_starts = 0;
  for (const TraceRecord& r : c.trace) {
    EXPECT_EQ(r.iteration, 3);
    EXPECT_EQ((r.id >> 40) & 0xff, 3u);
    EXPECT_LT(r.worker, kThreads);
    if (r.duration_ns & TraceRecord::kBlockStart) ++block_starts;
    for (std::uint64_t k = 0; k < r.children; ++k) {
      EXPECT_TRUE(ids.count(r.first_child + k)) << "child " << k << " of " << r.id;
      EXPECT_EQ(r.first_child >> 48, r.worker + 1u);  // created by the worker that ran r
    }
    children += r.children;
  }
  EXPECT_EQ(children, kSize - 1);  // every task but the root is someone's child
  std::uint64_t takes = c.per_worker[0].takes + c.per_worker[1].takes;
  EXPECT_EQ(block_starts, takes);
}

// Over the memory limit the stage stops early, unfinished, and says so.
TEST(RunStage, StopsOverTheMemoryLimit) {
  auto s = make_scheduler("stack", SchedulerConfig{2, 1});
  HeapBody body(1u << 20, 2);
  body.bytes_per_task = 1000;
  StageConfig cfg;
  cfg.threads = 2;
  cfg.max_bytes = 5'000'000;  // about 5,000 tasks' worth
  cfg.time_limit_s = 60;
  std::vector<Task> initial = roots();
  const StageCounters c = run_stage(*s, initial, cfg, body);
  EXPECT_TRUE(c.over_memory);
  EXPECT_FALSE(c.timed_out);
  EXPECT_GT(c.bytes_held, cfg.max_bytes);
  const std::uint64_t tasks = c.per_worker[0].tasks + c.per_worker[1].tasks;
  EXPECT_GE(tasks, 5000u);
  EXPECT_LT(tasks, 1u << 19);  // far from the whole tree: reports come every 256 blocks
  EXPECT_EQ(body.finished_early.load(), 0);  // and the hooks still end in order
}

// A scheduler that loses a task (here: the 100th submitted) keeps `pending` above zero;
// with a time limit the stage stops instead of hanging.
class Lossy : public IScheduler {
 public:
  Lossy() : inner_(make_scheduler("stack", SchedulerConfig{1, 1})) {}
  std::size_t take(int w, std::span<Task> out) override {
    std::lock_guard lock(m_);
    return inner_->take(w, out);
  }
  void submit(int w, std::span<const Task> tasks) override {
    std::lock_guard lock(m_);
    for (const Task& t : tasks)
      if (++submitted_ != 100) inner_->submit(w, std::span<const Task>(&t, 1));
  }
  [[nodiscard]] SchedulerCounters counters() const override { return inner_->counters(); }
  [[nodiscard]] const char* name() const override { return "lossy"; }

 private:
  std::mutex m_;
  std::unique_ptr<IScheduler> inner_;
  int submitted_ = 0;
};

TEST(RunStage, StopsAtTheTimeLimitWhenATaskIsLost) {
  Lossy s;
  HeapBody body(1000, 1);
  StageConfig cfg;
  cfg.time_limit_s = 0.2;
  std::vector<Task> initial = roots();
  const StageCounters c = run_stage(s, initial, cfg, body);
  EXPECT_TRUE(c.timed_out);
  EXPECT_LT(std::count(body.seen.begin(), body.seen.end(), 1u), 1000);
  // Without the loss the same stage finishes, and is not timed out.
  auto stack = make_scheduler("stack", SchedulerConfig{1, 1});
  HeapBody whole(1000, 1);
  initial = roots();
  EXPECT_FALSE(run_stage(*stack, initial, cfg, whole).timed_out);
  EXPECT_EQ(std::count(whole.seen.begin(), whole.seen.end(), 1u), 1000);
}

// The progress report: called from its own thread while the stage runs, with tasks and
// results that never fall and never pass the truth, and never after run_stage returns.
TEST(RunStage, ProgressReportsWhileTheStageRuns) {
  struct SlowHeap : HeapBody {
    using HeapBody::HeapBody;
    void process(int w, const Task& t, std::vector<Task>& out) {
      HeapBody::process(w, t, out);
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  };
  auto s = make_scheduler("fifo", SchedulerConfig{2, 2});
  SlowHeap body(2000, 2);  // about 0.2 s on two workers
  std::mutex m;
  std::vector<StageProgress> reports;
  std::atomic<bool> returned{false};
  std::atomic<int> late{0};
  StageConfig cfg;
  cfg.threads = 2;
  cfg.block_size = 2;
  cfg.time_limit_s = 60;
  cfg.progress_interval_ms = 10;
  cfg.progress = [&](const StageProgress& p) {
    if (returned.load()) ++late;
    std::lock_guard lock(m);
    reports.push_back(p);
  };
  std::vector<Task> initial = roots();
  (void)run_stage(*s, initial, cfg, body);
  returned = true;
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  EXPECT_EQ(late.load(), 0);
  ASSERT_GE(reports.size(), 3u);
  for (std::size_t i = 1; i < reports.size(); ++i) {
    EXPECT_GE(reports[i].tasks, reports[i - 1].tasks);
    EXPECT_GE(reports[i].results, reports[i - 1].results);
    EXPECT_GE(reports[i].elapsed_s, reports[i - 1].elapsed_s);
  }
  EXPECT_GT(reports.back().tasks, 0u);
  EXPECT_LE(reports.back().tasks, 2000u);
  EXPECT_LE(reports.back().results, 2000u);  // HeapBody's results: its tasks done
}

}  // namespace
}  // namespace hrad
