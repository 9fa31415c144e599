#include "core/stage/run_stage.h"

#include "core/parallel/timed_lock.h"

#include <chrono>

namespace hrad::stage_detail {

// First a few pause loops (work usually appears within microseconds, and asking again
// at once would only take the scheduler's lock from the worker about to submit), then
// yields, then short sleeps, so that a worker with nothing to do stops competing for a
// core (with the solver thread, or another process) once it has waited about a
// millisecond.
void idle_backoff(int round) {
  if (round < 10) {
    for (int i = 0; i < (1 << round); ++i) cpu_relax();
  } else if (round < 40) {
    std::this_thread::yield();
  } else {
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
}

Shared::Shared(IScheduler& sched, std::span<const Task> initial, const StageConfig& cfg)
    : scheduler(sched),
      config(cfg),
      initial_(initial),
      start_(Clock::now()),
      pending_(static_cast<std::int64_t>(initial.size())),
      shown_(static_cast<std::size_t>(cfg.threads)) {
  // The solver thread (paper §3.2) detects termination: it sleeps until the last
  // in-flight task retires (the worker that brings `pending` to zero wakes it) and
  // tells the workers to stop.
  solver_ = std::thread([this] {
    if (config.plan) (void)bind_thread(config.topology, config.plan->solver, nullptr);
    for (std::int64_t v = pending_.v.load(std::memory_order_acquire); v != 0 && !stopping();
         v = pending_.v.load(std::memory_order_acquire))
      pending_.v.wait(v, std::memory_order_acquire);
    done_.v.store(true, std::memory_order_release);
  });
  // Progress (StageConfig::progress): a thread that wakes every interval, sums what the
  // workers published and reports it, until the stage is over.
  if (config.progress) {
    reporter_ = std::thread([this] {
      std::unique_lock lock(progress_mutex_);
      while (!progress_cv_.wait_for(lock, std::chrono::milliseconds(config.progress_interval_ms),
                                    [&] { return stage_over_; })) {
        StageProgress p;
        for (const Shown& s : shown_) {
          p.tasks += s.tasks.load(std::memory_order_relaxed);
          p.results += s.results.load(std::memory_order_relaxed);
        }
        const std::int64_t left = pending_.v.load(std::memory_order_relaxed);
        // `pending` counts retirements late, so it can exceed what is truly left.
        p.pending = left > 0 ? static_cast<std::uint64_t>(left) : 0;
        p.elapsed_s = seconds_since(start_);
        config.progress(p);
      }
    });
  }
}

Shared::~Shared() {
  StageCounters ignored;
  if (solver_.joinable() || reporter_.joinable()) join(ignored);
}

bool Shared::load_more(int worker, StageWorkerCounters& c) {
  if (load_cursor_.v.load(std::memory_order_relaxed) >= initial_.size()) return false;
  const std::size_t i = load_cursor_.v.fetch_add(kStageLoadChunk, std::memory_order_relaxed);
  if (i >= initial_.size()) return false;
  const auto t0 = Clock::now();
  scheduler.submit(worker, initial_.subspan(i, std::min(kStageLoadChunk, initial_.size() - i)));
  ++c.submits;
  c.load_s += seconds_since(t0);
  return true;
}

void Shared::report_bytes(std::uint64_t own, std::uint64_t& published) {
  const std::uint64_t total =
      bytes_.v.fetch_add(own - published, std::memory_order_relaxed) + own - published;
  published = own;
  if (total > config.max_bytes) {
    over_memory_.v.store(true, std::memory_order_relaxed);
    stop_.v.store(true, std::memory_order_release);
  }
}

void Shared::abandon() {
  pending_.v.store(-1, std::memory_order_release);
  pending_.v.notify_one();
}

void Shared::check_time() {
  if (seconds_since(start_) <= config.time_limit_s) return;
  timed_out_.v.store(true, std::memory_order_relaxed);
  stop_.v.store(true, std::memory_order_release);
}

void Shared::went_busy() {
  const int now_busy = busy_.v.fetch_add(1, std::memory_order_relaxed) + 1;
  int seen = peak_.v.load(std::memory_order_relaxed);
  while (now_busy > seen && !peak_.v.compare_exchange_weak(seen, now_busy)) {
  }
}

void Shared::join(StageCounters& out) {
  if (solver_.joinable()) solver_.join();
  if (reporter_.joinable()) {
    {
      const std::lock_guard lock(progress_mutex_);
      stage_over_ = true;
    }
    progress_cv_.notify_one();
    reporter_.join();
  }
  out.peak_parallelism = peak_.v.load();
  out.over_memory = over_memory_.v.load();
  out.timed_out = timed_out_.v.load();
  out.bytes_held = bytes_.v.load();
}

}  // namespace hrad::stage_detail
