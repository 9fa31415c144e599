#include "experiments/sim/simulator.h"

#include <fmt/format.h>

#include <algorithm>
#include <deque>
#include <queue>
#include <stdexcept>

namespace hrad::sim {

namespace {

/// A lock or a deque: one holder at a time, granted in request order.
struct Resource {
  double free_at = 0;
  int last = -1;              ///< the processor granted last (hand-offs)
  std::deque<double> grants;  ///< grant times not yet reached: who waits (hand-offs)
};

struct Proc {
  std::vector<std::uint32_t> block;
  bool idle = false;
  double idle_since = 0;
  std::uint64_t rng = 0;
};

enum class EventKind { kTake, kBlockEnd };

struct Event {
  double t = 0;
  std::uint64_t seq = 0;  ///< ties: first scheduled, first served
  int proc = 0;
  EventKind kind = EventKind::kTake;
  bool operator>(const Event& o) const { return t != o.t ? t > o.t : seq > o.seq; }
};

/// One shared queue (stack, fifo, priority); blocked keeps one stack per processor
/// under its one lock, stealing one deque per processor with a lock each.
bool is_central(Policy p) { return p != Policy::kStealing && p != Policy::kBlocked; }
bool takes_oldest(Policy p) { return p == Policy::kFifo || p == Policy::kPriority; }

class IterationReplay {
 public:
  IterationReplay(const IterationGraph& g, const SimConfig& c, const OutsideLoop& outside,
                  IterationResult& out, const std::function<void(std::uint64_t)>& on_tasks)
      : g_(g),
        outside_(outside),
        c_(c),
        k_(c.costs),
        out_(out),
        on_tasks_(on_tasks),
        block_(static_cast<std::size_t>(c.block_size)),
        slow_(c.procs >= 2 ? c.costs.slowdown * (1 + c.costs.slowdown_per_proc * (c.procs - 1))
                           : 1.0),
        procs_(static_cast<std::size_t>(c.procs)),
        deques_(is_central(c.policy) ? 0 : procs_.size()),
        deque_locks_(c.policy == Policy::kStealing ? procs_.size() : 0),
        runs_(g.tasks.size(), 0) {
    for (std::size_t p = 0; p < procs_.size(); ++p)
      procs_[p].rng = 0x9E3779B97F4A7C15ull * static_cast<std::uint64_t>(p + 1);
  }

  void run() {
    out_.iteration = g_.iteration;
    // Processors load the initial tasks in chunks themselves, when they find nothing
    // to take (as the refiners do, core/solver/refiner.h).
    const double start = k_.start_ns;
    out_.overhead_ns += start * static_cast<double>(procs_.size());
    for (std::size_t p = 0; p < procs_.size(); ++p)
      schedule(start, static_cast<int>(p), EventKind::kTake);
    while (!events_.empty()) {
      const Event e = events_.top();
      events_.pop();
      if (e.kind == EventKind::kTake)
        take(e.proc, e.t);
      else
        block_end(e.proc, e.t);
    }
    if (done_ != g_.tasks.size())
      throw std::logic_error(fmt::format("simulation of iteration {} stalled: {} of {} tasks run",
                                         g_.iteration, done_, g_.tasks.size()));
    for (std::uint32_t r : runs_)
      if (r != 1) throw std::logic_error("simulation ran a task more or less than once");
    double end = 0;
    for (const Proc& p : procs_) end = std::max(end, p.idle_since);
    for (const Proc& p : procs_) out_.idle_ns += end - p.idle_since;
    // Outside the loop: Amdahl over the 1-thread measurement (simulator.h).
    const double s = k_.outside_serial_share, procs = static_cast<double>(procs_.size());
    const double outside = outside_.total_ns() * (s + (1 - s) / procs);
    out_.outside_ns = outside * procs;
    out_.time_ns = end + outside;
    if (c_.keep_executions) out_.executions = std::move(runs_);
  }

 private:
  void schedule(double t, int proc, EventKind kind) { events_.push(Event{t, seq_++, proc, kind}); }

