// The stage driver: runs one stage of tasks to completion on a team of workers, with
// any scheduler (schedulers/scheduler.h) and any body (core/stage/stage_body.h, the
// rule applied to a task). It owns the threads (an OpenMP team), termination, the
// accounting (busy, idle, CPU and load time, peak parallelism), tracing, pinning, the
// memory limit and the progress report; the body owns what a task means.
//
// Workers take blocks of up to `block_size` tasks from the scheduler and pass each to
// the body; the tasks the body creates are buffered and submitted after the block (the
// paper's blocking, §3.5; with block size 1, plain task-at-a-time scheduling), in one
// visit with the next take (IScheduler::submit_and_take).
//
// The initial tasks are loaded into the scheduler in chunks by the workers themselves,
// by whichever finds nothing of its own to take, so the load runs in parallel and on
// demand; while chunks are left to load, workers take only their own work
// (IScheduler::take_own). A solver thread runs beside the workers (paper §3.2) and
// detects termination: `pending` counts tasks submitted or still to be loaded and not
// yet known to be finished; it starts at the whole initial load, a worker adds a
// block's children before it submits them and takes retired tasks off in the same
// update or later (at most 1,024 owed, all before it goes idle), so pending reaches
// zero only when no task is queued, left to load or in flight. The worker that brings
// it to zero wakes the solver thread, which tells the workers to stop (the solver
// thread sleeps meanwhile: it takes no core).
//
// Task ids (core/parallel/trace.h): the i-th initial task gets iteration << 40 | i, a
// task created by worker w gets (w + 1) << 48 | iteration << 40 | its sequence number.
#pragma once

#include "core/base/clock.h"
#include "core/base/interrupt.h"
#include "core/parallel/pin_plan.h"
#include "core/parallel/trace.h"
#include "core/stage/stage_body.h"
#include "schedulers/scheduler.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace hrad {

/// How far a stage has come, as StageProgressFn sees it.
struct StageProgress {
  std::uint64_t tasks = 0;    ///< tasks examined so far, over all workers
  std::uint64_t pending = 0;  ///< tasks known and not yet examined (queued or still to load)
  std::uint64_t results = 0;  ///< what the body's end_block reported, summed over workers
  double elapsed_s = 0;       ///< since the stage started
};
using StageProgressFn = std::function<void(const StageProgress&)>;

struct StageConfig {
  int threads = 1;
  int block_size = 1;  ///< the scheduler's (0: guided; the take buffer is max_block's)
  /// > 0: every task is recorded (StageCounters::trace) under this iteration number,
  /// which also goes into the task ids.
  int trace_iteration = 0;
  /// The stage stops, unfinished (StageCounters::over_memory), when the workers'
  /// bytes_held() sum to more than this; 0: no limit.
  std::uint64_t max_bytes = 0;
  /// The stage stops, unfinished (StageCounters::timed_out), when its workers have
  /// found nothing to do for this long past this many seconds from its start; 0: no
  /// limit. For tests: a scheduler that loses a task would otherwise never let the
  /// stage end.
  double time_limit_s = 0;
  /// Worker i (and the solver thread) are bound as `plan` says, through `topology`;
  /// each worker's thread gets its previous CPU set back when the stage ends.
  /// Without a plan, workers are unbound and on node 0.
  const Topology* topology = nullptr;
  const PinPlan* plan = nullptr;
  /// Called about every `progress_interval_ms` from a thread of its own while the
  /// stage runs (never two calls at once, never after run_stage returns); workers
  /// publish their counts once per block. Empty: no such thread runs.
  StageProgressFn progress;
  int progress_interval_ms = 100;
};

/// One worker's share of a stage.
struct StageWorkerCounters {
  std::uint64_t tasks = 0;
  double busy_s = 0;  ///< wall time in the loop, less idle and loading
  double idle_s = 0;  ///< waiting for tasks
  double load_s = 0;  ///< loading initial tasks
  /// CPU time of the worker's thread over the whole stage (its own clock,
  /// core/base/clock.h), which stops while the thread waits for a core.
  double cpu_s = 0;
  double finish_s = 0;  ///< in the body's finish()
  /// When the worker entered and left its loop, in seconds from the stage's start.
  double loop_start_s = 0, loop_end_s = 0;
  std::uint64_t takes = 0;     ///< takes that returned tasks
  std::uint64_t submits = 0;   ///< submits (of children, and of initial chunks)
  const char* bound = "none";  ///< what bind_thread said (core/parallel/pin_plan.h)
  std::string bind_warning;    ///< why binding failed, if it did
};

