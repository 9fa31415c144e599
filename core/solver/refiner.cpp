#include "core/solver/refiner.h"

#include "core/hierarchy/hierarchy.h"
#include "core/stage/run_stage.h"
#include "core/transport/transport.h"

#include <algorithm>
#include <cmath>
#include <span>

namespace hrad {

// One refiner's state: the rule's counters and the links of its current block.
struct alignas(64) Refiner::Worker {
  int id = 0;
  int node = 0;  ///< NUMA node of the pin plan (set_binding); 0 when unpinned
  RefineCounters c;
  /// Links accepted in the current block, stored after it (see store_links).
  std::vector<std::pair<Element*, Link>> accepted;
  std::vector<Link> batch;        ///< one receiver's accepted links, for store_links
  std::vector<Element*> started;  ///< receivers whose first link this worker stored
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

bool Refiner::oracle_may_split(const Element& e) const {
  return !e.is_cluster() && e.depth < limits_.oracle_levels && Hierarchy::can_subdivide(e);
}

bool Refiner::held_by_min_area(const Element& e) const {
  return !e.is_cluster() && !(e.area > limits_.min_area) && !oracle_may_split(e) &&
         Hierarchy::can_subdivide(e);
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
  /// The visibility the oracle decided on, when the accepted link's own came from other
  /// rays (stored with the link for the next iteration's judgement); else negative.
  double decided = -1;
};

void Refiner::process(const Task& task, Worker& w, std::vector<Task>& out) {
  Element& r = *task.receiver;
  Element& s = *task.source;
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
  const Step step = pc == PairClass::Regular ? judge(task, w, est) : open_pair(pc, task, w, est);
  if (step.drop) return;
  if (step.accept) {
    w.accepted.emplace_back(
        &r, Link{&s, static_cast<float>(est.form_factor), est.visibility, step.decided});
    if (task.evaluated)
      ++w.c.links_kept;
    else
      ++w.c.links_created;
    return;
  }
  Element& split = step.split_r ? r : s;
  const std::span<Element> kids =
      split.is_cluster() ? split.child_span() : hierarchy_.subdivide(split, w.id, element_locks_);
  const float child_priority =
      static_cast<float>(step.error / std::max<std::size_t>(kids.size(), 1));
  for (Element& c : kids) {
    Task t;  // its id is the driver's (core/stage/run_stage.h)
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
    est.visibility =
        est.form_factor > 0 ? transport_.visibility(r, s, w.c.rays_cast, w.c.rays_skipped) : 0.0;
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
  }
  if (oracle_.needs_spread()) est.form_factor_spread = transport_.form_factor_spread(r, s);
  const OracleThresholds th{limits_.eps_power, limits_.mean_irradiance, limits_.channel_weight};
  // What the oracle may refine: past min_area too, down to oracle_levels below the input
  // polygon (RefineLimits).
  const bool ask_r = can_r || oracle_may_split(r), ask_s = can_s || oracle_may_split(s);
  // Visibility rays are cast where they are read: for the decision when it depends on
  // them, and for the link once it is accepted. A pair that is refined whatever its
  // visibility (bf reads the unoccluded F of a surface pair) casts none; the link set
  // and every accepted link's estimate are the same as if each pair had cast its rays
  // first (the rays hash the pair, not the order).
  const bool depends = (ask_r || ask_s) && depends_on_visibility(oracle_, est, th);
  bool known = task.evaluated;
  const int decision_rays = limits_.decision_visibility_rays;
  if (!known && (depends || (!ask_r && !ask_s))) {
    est.visibility = transport_.visibility(r, s, w.c.rays_cast, w.c.rays_skipped, 0,
                                           depends ? decision_rays : 0);
    known = true;
  }
  Verdict v = oracle_.judge(est, th);
  // A surface pair always gets an independent estimate where its decision depended on
  // its visibility (the shadow test, kShadowContrast): otherwise the accepted ones would
  // be those whose rays found the pair more open or more hidden than it is.
  const bool surfaces = !r.is_cluster() && !s.is_cluster();
  if (depends && (limits_.independent_estimates || surfaces)) {
    // Decide on the first rays (a reloaded link may hold the second), and if the
    // link is accepted, estimate its visibility from the second (RefineLimits). A
    // link accepted this way last time holds both: the rays need not be cast again.
    const bool both = task.evaluated && task.decided_q != 0;
    if (task.evaluated) {
      est.visibility =
          both ? Link::decided_value(task.decided_q)
               : transport_.visibility(r, s, w.c.rays_cast, w.c.rays_skipped, 0, decision_rays);
      v = oracle_.judge(est, th);
    }
    if (v.decision == Decision::Accept) {
      st.decided = est.visibility;
      est.visibility = both ? static_cast<double>(task.visibility)
                            : transport_.visibility(r, s, w.c.rays_cast, w.c.rays_skipped, 1);
    }
  } else if (!known && v.decision == Decision::Accept) {
    est.visibility = transport_.visibility(r, s, w.c.rays_cast, w.c.rays_skipped);
    v = oracle_.judge(est, th);  // the same decision; its error may count the visibility
  }
  st.error = v.error;
  if (v.decision == Decision::Accept || (!ask_r && !ask_s)) {
    st.accept = true;
    w.c.accepted_error += v.error;
    if (v.decision != Decision::Accept && (held_by_min_area(r) || held_by_min_area(s))) {
      ++w.c.held_links;
      w.c.held_error += v.error;
    }
  } else if (can_r || can_s) {
    st.split_r = split_receiver(r, s, can_r, can_s);
  } else {  // past min_area: the oracle's own levels (RefineLimits::min_area)
    st.split_r = split_receiver(r, s, ask_r, ask_s);
  }
  return st;
}

// Refinement as a stage body (core/stage/stage_body.h): the driver runs the team and
// hands each task to process(); a block's accepted links are stored after it, and the
// lists a refiner started are compacted once every refiner is done.
struct Refiner::Body {
  Refiner& refiner;
  std::vector<Worker>& workers;
  Worker& at(int id) { return workers[static_cast<std::size_t>(id)]; }