  // Processor p requests `r` at `t` for `held` ns (its time); returns the release time.
  // With `handoffs` (the central lock): a waiter is granted handoff_ns after the release
  // (+ handoff_waiter_ns per further waiter); a free lock last held by another processor
  // is held handoff_ns longer (cost_model.h).
  double acquire(Resource& r, int p, double t, double held, bool handoffs = false) {
    double grant = std::max(t, r.free_at);
    if (handoffs) {
      while (!r.grants.empty() && r.grants.front() <= t) r.grants.pop_front();
      // Grants still ahead of t are the processors queued before p: at saturation also
      // about the number waiting when the lock passes to p (the queue turns over), so
      // w = max(1, queued ahead) and the hand-off costs handoff_waiter_ns × (w − 1) more.
      if (r.free_at > t)
        grant +=
            k_.handoff_ns + k_.handoff_waiter_ns *
                                static_cast<double>(std::max<std::size_t>(1, r.grants.size()) - 1);
      else if (r.last >= 0 && r.last != p)
        held += k_.handoff_ns;
      r.grants.push_back(grant);
      r.last = p;
    }
    out_.lock_wait_ns += grant - t;
    out_.overhead_ns += held;
    r.free_at = grant + held;
    return r.free_at;
  }

  // Moves up to `n` tasks from `q` into `into`: the newest (back) or the oldest (front).
  static void pop(std::deque<std::uint32_t>& q, std::size_t n, bool oldest,
                  std::vector<std::uint32_t>& into) {
    for (std::size_t i = 0; i < n; ++i) {
      if (oldest) {
        into.push_back(q.front());
        q.pop_front();
      } else {
        into.push_back(q.back());
        q.pop_back();
      }
    }
  }

  void take(int p, double t) {
    Proc& me = procs_[static_cast<std::size_t>(p)];
    me.block.clear();
    double ready = t;
    if (is_central(c_.policy)) {
      ready = acquire(lock_, p, t, k_.take_op_ns + take_central(p), true);
    } else if (c_.policy == Policy::kBlocked) {
      ready = acquire(lock_, p, t, k_.take_op_ns + take_blocked(p), true);
    } else {
      auto& own = deques_[static_cast<std::size_t>(p)];
      if (!own.empty()) {
        const std::size_t n =
            block_ > 0 ? std::min(block_, own.size()) : guided_block(own.size(), 1);
        ready = acquire(deque_locks_[static_cast<std::size_t>(p)], p, t,
                        k_.local_op_ns + static_cast<double>(n) * k_.local_task_ns);
        pop(own, n, false, me.block);
      } else if (procs_.size() > 1 && loaded_ >= g_.roots) {  // take_own while loading
        me.rng ^= me.rng << 13;
        me.rng ^= me.rng >> 7;
        me.rng ^= me.rng << 17;
        const std::size_t start = me.rng % procs_.size();
        for (std::size_t i = 0; i < procs_.size(); ++i) {
          const std::size_t v = (start + i) % procs_.size();
          if (v == static_cast<std::size_t>(p) || deques_[v].empty()) continue;
          const std::size_t half = (deques_[v].size() + 1) / 2;
          const std::size_t n = std::min(block_ > 0 ? block_ : kGuidedMaxBlock, half);
          ready = acquire(deque_locks_[v], p, t,
                          k_.steal_op_ns + static_cast<double>(n) * k_.steal_task_ns);
          pop(deques_[v], n, true, me.block);
          out_.steals += n;
          break;
        }
      }
    }
    run_block(p, ready);
  }

  // Under the central lock, `blocked` (schedulers/blocked.cpp): moves up to a block from
  // p's own stack's newest, else (once every initial task is loaded: take_own before)
  // from the oldest of the next non-empty stack, into p's block; returns the time the
  // tasks add to the hold.
  double take_blocked(int p) {
    Proc& me = procs_[static_cast<std::size_t>(p)];
    std::deque<std::uint32_t>* from = &deques_[static_cast<std::size_t>(p)];
    bool steal = false;
    const bool may_steal = loaded_ >= g_.roots;
    for (std::size_t k = 1; may_steal && from->empty() && k < procs_.size(); ++k) {
      from = &deques_[(static_cast<std::size_t>(p) + k) % procs_.size()];
      steal = true;
    }
    const std::size_t n = std::min(take_size(pooled_), from->size());
    pop(*from, n, steal, me.block);
    pooled_ -= n;
    if (steal) out_.steals += n;
    return static_cast<double>(n) * k_.take_task_ns;
  }

  // Under the central lock, stack / fifo / priority: up to a block into p's block;
  // returns the time the tasks add to the hold.
  double take_central(int p) {
    const std::size_t n = std::min(take_size(central_.size()), central_.size());
    pop(central_, n, takes_oldest(c_.policy), procs_[static_cast<std::size_t>(p)].block);
    return static_cast<double>(n) * k_.take_task_ns;
  }