struct StageCounters {
  std::vector<StageWorkerCounters> per_worker;
  int peak_parallelism = 0;  ///< most workers busy at once
  /// The stage's serial edges: from its start until the last worker entered its loop
  /// (the team, solver and progress threads starting), and from the last worker
  /// leaving its loop until run_stage returns, less the longest finish() (the body's).
  double start_s = 0, end_s = 0;
  /// The stage stopped because the workers' bytes_held() passed StageConfig::max_bytes
  /// (it is then unfinished); `bytes_held` is what they held when that was seen (the
  /// sum of their last reports when a limit was set).
  bool over_memory = false;
  std::uint64_t bytes_held = 0;
  bool timed_out = false;  ///< stopped at StageConfig::time_limit_s, unfinished
  /// One record per task when tracing was asked for (unordered).
  std::vector<TraceRecord> trace;
};

/// Initial tasks a worker loads into the scheduler per call (the simulator,
/// experiments/sim/, models the same).
constexpr std::size_t kStageLoadChunk = 4096;

namespace stage_detail {

/// An atomic alone on its cache line(s): the driver's shared counters are written by
/// every worker, and must not drag the lines of anything else with them.
template <class T>
struct alignas(64) PaddedAtomic {
  std::atomic<T> v;
  explicit PaddedAtomic(T x) : v(x) {}
};

/// What a worker publishes for the progress thread, once per block.
struct alignas(64) Shown {
  std::atomic<std::uint64_t> tasks{0};
  std::atomic<std::uint64_t> results{0};
};

/// Retired tasks a worker may owe the shared count before it publishes them.
constexpr std::int64_t kOwedLimit = 1024;
/// Blocks between a worker's looks at its memory (StageConfig::max_bytes).
constexpr int kMemoryCheckBlocks = 256;

/// How an idle worker waits before asking the scheduler again (run_stage.cpp).
void idle_backoff(int round);

/// The state the workers share, with the solver and progress threads: started by the
/// constructor, joined by join().
class Shared {
 public:
  Shared(IScheduler& scheduler, std::span<const Task> initial, const StageConfig& config);
  Shared(const Shared&) = delete;
  Shared& operator=(const Shared&) = delete;
  ~Shared();

  /// Loads the next chunk of initial tasks into the scheduler as `worker`; false when
  /// every chunk has been taken.
  bool load_more(int worker, StageWorkerCounters& c);
  [[nodiscard]] bool loading() const {
    return load_cursor_.v.load(std::memory_order_relaxed) < initial_.size();
  }
  /// Adds what this worker's bytes_held() grew by since its last report; sets the
  /// stop flag when the sum is over the limit.
  void report_bytes(std::uint64_t own, std::uint64_t& published);
  /// Whether the stage is to stop unfinished (interrupt, memory or time limit).
  [[nodiscard]] bool stopping() const {
    return interrupted() || stop_.v.load(std::memory_order_acquire);
  }
  /// Stops the stage here, tasks left where they are; the change of `pending` wakes
  /// the solver thread, which then sees the flag too.
  void abandon();
  /// An idle worker past the time limit stops the stage (StageCounters::timed_out).
  void check_time();
  /// Adds `delta` to pending (children added, retirements taken off); true when it
  /// brought pending to zero (the caller then calls wake_solver).
  bool add_pending(std::int64_t delta) {
    return pending_.v.fetch_add(delta, std::memory_order_acq_rel) + delta == 0;
  }
  void wake_solver() { pending_.v.notify_one(); }
  [[nodiscard]] bool done() const { return done_.v.load(std::memory_order_acquire); }
  void went_idle() { busy_.v.fetch_sub(1, std::memory_order_relaxed); }
  void went_busy();
  Shown& shown(int worker) { return shown_[static_cast<std::size_t>(worker)]; }
  [[nodiscard]] Clock::time_point start() const { return start_; }
  /// Joins the solver and progress threads; fills the stage-wide counters.
  void join(StageCounters& out);

  IScheduler& scheduler;
  const StageConfig& config;

 private:
  std::span<const Task> initial_;
  Clock::time_point start_;
  PaddedAtomic<std::int64_t> pending_;
  PaddedAtomic<bool> done_{false};
  PaddedAtomic<bool> stop_{false};
  PaddedAtomic<bool> over_memory_{false};
  PaddedAtomic<bool> timed_out_{false};
  PaddedAtomic<std::size_t> load_cursor_{0};
  PaddedAtomic<int> busy_{0};
  PaddedAtomic<int> peak_{0};
  PaddedAtomic<std::uint64_t> bytes_{0};
  std::vector<Shown> shown_;
  std::thread solver_;
  std::thread reporter_;
  std::mutex progress_mutex_;
  std::condition_variable progress_cv_;
  bool stage_over_ = false;
};

/// One worker of a stage: its loop (take, process, submit, until the stage is done) and
/// the state the loop keeps between blocks.
template <StageBody Body>
class Worker {
 public:
  Worker(Shared& sh, Body& body, int id, StageWorkerCounters& c, std::vector<TraceRecord>& trace)
      : sh_(sh),
        cfg_(sh.config),
        body_(body),
        id_(id),
        c_(c),
        trace_(trace),
        next_id_((static_cast<std::uint64_t>(id + 1) << 48) |
                 (static_cast<std::uint64_t>(sh.config.trace_iteration) << 40)),
        block_(max_block(sh.config.block_size)) {
    out_.reserve(std::min<std::size_t>(block_.size() * 8, 8192));
  }

