#include "core/solver/refiner.h"

#include "core/base/clock.h"
#include "core/base/interrupt.h"
#include "core/hierarchy/hierarchy.h"
#include "core/parallel/timed_lock.h"
#include "core/transport/transport.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <span>
#include <thread>

namespace hrad {

namespace {
/// Initial tasks a refiner loads into the scheduler per call.
constexpr std::size_t kLoadChunk = 4096;
/// Retired tasks a refiner may owe the shared count before it publishes them.
constexpr std::int64_t kOwedLimit = 1024;
/// Blocks between a refiner's looks at its arenas' size (RefineLimits::max_bytes).
constexpr int kMemoryCheckBlocks = 256;
}  // namespace

struct alignas(64) Refiner::Worker {
  int id = 0;
  int node = 0;  ///< NUMA node of the pin plan (set_binding); 0 when unpinned
  RefineCounters c;
  /// Links accepted in the current block, stored after it (see store_links).
  std::vector<std::pair<Element*, Link>> accepted;
  std::vector<Link> batch;  ///< one receiver's accepted links, for store_links
  std::vector<Element*> started;  ///< receivers whose first link this worker stored
  std::uint64_t next_id = 0;  ///< ids of the tasks this worker creates
  std::vector<TraceRecord> trace;
  /// c.tasks and the links accepted, published once per block for the progress
  /// thread (Refiner::set_progress) when there is one; only this worker writes them.
  alignas(64) std::atomic<std::uint64_t> shown_tasks{0};
  std::atomic<std::uint64_t> shown_links{0};
};

// Stores a block's accepted links at their receivers, one lock acquisition per
// receiver: refiners working depth-first often accept several links of the same
// receiver in one block, and taking the hashed lock once per link made the link
// pool the most contended lock. Refiners still meet on the same receivers (siblings
// of one parent go to both), so with `wait` false a receiver whose lock is busy keeps
// its links in the buffer for the next call instead of waiting: nothing reads a
// receiver's links during a refinement stage. The refiner's last call waits.
void Refiner::store_links(Worker& w, bool wait) {
  auto& a = w.accepted;
  // Group by receiver, keeping each receiver's links in acceptance order. A block's
  // list is short, and stable_sort would allocate a buffer on every call.
  const auto by_receiver = [](const auto& x, const auto& y) { return x.first < y.first; };
  if (a.size() <= 64) {
    for (std::size_t i = 1; i < a.size(); ++i)
      for (std::size_t j = i; j > 0 && by_receiver(a[j], a[j - 1]); --j) std::swap(a[j], a[j - 1]);
  } else {
    std::stable_sort(a.begin(), a.end(), by_receiver);
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < a.size();) {
    Element* r = a[i].first;
    std::size_t j = i;
    while (j < a.size() && a[j].first == r) ++j;
    auto guard = wait ? link_locks_.lock(r, w.id) : link_locks_.try_lock(r);
    if (guard.owns_lock()) {
      w.batch.clear();
      for (std::size_t k = i; k < j; ++k) w.batch.push_back(a[k].second);
      if (hierarchy_.store_links(*r, w.batch, w.id)) w.started.push_back(r);
    } else {
      for (std::size_t k = i; k < j; ++k) a[kept++] = a[k];
    }
    i = j;
  }
  a.resize(kept);
}

Refiner::Refiner(Hierarchy& hierarchy, const Transport& transport, const IOracle& oracle,
                 RefineLimits limits, LockPool& element_locks, LockPool& link_locks)
    : hierarchy_(hierarchy),
      transport_(transport),
      oracle_(oracle),
      limits_(limits),
      element_locks_(element_locks),
      link_locks_(link_locks) {}

bool Refiner::splittable(const Element& e) const {
  if (e.is_cluster()) return e.child_count > 0;
  return e.area > limits_.min_area && Hierarchy::can_subdivide(e);
}

// Which element to refine when both could be: the larger one. Surfaces compare
// areas; when a cluster is involved, bounding-sphere radii. Sizes equal to
// round-off (mirror-image elements, or the same scene at another scale) are a
// tie, broken by id, so the choice does not depend on the scene's units.
static bool refine_receiver(const Element& r, const Element& s) {
  const bool surfaces = !r.is_cluster() && !s.is_cluster();
  const double a = surfaces ? r.area : r.radius();
  const double b = surfaces ? s.area : s.radius();
  if (std::abs(a - b) > 1e-9 * std::max(a, b)) return a > b;
  return r.id >= s.id;
}

/// Whether to split the receiver: when it can be split and is the larger of two that can.
static bool split_receiver(const Element& r, const Element& s, bool can_r, bool can_s) {
  return can_r && (!can_s || refine_receiver(r, s));
}

/// True when the oracle's decision on `est` depends on its visibility estimate: it
/// decides otherwise for one of V = 0, 1/2 and 1 (the classes bf and error tell apart:
/// hidden, partly and wholly visible).
static bool depends_on_visibility(const IOracle& oracle, LinkEstimate est,
                                  const OracleThresholds& th) {
  Decision d[3];
  const double vs[3] = {0.0, 0.5, 1.0};
  for (int i = 0; i < 3; ++i) {
    est.visibility = vs[i];
    d[i] = oracle.judge(est, th).decision;
  }
  return d[0] != d[1] || d[1] != d[2];
}

// A task's verdict: drop it, accept its link, or split one end (the receiver when
// split_r); `error` is the oracle's estimate, handed on to the children as priority.
struct Refiner::Step {
  bool drop = false;
  bool accept = false;
  bool split_r = false;
  double error = 0;
};

void Refiner::process(const Task& task, Worker& w, std::vector<Task>& out) {
  Element& r = *task.receiver;
  Element& s = *task.source;
  ++w.c.tasks;
  ++(r.home_node == w.node ? w.c.tasks_local : w.c.tasks_remote);  // NUMA report
  LinkEstimate est{&r, &s, task.form_factor, task.visibility, 0};
  PairClass pc = PairClass::Regular;
  if (!task.evaluated) {
    pc = transport_.classify(r, s);
    if (pc == PairClass::Cull) {
      ++w.c.culled;
      w.c.rays_skipped += static_cast<std::uint64_t>(transport_.rays_per_link());
      return;
    }
  }
  const Step step =
      pc == PairClass::Regular ? judge(task, w, est) : open_pair(pc, task, w, est);
  if (step.drop) return;
  if (step.accept) {
    w.accepted.emplace_back(&r, Link{&s, static_cast<float>(est.form_factor),
                                      static_cast<float>(est.visibility)});
    if (task.evaluated) ++w.c.links_kept; else ++w.c.links_created;
    return;
  }
  Element& split = step.split_r ? r : s;
  const std::span<Element> kids =
      split.is_cluster() ? split.child_span() : hierarchy_.subdivide(split, w.id, element_locks_);
  const float child_priority = static_cast<float>(step.error / std::max<std::size_t>(kids.size(), 1));
  for (Element& c : kids) {
    Task t;
    t.id = w.next_id++;
    t.receiver = step.split_r ? &c : &r;
    t.source = step.split_r ? &s : &c;
    t.priority = child_priority;
    out.push_back(t);
  }
}

// A pair that must be opened (one end inside the other, or a near-field pair with a
// cluster end): the end that can be opened is, and a pair that cannot be opened is
// accepted with its transport (near field) or carries none (overlapping).
Refiner::Step Refiner::open_pair(PairClass pc, const Task& task, Worker& w, LinkEstimate& est) {
  const Element& r = *est.receiver;
  const Element& s = *est.source;
  const bool can_r = splittable(r), can_s = splittable(s);
  Step st;
  st.error = task.priority;
  if (pc == PairClass::ReceiverInside) {
    st.split_r = false;  // s contains r: open s
    st.accept = !can_s;
  } else if (pc == PairClass::SourceInside) {
    st.split_r = true;
    st.accept = !can_r;
  } else {
    st.split_r = split_receiver(r, s, can_r, can_s);
    st.accept = !can_r && !can_s;
  }
  if (st.accept && (pc == PairClass::ReceiverInside || pc == PairClass::SourceInside)) {
    // An element overlapping itself that cannot be opened carries no transport.
    ++w.c.culled;
    st.drop = true;
    return st;
  }
  if (st.accept) {
    est.form_factor = transport_.form_factor(r, s);
    est.visibility = est.form_factor > 0
                         ? transport_.visibility(r, s, w.c.rays_cast, w.c.rays_skipped)
                         : 0.0;
  }
  return st;
}

// A regular pair (or a reloaded link): its form factor and visibility if not known yet,
// then the oracle's verdict.
Refiner::Step Refiner::judge(const Task& task, Worker& w, LinkEstimate& est) {
  const Element& r = *est.receiver;
  const Element& s = *est.source;
  const bool can_r = splittable(r), can_s = splittable(s);
  Step st;  // a straddling pair's children get priority 0
  if (!task.evaluated) {
    est.form_factor = transport_.form_factor(r, s);
    if (est.form_factor <= 0) {
      // classify() found part of each element in front of the other. Two
      // surfaces are integrated over the part of the receiver in front of the
      // source (Transport::form_factor), so a zero there means little light, and a
      // surface facing a cluster whose centre direction gives zero has members that
      // may still see it: such a pair is split while it can be (the cluster end
      // first), and only then dropped. A pair of clusters is dropped at once:
      // splitting those to the smallest elements made 13 of the cabin's 78 M tasks
      // (and most of its 40 M culled ones) for no measurable light
      // (docs/energy-budget.md).
      if ((!can_r && !can_s) || (r.is_cluster() && s.is_cluster())) {
        ++w.c.culled;
        w.c.rays_skipped += static_cast<std::uint64_t>(transport_.rays_per_link());
        st.drop = true;
        return st;
      }
      if (r.is_cluster() != s.is_cluster())
        st.split_r = r.is_cluster() ? can_r : !can_s;  // the cluster end when it can
      else
        st.split_r = split_receiver(r, s, can_r, can_s);
      return st;
    }
    est.visibility = transport_.visibility(r, s, w.c.rays_cast, w.c.rays_skipped);
  }
  if (oracle_.needs_spread()) est.form_factor_spread = transport_.form_factor_spread(r, s);
  const OracleThresholds th{limits_.eps_power, limits_.mean_irradiance};
  Verdict v = oracle_.judge(est, th);
  if ((can_r || can_s) && limits_.independent_estimates &&
      depends_on_visibility(oracle_, est, th)) {
    // Decide on the first rays (a reloaded link may hold the second), and if the
    // link is accepted, estimate its visibility from the second (RefineLimits).
    if (task.evaluated) {
      est.visibility = transport_.visibility(r, s, w.c.rays_cast, w.c.rays_skipped, 0);
      v = oracle_.judge(est, th);
    }
    if (v.decision == Decision::Accept)
      est.visibility = transport_.visibility(r, s, w.c.rays_cast, w.c.rays_skipped, 1);
  }
  st.error = v.error;
  if (v.decision == Decision::Accept || (!can_r && !can_s)) {
    st.accept = true;
  } else {
    st.split_r = split_receiver(r, s, can_r, can_s);
  }
  return st;
}

namespace {

/// An atomic alone on its cache line(s): the driver's shared counters are written by
/// every refiner, and must not drag the lines of anything else with them.
template <class T>
struct alignas(64) PaddedAtomic {
  std::atomic<T> v;
  explicit PaddedAtomic(T x) : v(x) {}
};

/// How an idle refiner waits before asking the scheduler again: first a few pause
/// loops (work usually appears within microseconds, and asking again at once would
/// only take the scheduler's lock from the refiner about to submit), then yields,
/// then short sleeps, so that a refiner with nothing to do stops competing for a
/// core (with the solver thread, or another process) once it has waited about a
/// millisecond.
void idle_backoff(int round) {
  if (round < 10) {
    for (int i = 0; i < (1 << round); ++i) cpu_relax();
  } else if (round < 40) {
    std::this_thread::yield();
  } else {
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
}

}  // namespace

RefineCounters Refiner::run(IScheduler& scheduler, std::span<Task> initial, int threads,
                            int block_size, int trace_iteration) {
  const bool tracing = trace_iteration > 0;
  for (std::size_t i = 0; i < initial.size(); ++i)
    initial[i].id = (static_cast<std::uint64_t>(trace_iteration) << 40) | i;
  const auto stage_start = Clock::now();
  // `pending` counts tasks submitted (or still to be loaded) and not yet known to be
  // finished. It starts at the whole initial load, so it cannot reach zero before every
  // initial task was loaded and finished. A block's children are added before they are
  // submitted, and its retired tasks are taken off then or later (see the loop), so it
  // stays above zero while any task is queued, left to load, or in flight.
  PaddedAtomic<std::int64_t> pending(static_cast<std::int64_t>(initial.size()));
  PaddedAtomic<bool> done(false);
  PaddedAtomic<std::size_t> load_cursor(0);  // next initial task to load
  PaddedAtomic<int> busy(0);                 // refiners not idle
  PaddedAtomic<int> peak(0);
  // Arena bytes of all refiners, each adding what its own arenas grew by every
  // kMemoryCheckBlocks blocks (the arenas' counters are their owners' alone), and
  // whether that passed limits_.max_bytes.
  PaddedAtomic<std::uint64_t> arena_bytes(0);
  PaddedAtomic<bool> over_memory(false);
  std::vector<Worker> workers(static_cast<std::size_t>(threads));
  const std::span<const Task> all(initial);

  // Loads the next chunk of initial tasks into the scheduler, as `worker`; false when
  // every chunk has been taken. A refiner loads when it finds nothing of its own to
  // take, so loading runs in parallel and only as fast as the work needs it (paper §3.2 has a
  // solver thread load them; on P cores for P refiners that thread would compete with
  // the refiners for a core while they wait for it).
  auto load_more = [&](Worker& w) {
    if (load_cursor.v.load(std::memory_order_relaxed) >= all.size()) return false;
    const std::size_t i = load_cursor.v.fetch_add(kLoadChunk, std::memory_order_relaxed);
    if (i >= all.size()) return false;
    const auto t0 = Clock::now();
    scheduler.submit(w.id, all.subspan(i, std::min(kLoadChunk, all.size() - i)));
    ++w.c.submits;
    w.c.load_s += seconds_since(t0);
    return true;
  };

  // The solver thread (paper §3.2) detects termination: it sleeps until the last
  // in-flight task retires (the refiner that brings `pending` to zero wakes it) and
  // tells the refiners to stop.
  std::thread solver([&] {
    if (plan_) (void)bind_thread(topology_, plan_->solver, nullptr);
    for (std::int64_t v = pending.v.load(std::memory_order_acquire);
         v != 0 && !interrupted() && !over_memory.v.load(std::memory_order_acquire);
         v = pending.v.load(std::memory_order_acquire))
      pending.v.wait(v, std::memory_order_acquire);
    done.v.store(true, std::memory_order_release);
  });

  // Progress during the stage (set_progress): a thread that wakes every interval,
  // sums what the refiners published and reports it, until the stage is over.
  const bool report = static_cast<bool>(progress_);
  std::mutex progress_mutex;
  std::condition_variable progress_cv;
  bool stage_over = false;
  std::thread reporter;
  if (report) {
    reporter = std::thread([&] {
      std::unique_lock lock(progress_mutex);
      while (!progress_cv.wait_for(lock, std::chrono::milliseconds(progress_interval_ms_),
                                   [&] { return stage_over; })) {
        RefineProgress p;
        for (const Worker& w : workers) {
          p.tasks += w.shown_tasks.load(std::memory_order_relaxed);
          p.links += w.shown_links.load(std::memory_order_relaxed);
        }
        const std::int64_t left = pending.v.load(std::memory_order_relaxed);
        // `pending` counts retirements late, so it can exceed what is truly left.
        p.pending = left > 0 ? static_cast<std::uint64_t>(left) : 0;
        p.elapsed_s = seconds_since(stage_start);
        progress_(p);
      }
    });
  }

#pragma omp parallel num_threads(threads)
  {
    Worker& w = workers[static_cast<std::size_t>(omp_get_thread_num())];
    w.id = omp_get_thread_num();
    const double cpu_start = thread_cpu_seconds();
    // OpenMP keeps its threads (this one may be the caller's) for later stages and
    // later runs: a bound refiner gives the thread its CPU set back when the stage
    // ends, so a run without pinning never inherits another's binding.
    const ThreadBinding unbound;
    const bool planned = plan_ && static_cast<std::size_t>(w.id) < plan_->refiners.size();
    const ThreadBinding& b = planned ? plan_->refiners[static_cast<std::size_t>(w.id)] : unbound;
    w.node = b.node;
    const ScopedThreadBinding binding(topology_, b, &w.c.bind_warning);
    w.c.bound = binding.outcome();
    w.next_id = (static_cast<std::uint64_t>(w.id + 1) << 48) |
                (static_cast<std::uint64_t>(trace_iteration) << 40);
    std::vector<Task> block(static_cast<std::size_t>(block_size));
    std::vector<Task> out;
    out.reserve(static_cast<std::size_t>(block_size) * 8);
    const auto loop_start = Clock::now();
    Clock::time_point idle_since = loop_start;
    bool idle = true;  // not yet counted in `busy`
    int idle_round = 0;
    std::int64_t owed = 0;  // retired tasks not yet taken off `pending` (<= 0)
    std::size_t ready = 0;  // tasks already in `block` (taken with the last submit)
    // While chunks are left to load, a refiner with nothing of its own loads one
    // rather than take what another has just loaded.
    const auto loading = [&] { return load_cursor.v.load(std::memory_order_relaxed) < all.size(); };
    std::uint64_t published = 0;  // this refiner's arena bytes already in arena_bytes
    int blocks_since_check = kMemoryCheckBlocks;
    for (;;) {
      if (limits_.max_bytes > 0 && ++blocks_since_check >= kMemoryCheckBlocks) {
        blocks_since_check = 0;
        const std::uint64_t own = hierarchy_.arena(w.id).bytes_used() +
                                  hierarchy_.link_arena(w.id).bytes_used() +
                                  hierarchy_.link_staging_arena(w.id).bytes_used();
        const std::uint64_t total =
            arena_bytes.v.fetch_add(own - published, std::memory_order_relaxed) + own - published;
        published = own;
        if (total > limits_.max_bytes) over_memory.v.store(true, std::memory_order_release);
      }
      if (interrupted() || over_memory.v.load(std::memory_order_acquire)) {
        // Stop here, tasks left where they are (core/base/interrupt.h, max_bytes): the
        // stage is abandoned. The change of `pending` wakes the solver thread, which
        // then sees the flag too.
        pending.v.store(-1, std::memory_order_release);
        pending.v.notify_one();
        break;
      }
      const std::size_t n = ready > 0   ? ready
                            : loading() ? scheduler.take_own(w.id, block)
                                        : scheduler.take(w.id, block);
      ready = 0;
      if (n == 0) {
        if (load_more(w)) continue;
        if (owed != 0) {  // before going idle, publish what this refiner retired
          const bool last = pending.v.fetch_add(owed, std::memory_order_acq_rel) + owed == 0;
          owed = 0;
          if (last) pending.v.notify_one();
        }
        if (done.v.load(std::memory_order_acquire)) break;
        if (!idle) {
          idle = true;
          idle_since = Clock::now();
          busy.v.fetch_sub(1, std::memory_order_relaxed);
        }
        idle_backoff(idle_round++);
        continue;
      }
      if (idle) {
        // Only the idle -> busy transitions touch the shared counters.
        w.c.idle_s += seconds_since(idle_since);
        idle = false;
        idle_round = 0;
        const int now_busy = busy.v.fetch_add(1, std::memory_order_relaxed) + 1;
        int seen = peak.v.load(std::memory_order_relaxed);
        while (now_busy > seen && !peak.v.compare_exchange_weak(seen, now_busy)) {
        }
      }
      if (tracing) {
        for (std::size_t i = 0; i < n; ++i) {
          const auto t_start = Clock::now();
          const std::size_t before = out.size();
          const std::uint64_t first_child = w.next_id;
          process(block[i], w, out);
          TraceRecord rec;
          rec.id = block[i].id;
          rec.first_child = first_child;
          rec.start_ns = static_cast<std::uint64_t>(
              std::chrono::duration_cast<std::chrono::nanoseconds>(t_start - stage_start).count());
          const auto d = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t_start);
          rec.duration_ns = static_cast<std::uint32_t>(
              std::min<std::int64_t>(d.count(), TraceRecord::kBlockStart - 1));
          if (i == 0) rec.duration_ns |= TraceRecord::kBlockStart;
          rec.children = static_cast<std::uint16_t>(out.size() - before);
          rec.worker = static_cast<std::uint8_t>(w.id);
          rec.iteration = static_cast<std::uint8_t>(trace_iteration);
          w.trace.push_back(rec);
        }
      } else {
        for (std::size_t i = 0; i < n; ++i) process(block[i], w, out);
      }
      store_links(w, false);
      ++w.c.takes;
      if (report) {
        w.shown_tasks.store(w.c.tasks, std::memory_order_relaxed);
        w.shown_links.store(w.c.links_created + w.c.links_kept, std::memory_order_relaxed);
      }
      // The shared count changes by (children - block) per block. Children are counted
      // before anyone can see them; retirements may be published late (the count then
      // only stays above the true one, so it cannot reach zero early): a block with
      // children publishes its own change and whatever was owed, and otherwise the
      // retirements are owed until kOwedLimit or until the refiner goes idle. Blocks of
      // reloaded links, which are accepted again without children, then cost no shared
      // write.
      bool last = false;
      owed -= static_cast<std::int64_t>(n);
      if (!out.empty() || owed <= -kOwedLimit) {
        const std::int64_t delta = static_cast<std::int64_t>(out.size()) + owed;
        owed = 0;
        last = pending.v.fetch_add(delta, std::memory_order_acq_rel) + delta == 0;
      }
      if (!out.empty()) {
        // One visit to the pool between two blocks: the children go in, the next
        // block comes out (IScheduler::submit_and_take).
        ++w.c.submits;
        ready = scheduler.submit_and_take(w.id, out, block, loading());
        out.clear();
      }
      if (last) pending.v.notify_one();  // the last task retired: wake the solver thread
    }
    const auto loop_end = Clock::now();
    store_links(w, true);  // whatever a busy lock made it defer
    if (idle) w.c.idle_s += seconds_between(idle_since, loop_end);
    // Busy: the loop less its idle and loading time (two clock reads per stage; a pair
    // per block cost 5 % of the refinement at block size 1).
    w.c.busy_s = std::max(
        0.0, seconds_between(loop_start, loop_end) - w.c.idle_s - w.c.load_s);
    // Every store is done: each refiner moves the lists it started into one block of
    // its own link arena (so, under first-touch, onto its node), then forgets its
    // staging blocks. Others may still be reading from this refiner's staging blocks;
    // the reset only marks them free, and nothing allocates from them this stage.
#pragma omp barrier
    const auto compact_start = Clock::now();
    for (Element* r : w.started) hierarchy_.compact_links(*r, w.id);
    hierarchy_.reset_link_staging(w.id);
    w.c.compact_s = seconds_since(compact_start);
    w.c.link_bytes = hierarchy_.link_arena(w.id).bytes_used();
    w.c.cpu_s = thread_cpu_seconds() - cpu_start;
  }
  solver.join();
  if (report) {
    {
      const std::lock_guard lock(progress_mutex);
      stage_over = true;
    }
    progress_cv.notify_one();
    reporter.join();
  }