  // Tasks per take from a central pool holding `pool` (block size 0: guided).
  [[nodiscard]] std::size_t take_size(std::size_t pool) const {
    return block_ > 0 ? block_ : guided_block(pool, c_.procs);
  }

  // p starts the block in me.block at `ready` (empty: goes idle, or loads a chunk).
  void run_block(int p, double ready) {
    Proc& me = procs_[static_cast<std::size_t>(p)];
    if (me.block.empty()) {
      ++out_.empty_takes;
      if (loaded_ < g_.roots) {
        schedule(load(p, ready), p, EventKind::kTake);
        return;
      }
      me.idle = true;
      me.idle_since = ready;
      idle_.push_back(p);
      return;
    }
    ++out_.takes;
    double work = 0;
    for (std::uint32_t i : me.block) {
      work += static_cast<double>(g_.tasks[i].duration_ns) * slow_ + k_.task_ns;
      ++runs_[i];
    }
    done_ += me.block.size();
    out_.tasks += me.block.size();
    if (on_tasks_) on_tasks_(me.block.size());
    out_.busy_ns += work - static_cast<double>(me.block.size()) * k_.task_ns;
    out_.overhead_ns += k_.block_ns + static_cast<double>(me.block.size()) * k_.task_ns;
    schedule(ready + work + k_.block_ns, p, EventKind::kBlockEnd);
  }

  void block_end(int p, double t) {
    Proc& me = procs_[static_cast<std::size_t>(p)];
    std::size_t created = 0;
    for (std::uint32_t i : me.block) created += g_.tasks[i].children;
    if (created == 0) {
      schedule(t, p, EventKind::kTake);
      return;
    }
    ++out_.submits;
    std::deque<std::uint32_t>* q = nullptr;
    const std::vector<std::uint32_t> block = std::move(me.block);
    me.block.clear();
    const auto push_children = [&] {
      for (std::uint32_t i : block) {
        const SimTask& task = g_.tasks[i];
        for (std::uint32_t c = 0; c < task.children; ++c) q->push_back(task.first_child + c);
      }
      if (c_.policy == Policy::kBlocked) pooled_ += created;
    };
    if (c_.policy != Policy::kStealing) {
      // submit_and_take: the children pushed and the next block taken under one
      // acquisition (the driver's visit between two blocks; schedulers/blocked.cpp,
      // schedulers/central_pool.h). `blocked` copies the batch first, outside the lock.
      const bool blocked = c_.policy == Policy::kBlocked;
      q = blocked ? &deques_[static_cast<std::size_t>(p)] : &central_;
      const double copy = blocked ? static_cast<double>(created) * k_.copy_task_ns : 0;
      out_.overhead_ns += copy;
      push_children();
      const double held = k_.submit_op_ns + static_cast<double>(created) * k_.submit_task_ns +
                          k_.take_op_ns + (blocked ? take_blocked(p) : take_central(p));
      const double release = acquire(lock_, p, t + copy, held, true);
      wake(release, further_blocks(blocked ? pooled_ : central_.size()));
      run_block(p, release);
      return;
    }
    const double release = submit(p, t, created, q);
    push_children();
    schedule(release, p, EventKind::kTake);  // the submitter takes the next block itself
    wake(release, further_blocks(q->size()));
  }

  // Blocks waiting in a pool of `size` beyond the one its submitter takes next.
  [[nodiscard]] std::size_t further_blocks(std::size_t size) const {
    const std::size_t b = take_size(size);
    return size > b ? (size - b + b - 1) / b : 0;
  }

  // Processor p submits `n` tasks at t: to the central pool, its blocked stack (both
  // under the central lock; blocked copies the batch first, outside it) or its deque.
  // Sets `q` to the queue they go to; returns the release time.
  double submit(int p, double t, std::size_t n, std::deque<std::uint32_t>*& q) {
    const auto tasks = static_cast<double>(n);
    if (c_.policy == Policy::kStealing) {
      q = &deques_[static_cast<std::size_t>(p)];
      return acquire(deque_locks_[static_cast<std::size_t>(p)], p, t,
                     k_.local_op_ns + tasks * k_.local_task_ns);
    }
    q = c_.policy == Policy::kBlocked ? &deques_[static_cast<std::size_t>(p)] : &central_;
    const double copy = c_.policy == Policy::kBlocked ? tasks * k_.copy_task_ns : 0;
    out_.overhead_ns += copy;
    return acquire(lock_, p, t + copy, k_.submit_op_ns + tasks * k_.submit_task_ns, true);
  }