  void run() {
    const double cpu_start = thread_cpu_seconds();
    // OpenMP keeps its threads (this one may be the caller's) for later stages and
    // later runs: a bound worker gives the thread its CPU set back when the stage ends,
    // so a run without pinning never inherits another's binding.
    const ThreadBinding unbound;
    const bool planned = cfg_.plan && static_cast<std::size_t>(id_) < cfg_.plan->refiners.size();
    const ThreadBinding& b = planned ? cfg_.plan->refiners[static_cast<std::size_t>(id_)] : unbound;
    const ScopedThreadBinding binding(cfg_.topology, b, &c_.bind_warning);
    c_.bound = binding.outcome();
    body_.begin(id_, b.node);
    const auto loop_start = Clock::now();
    idle_since_ = loop_start;
    loop();
    const auto loop_end = Clock::now();
    c_.loop_start_s = seconds_between(sh_.start(), loop_start);
    c_.loop_end_s = seconds_between(sh_.start(), loop_end);
    body_.end_loop(id_);
    if (idle_) c_.idle_s += seconds_between(idle_since_, loop_end);
    // Busy: the loop less its idle and loading time (two clock reads per stage; a pair
    // per block cost 5 % of the refinement at block size 1).
    c_.busy_s = std::max(0.0, seconds_between(loop_start, loop_end) - c_.idle_s - c_.load_s);
#pragma omp barrier
    const auto finish_start = Clock::now();
    body_.finish(id_);
    c_.finish_s = seconds_since(finish_start);
    c_.cpu_s = thread_cpu_seconds() - cpu_start;
  }

 private:
  void loop() {
    IScheduler& scheduler = sh_.scheduler;
    for (;;) {
      if (cfg_.max_bytes > 0 && ++blocks_since_check_ >= kMemoryCheckBlocks) {
        blocks_since_check_ = 0;
        sh_.report_bytes(body_.bytes_held(id_), published_);
      }
      if (sh_.stopping()) {
        sh_.abandon();
        return;
      }
      // While chunks are left to load, a worker with nothing of its own loads one rather
      // than take what another has just loaded.
      const std::size_t n = ready_ > 0      ? ready_
                            : sh_.loading() ? scheduler.take_own(id_, block_)
                                            : scheduler.take(id_, block_);
      ready_ = 0;
      if (n == 0) {
        if (!wait_for_work()) return;
        continue;
      }
      if (idle_) {  // only the idle -> busy transitions touch the shared counters
        c_.idle_s += seconds_since(idle_since_);
        idle_ = false;
        idle_round_ = 0;
        sh_.went_busy();
      }
      if (cfg_.trace_iteration > 0) {
        process_traced(n);
      } else {
        for (std::size_t i = 0; i < n; ++i) body_.process(id_, block_[i], out_);
        for (Task& t : out_) t.id = next_id_++;
      }
      end_block(n);
    }
  }

  // Nothing was taken: load a chunk of initial tasks if any is left, else publish what
  // this worker owes the count, go idle and back off. False when the stage is done.
  bool wait_for_work() {
    if (sh_.load_more(id_, c_)) return true;
    if (owed_ != 0) {  // before going idle, publish what this worker retired
      const bool last = sh_.add_pending(owed_);
      owed_ = 0;
      if (last) sh_.wake_solver();
    }
    if (sh_.done()) return false;
    if (!idle_) {
      idle_ = true;
      idle_since_ = Clock::now();
      sh_.went_idle();
    }
    if (cfg_.time_limit_s > 0 && idle_round_ >= 40) sh_.check_time();
    idle_backoff(idle_round_++);
    return true;
  }

