// Microbenchmark of the stage driver (core/stage/run_stage.h) with every registered
// scheduler: one stage over a complete binary tree of 2^17 - 1 tasks whose body does
// nothing but create the children, so the time is the driver's and the scheduler's
// (take, submit, termination count, accounting) as a refinement stage pays them. The
// same driver runs refinement; tests/run_stage_test.cpp and tests/scheduler_test.cpp
// test it with such bodies.
//
// Counter per_task: wall time of the stage / tasks, in seconds (printed as e.g.
// "45ns"); at 2 threads that is the team's aggregate rate.
//
// | argument | meaning                           |
// |----------|-----------------------------------|
// | /B       | block size (tasks per take)       |
// | /T       | threads in the team               |
#include "experiments/micro/scheduler_bench.h"

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "core/stage/run_stage.h"
#include "schedulers/scheduler.h"

namespace {

using hrad::Task;

constexpr std::uint32_t kTasks = (1u << 17) - 1;

// Task k (its number in `priority`) has children 2k+1 and 2k+2 below kTasks.
struct TreeBody {
  void begin(int, int) {}
  void process(int, const Task& t, std::vector<Task>& out) {
    const auto k = static_cast<std::uint32_t>(t.priority);
    for (std::uint32_t c = 2 * k + 1; c <= 2 * k + 2 && c < kTasks; ++c) {
      Task child;
      child.priority = static_cast<float>(c);
      out.push_back(child);
    }
  }
  std::uint64_t end_block(int, std::size_t) { return 0; }
  std::uint64_t bytes_held(int) { return 0; }
  void end_loop(int) {}
  void finish(int) {}
};

void BM_StageDriver(benchmark::State& state, const std::string& name) {
  const int block = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  std::uint64_t tasks = 0;
  for (auto _ : state) {
    auto s = hrad::make_scheduler(name, hrad::SchedulerConfig{threads, block});
    std::vector<Task> initial(1);
    TreeBody body;
    hrad::StageConfig cfg;
    cfg.threads = threads;
    cfg.block_size = block;
    const hrad::StageCounters c = hrad::run_stage(*s, initial, cfg, body);
    for (const auto& w : c.per_worker) tasks += w.tasks;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(tasks));
  state.counters["per_task"] = benchmark::Counter(
      static_cast<double>(tasks), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

void hrad::register_stage_benchmarks() {
  for (const std::string& name : scheduler_names())
    benchmark::RegisterBenchmark(("BM_StageDriver/" + name).c_str(), BM_StageDriver, name)
        ->ArgsProduct({{1, 10, 100}, {1, 2}})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
}