  // Processor p loads the next chunk of initial tasks at t and wakes idle processors
  // for it; returns when it is done.
  double load(int p, double t) {
    const std::size_t n = std::min<std::size_t>(c_.load_chunk, g_.roots - loaded_);
    std::deque<std::uint32_t>* q = nullptr;
    const double release = submit(p, t, n, q);
    for (std::size_t i = 0; i < n; ++i) q->push_back(static_cast<std::uint32_t>(loaded_ + i));
    loaded_ += n;
    if (c_.policy == Policy::kBlocked) pooled_ += n;
    ++out_.submits;
    const std::size_t pool = c_.policy == Policy::kBlocked ? pooled_ : q->size();
    wake(release, (pool + take_size(pool) - 1) / take_size(pool));
    return release;
  }

  void wake(double at, std::size_t count) {
    for (std::size_t w = 0; w < count && !idle_.empty(); ++w) {
      Proc& other = procs_[static_cast<std::size_t>(idle_.front())];
      const double when = std::max(at, other.idle_since);
      out_.idle_ns += when - other.idle_since;
      other.idle = false;
      schedule(when, idle_.front(), EventKind::kTake);
      idle_.pop_front();
    }
  }

  const IterationGraph& g_;
  const OutsideLoop& outside_;
  const SimConfig& c_;
  const CostModel& k_;
  IterationResult& out_;
  const std::function<void(std::uint64_t)>& on_tasks_;
  const std::size_t block_;
  const double slow_;
  std::vector<Proc> procs_;
  std::deque<std::uint32_t> central_;  ///< the central pool (stack, fifo, priority)
  Resource lock_;
  std::vector<std::deque<std::uint32_t>> deques_;  ///< per processor: blocked, stealing
  std::vector<Resource> deque_locks_;
  std::deque<int> idle_;  ///< idle processors, in the order they went idle
  std::priority_queue<Event, std::vector<Event>, std::greater<>> events_;
  std::uint64_t seq_ = 0;
  std::size_t done_ = 0;
  std::size_t loaded_ = 0;  ///< initial tasks submitted so far
  std::size_t pooled_ = 0;  ///< `blocked`: tasks in all its stacks together
  std::vector<std::uint32_t> runs_;
};

}  // namespace

double SimResult::time_ns() const {
  double t = 0;
  for (const IterationResult& r : iterations) t += r.time_ns;
  return t;
}

IterationResult SimResult::totals() const {
  IterationResult s;
  for (const IterationResult& r : iterations) {
    s.time_ns += r.time_ns;
    s.busy_ns += r.busy_ns;
    s.overhead_ns += r.overhead_ns;
    s.lock_wait_ns += r.lock_wait_ns;
    s.idle_ns += r.idle_ns;
    s.outside_ns += r.outside_ns;
    s.tasks += r.tasks;
    s.takes += r.takes;
    s.empty_takes += r.empty_takes;
    s.submits += r.submits;
    s.steals += r.steals;
  }
  return s;
}

SimResult simulate(const TaskGraph& graph, const SimConfig& config,
                   const std::function<void(double)>& progress) {
  if (config.procs < 1)
    throw std::invalid_argument(fmt::format("procs must be >= 1, not {}", config.procs));
  if (config.block_size < 0)
    throw std::invalid_argument(
        fmt::format("block size must be >= 1 (or 0: guided), not {}", config.block_size));
  const double total = static_cast<double>(std::max<std::uint64_t>(1, graph.tasks()));
  std::uint64_t done = 0, reported = 0;
  const std::function<void(std::uint64_t)> on_tasks = [&](std::uint64_t n) {
    done += n;
    if (progress && done - reported >= 65536) {
      reported = done;
      progress(static_cast<double>(done) / total);
    }
  };
  SimResult result;
  const OutsideLoop none;
  for (std::size_t k = 0; k < graph.iterations.size(); ++k) {
    result.iterations.emplace_back();
    const OutsideLoop& outside = k < config.outside.size() ? config.outside[k] : none;
    IterationReplay(graph.iterations[k], config, outside, result.iterations.back(), on_tasks).run();
  }
  if (progress) progress(1.0);
  return result;
}

}  // namespace hrad::sim