  RefineCounters total;
  for (const Worker& w : workers) {
    total.tasks += w.c.tasks;
    total.links_created += w.c.links_created;
    total.links_kept += w.c.links_kept;
    total.culled += w.c.culled;
    total.rays_cast += w.c.rays_cast;
    total.rays_skipped += w.c.rays_skipped;
    total.busy_s += w.c.busy_s;
    total.idle_s += w.c.idle_s;
    total.cpu_s += w.c.cpu_s;
    total.load_s += w.c.load_s;
    total.link_bytes += w.c.link_bytes;
    total.compact_s = std::max(total.compact_s, w.c.compact_s);
    total.takes += w.c.takes;
    total.submits += w.c.submits;
    total.per_worker.push_back(w.c);
    total.trace.insert(total.trace.end(), w.trace.begin(), w.trace.end());
  }
  total.peak_parallelism = peak.v.load();
  total.over_memory = over_memory.v.load();
  total.arena_bytes = arena_bytes.v.load();
  return total;
}

void Refiner::reload_links(Hierarchy& hierarchy, const std::vector<Element*>& elements,
                           int threads, std::vector<Task>& tasks) {
  // Each element's tasks go to a fixed place (a prefix sum of the link counts), so
  // the list is the same whatever the thread count, and is filled in parallel.
  const auto n = static_cast<std::ptrdiff_t>(elements.size());
  std::vector<std::size_t> first(elements.size() + 1, 0);
  for (std::size_t i = 0; i < elements.size(); ++i)
    first[i + 1] = first[i] + elements[i]->links.size();
  tasks.resize(first.back());  // only a longer list constructs (serially) its new tail
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1024) if (first.back() > 65536)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    Element* e = elements[static_cast<std::size_t>(i)];
    Task* t = tasks.data() + first[static_cast<std::size_t>(i)];
    for (const Link& l : e->links) {
      t->receiver = e;
      t->source = l.source;
      t->form_factor = l.form_factor;
      t->visibility = l.visibility;
      t->priority = static_cast<float>(reflected_power_scale(*e, *l.source) * l.form_factor);
      t->evaluated = true;
      ++t;
    }
  }
  hierarchy.release_links(elements);
}

}  // namespace hrad