  void begin(int id, int node) {
    at(id).id = id;
    at(id).node = node;
  }
  void process(int id, const Task& task, std::vector<Task>& out) {
    refiner.process(task, at(id), out);
  }
  std::uint64_t end_block(int id, std::size_t /*tasks*/) {
    Worker& w = at(id);
    refiner.store_links(w, false);
    return w.c.links_created + w.c.links_kept;
  }
  std::uint64_t bytes_held(int id) const {
    const Hierarchy& h = refiner.hierarchy_;
    return h.arena(id).bytes_used() + h.link_arena(id).bytes_used() +
           h.link_staging_arena(id).bytes_used();
  }
  void end_loop(int id) { refiner.store_links(at(id), true); }  // what a busy lock deferred
  // Every store is done: each refiner moves the lists it started into one block of its
  // own link arena (so, under first-touch, onto its node), then forgets its staging
  // blocks. Others may still be reading from this refiner's staging blocks; the reset
  // only marks them free, and nothing allocates from them this stage.
  void finish(int id) {
    Worker& w = at(id);
    Hierarchy& h = refiner.hierarchy_;
    for (Element* r : w.started) h.compact_links(*r, w.id);
    h.reset_link_staging(w.id);
    w.c.link_bytes = h.link_arena(w.id).bytes_used();
  }
};

RefineCounters Refiner::run(IScheduler& scheduler, std::span<Task> initial, int threads,
                            int block_size, int trace_iteration) {
  StageConfig config;
  config.threads = threads;
  config.block_size = block_size;
  config.trace_iteration = trace_iteration;
  config.max_bytes = limits_.max_bytes;
  config.topology = topology_;
  config.plan = plan_;
  if (progress_) {
    config.progress = [this](const StageProgress& p) {
      progress_(RefineProgress{p.tasks, p.pending, p.results, p.elapsed_s});
    };
    config.progress_interval_ms = progress_interval_ms_;
  }
  std::vector<Worker> workers(static_cast<std::size_t>(threads));
  Body body{*this, workers};
  StageCounters stage = run_stage(scheduler, initial, config, body);

  RefineCounters total;
  for (std::size_t i = 0; i < workers.size(); ++i) {
    RefineCounters& c = workers[i].c;
    static_cast<StageWorkerCounters&>(c) = stage.per_worker[i];
    total.tasks += c.tasks;
    total.links_created += c.links_created;
    total.links_kept += c.links_kept;
    total.culled += c.culled;
    total.accepted_error += c.accepted_error;
    total.held_error += c.held_error;
    total.held_links += c.held_links;
    total.rays_cast += c.rays_cast;
    total.rays_skipped += c.rays_skipped;
    total.busy_s += c.busy_s;
    total.idle_s += c.idle_s;
    total.cpu_s += c.cpu_s;
    total.load_s += c.load_s;
    total.link_bytes += c.link_bytes;
    total.finish_s = std::max(total.finish_s, c.finish_s);
    total.takes += c.takes;
    total.submits += c.submits;
    total.per_worker.push_back(c);
  }
  total.peak_parallelism = stage.peak_parallelism;
  total.stage_start_s = stage.start_s;
  total.stage_end_s = stage.end_s;
  total.over_memory = stage.over_memory;
  total.arena_bytes = stage.bytes_held;
  total.trace = std::move(stage.trace);
  return total;
}

namespace {
// A replaced task list has room for 1 / kTaskHeadroom more tasks than it holds.
constexpr std::size_t kTaskHeadroom = 8;
}  // namespace

void Refiner::reload_links(Hierarchy& hierarchy, const std::vector<Element*>& elements, int threads,
                           TaskList& tasks, const Rgb& channel_weight) {
  // Each element's tasks go to a fixed place (a prefix sum of the link counts), so
  // the list is the same whatever the thread count, and is filled in parallel.
  // The counts are read in parallel (each element's line is a cache miss), the prefix
  // sum runs over the dense array.
  const auto n = static_cast<std::ptrdiff_t>(elements.size());
  std::vector<std::size_t> first(elements.size() + 1, 0);
#pragma omp parallel for num_threads(threads) schedule(static) if (n > 65536)
  for (std::ptrdiff_t i = 0; i < n; ++i)
    first[static_cast<std::size_t>(i) + 1] = elements[static_cast<std::size_t>(i)]->links.size();
  for (std::size_t i = 0; i < elements.size(); ++i) first[i + 1] += first[i];
  // Every task is written below: a list too small is replaced rather than grown (nothing
  // copied), and its new tail left unwritten (TaskList). The replacement has room for
  // kTaskHeadroom more: the next stages keep most links and add a few, and a list
  // replaced at every stage had its pages faulted in again each time (the cabin's
  // 280 MB, 70,000 page faults a stage, 45 % of a run's). Room never written is never
  // made resident.
  if (first.back() > tasks.capacity()) {
    TaskList().swap(tasks);
    tasks.reserve(first.back() + first.back() / kTaskHeadroom);
  }
  tasks.resize(first.back());
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1024) if (first.back() > 65536)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    Element* e = elements[static_cast<std::size_t>(i)];
    Task* t = tasks.data() + first[static_cast<std::size_t>(i)];
    for (const Link& l : e->links) {
      t->receiver = e;
      t->source = l.source;
      t->form_factor = l.form_factor;
      t->visibility = static_cast<float>(l.visibility());
      t->decided_q = l.decided_q;
      t->priority =
          static_cast<float>(reflected_power_scale(*e, *l.source, channel_weight) * l.form_factor);
      t->evaluated = true;
      ++t;
    }
  }
  hierarchy.release_links(elements, threads);
}

}  // namespace hrad
