// Microbenchmark of scheduler cost per task (issue 4, "Speed"): every registered scheduler
// x block size {1, 10, 100} x threads {1, 2}. Each thread loops take(block) -> submit(the
// same tasks back), with no work in between, so the pool keeps its initial population and all
// time is scheduler time. At 1 thread that is the uncontended cost; at 2 threads both
// threads hammer the scheduler at once (contended; for `stealing` each worker serves
// itself from its own deque, which is the point of work stealing: its initial population
// waits in the inbox and each deque holds exactly one block, so every pop pays the
// last-item CAS on top of the fence, its worst case; no steals happen here).
//
// Counter per_task: wall time / tasks taken by all threads, in seconds (printed as e.g.
// "31.2ns"). Real time, so at 2 threads it is the aggregate throughput; the CPU cost per
// task there is about twice that.
//
// | argument | meaning                        |
// |----------|--------------------------------|
// | /B       | block size (tasks per take)    |
// | threads  | threads taking and submitting  |
#include "experiments/micro/scheduler_bench.h"

#include <benchmark/benchmark.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "schedulers/scheduler.h"

namespace {

using hrad::IScheduler;
using hrad::Task;

constexpr int kPopulation = 4096;  // tasks in the pool while the loop runs

// Created by thread 0 before the timed loop and destroyed after it; Google Benchmark
// puts a barrier at both ends of the loop, which orders these with the other threads.
std::unique_ptr<IScheduler> g_scheduler;

void BM_SchedulerCost(benchmark::State& state, const std::string& name) {
  const int block = static_cast<int>(state.range(0));
  const int worker = state.thread_index();
  if (worker == 0) {
    g_scheduler = hrad::make_scheduler(name, hrad::SchedulerConfig{state.threads(), block});
    std::mt19937 rng(1);
    std::vector<Task> initial(kPopulation);
    for (Task& t : initial) t.priority = static_cast<float>(rng() % 1000);
    g_scheduler->submit(0, initial);
  }
  std::vector<Task> buf(static_cast<std::size_t>(block));
  std::int64_t taken = 0;
  for (auto _ : state) {
    IScheduler& s = *g_scheduler;
    const std::size_t n = s.take(worker, buf);
    if (n > 0) s.submit(worker, std::span<const Task>(buf.data(), n));
    taken += static_cast<std::int64_t>(n);
  }
  if (worker == 0) {
    const hrad::SchedulerCounters c = g_scheduler->counters();
    state.counters["lock_wait_ms"] = c.lock_wait_s * 1e3;
    state.counters["steals"] = static_cast<double>(c.steals);
    g_scheduler.reset();
  }
  state.SetItemsProcessed(taken);
  state.counters["per_task"] = benchmark::Counter(
      static_cast<double>(taken), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

// Called by main (bench_main.cpp), after static initialisation: the schedulers register
// themselves then, so a static initialiser here could see only some of them.
void hrad::register_scheduler_benchmarks() {
  for (const std::string& name : scheduler_names()) {
    for (int threads : {1, 2}) {
      benchmark::RegisterBenchmark(("BM_SchedulerCost/" + name).c_str(), BM_SchedulerCost, name)
          ->Arg(1)
          ->Arg(10)
          ->Arg(100)
          ->Threads(threads)
          ->UseRealTime();
    }
  }
}