  // The block's tasks one by one, each timed and recorded (core/parallel/trace.h).
  void process_traced(std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      const auto t_start = Clock::now();
      const std::size_t before = out_.size();
      TraceRecord rec;
      rec.id = block_[i].id;
      rec.first_child = next_id_;
      body_.process(id_, block_[i], out_);
      for (std::size_t k = before; k < out_.size(); ++k) out_[k].id = next_id_++;
      rec.start_ns = static_cast<std::uint64_t>(
          std::chrono::duration_cast<std::chrono::nanoseconds>(t_start - sh_.start()).count());
      const auto d = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t_start);
      rec.duration_ns = static_cast<std::uint32_t>(
          std::min<std::int64_t>(d.count(), TraceRecord::kBlockStart - 1));
      if (i == 0) rec.duration_ns |= TraceRecord::kBlockStart;
      rec.children = static_cast<std::uint16_t>(out_.size() - before);
      rec.worker = static_cast<std::uint8_t>(id_);
      rec.iteration = static_cast<std::uint8_t>(cfg_.trace_iteration);
      trace_.push_back(rec);
    }
  }

  // After a block of n tasks: the body's end of block, the progress figures, the
  // termination count, and the children submitted with the next take.
  void end_block(std::size_t n) {
    c_.tasks += n;
    const std::uint64_t results = body_.end_block(id_, n);
    ++c_.takes;
    if (cfg_.progress) {
      sh_.shown(id_).tasks.store(c_.tasks, std::memory_order_relaxed);
      sh_.shown(id_).results.store(results, std::memory_order_relaxed);
    }
    // The shared count changes by (children - block) per block. Children are counted
    // before anyone can see them; retirements may be published late (the count then
    // only stays above the true one, so it cannot reach zero early): a block with
    // children publishes its own change and whatever was owed, and otherwise the
    // retirements are owed until kOwedLimit or until the worker goes idle. Blocks of
    // tasks that end without children then cost no shared write.
    bool last = false;
    owed_ -= static_cast<std::int64_t>(n);
    if (!out_.empty() || owed_ <= -kOwedLimit) {
      last = sh_.add_pending(static_cast<std::int64_t>(out_.size()) + owed_);
      owed_ = 0;
    }
    if (!out_.empty()) {
      ++c_.submits;
      ready_ = sh_.scheduler.submit_and_take(id_, out_, block_, sh_.loading());
      out_.clear();
    }
    if (last) sh_.wake_solver();  // the last task retired: wake the solver thread
  }

  Shared& sh_;
  const StageConfig& cfg_;
  Body& body_;
  const int id_;
  StageWorkerCounters& c_;
  std::vector<TraceRecord>& trace_;
  std::uint64_t next_id_;  // the id of the next task this worker creates
  std::vector<Task> block_, out_;
  Clock::time_point idle_since_;
  bool idle_ = true;  // not yet counted as busy
  int idle_round_ = 0;
  std::int64_t owed_ = 0;        // retired tasks not yet taken off `pending` (<= 0)
  std::size_t ready_ = 0;        // tasks already in `block_` (taken with the last submit)
  std::uint64_t published_ = 0;  // this worker's bytes already reported
  int blocks_since_check_ = kMemoryCheckBlocks;
};

}  // namespace stage_detail

/// Runs one stage from `initial` tasks to completion (or until it stops: interrupt,
/// StageConfig::max_bytes, StageConfig::time_limit_s) and returns its counters.
/// `initial` is read (and its ids set) in place; the caller keeps it.
template <StageBody Body>
StageCounters run_stage(IScheduler& scheduler, std::span<Task> initial, const StageConfig& config,
                        Body& body) {
  for (std::size_t i = 0; i < initial.size(); ++i)
    initial[i].id = (static_cast<std::uint64_t>(config.trace_iteration) << 40) | i;
  StageCounters total;
  total.per_worker.resize(static_cast<std::size_t>(config.threads));
  std::vector<std::vector<TraceRecord>> traces(static_cast<std::size_t>(config.threads));
  {
    stage_detail::Shared shared(scheduler, initial, config);
#pragma omp parallel num_threads(config.threads)
    {
      const int id = omp_get_thread_num();
      stage_detail::Worker<Body>(shared, body, id, total.per_worker[static_cast<std::size_t>(id)],
                                 traces[static_cast<std::size_t>(id)])
          .run();
    }
    shared.join(total);
    const double stage_s = seconds_since(shared.start());
    double last_in = 0, last_out = 0, finish = 0;
    for (const StageWorkerCounters& w : total.per_worker) {
      last_in = std::max(last_in, w.loop_start_s);
      last_out = std::max(last_out, w.loop_end_s);
      finish = std::max(finish, w.finish_s);
    }
    total.start_s = last_in;
    total.end_s = std::max(0.0, stage_s - last_out - finish);
  }
  for (const auto& t : traces) total.trace.insert(total.trace.end(), t.begin(), t.end());
  return total;
}

}  // namespace hrad
