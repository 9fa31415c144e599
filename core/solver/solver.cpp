#include "core/solver/solver.h"

#include "core/base/clock.h"
#include "core/base/interrupt.h"
#include "core/base/progress.h"
#include "core/config/effects.h"
#include "core/config/options_io.h"
#include "core/hierarchy/hierarchy.h"
#include "core/output/stats_json.h"
#include "core/parallel/lock_pool.h"
#include "core/parallel/trace.h"
#include "core/raycast/ray_scene.h"
#include "core/solver/numa_report.h"
#include "core/solver/progress_scale.h"
#include "core/solver/propagation.h"
#include "core/solver/push_weights.h"
#include "core/solver/refiner.h"
#include "core/solver/row_sums.h"
#include "core/transport/cluster_exposure.h"
#include "core/transport/form_factor.h"
#include "core/transport/open_fraction.h"
#include "core/transport/transport.h"
#include "oracles/oracle.h"
#include "schedulers/pool_order.h"
#include "schedulers/scheduler.h"

#include <fmt/format.h>
#include <omp.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace hrad {

namespace {

// The propagation of an iteration before the last only gives the next refinement the
// radiosities its oracle weighs links by, so it stops at this tolerance (or at
// gather_tolerance when that is looser); the last iteration's converges to
// gather_tolerance. builtin:office at the defaults: sweeps per iteration 41, 33, 25,
// 19 -> 21, 13, 2, 24, propagation 1.17 -> 0.74 s, 5 links of 359,002 different, the
// probe errors the same to 0.01 %. From 1e-4 to 1e-3: office 22, 17, 2, 25 -> 12, 2, 2,
// 34 sweeps, lab 19, 13, 9, 11 -> 12, 2, 2, 22 (52 -> 38); 672 of 367,610 office links
// and 562 of 1,065,529 lab links different; probes moved by 0.02 % (median) and at most
// 0.15 % (28 random probes each), against references of 1 % standard error. The Cornell
// box's first propagation stops after 2 sweeps instead of 7, and its next refinement
// sees darker receivers: 36,773 -> 40,458 links, probe error median 1.50 -> 1.47 %,
// worst 16.0 -> 15.1 %, the same time. From 1e-3 to 3e-3: lab 10, 7, 2, 11 -> 3, 2, 5,
// 11 sweeps (30 -> 21), cabin 3, 12, 6, 14 -> 3, 2, 8, 16 (35 -> 29), office 24 -> 23,
// links within 0.3 % (the Cornell box's the same), and at 48 random probes per scene
// (two sets of 24) medians and biases within 0.12 % and no worst probe worse by more
// than 0.4 %. At 1e-2 the office's links grew by 4 % and its worst probe went 90 ->
// 140 %.
constexpr double kIntermediateTolerance = 3e-3;
// warn_about_scene: a bounding box more than this many times the bulk of the area.
constexpr double kBulkRatioWarning = 100;
// The share of the accepted links' estimated error that min_area may keep from the
// refinement the oracle asks for before the oracle may refine past it and the run warns
// (Impl::watch_min_area). The office at eps 1e-5: 0.75 %; a room beside a large ground
// plane: 100 %.
constexpr double kMinAreaHeldWarning = 0.05;

/// Leaf surface elements (those without children), depth first: the solution's
/// finest mesh.
std::vector<const Element*> leaf_surfaces(const Element& root) {
  std::vector<const Element*> leaves;
  std::vector<const Element*> stack{&root};
  while (!stack.empty()) {
    const Element* e = stack.back();
    stack.pop_back();
    const auto kids = e->child_span();
    if (!kids.empty()) {
      for (const Element& k : kids) stack.push_back(&k);
    } else if (!e->is_cluster()) {
      leaves.push_back(e);
    }
  }
  return leaves;
}

// What the leaf s gives probe i (point p, unit normal n) in the final gather: the exact
// point-to-polygon form factor and the kernel-weighted visibility from k rays whose random
// numbers hash the probe index and the element id (f = 0: nothing).
struct ProbeView {
  double form_factor = 0, visibility = 0;
};
ProbeView probe_view(const Transport& transport, const Probe& pr, std::size_t i, const Element& s,
                     int k) {
  if ((s.B <= 0).all()) return {};
  const double f = point_to_polygon_ff(pr.p, pr.n, s.corners());
  if (f <= 0) return {};
  const std::uint64_t key = child_id(s.id, static_cast<std::uint32_t>(i) ^ 0x5EEDu);
  return {f, transport.visibility_from_point(pr.p, pr.n, s, key, k)};
}

// One element of the chain above a leaf, for Solver::explain_probe: what it is and holds,
// and its `top` strongest links by transport x source radiosity (channel mean).
nlohmann::json chain_level_json(const Element& a, int top) {
  std::vector<const Link*> links;
  for (const Link& l : a.links) links.push_back(&l);
  const auto strength = [](const Link* l) { return l->transport() * l->source->B.mean(); };
  std::sort(links.begin(), links.end(), [&](const Link* x, const Link* y) {
    return strength(x) != strength(y) ? strength(x) > strength(y) : x->source->id < y->source->id;
  });
  Rgb total = Rgb::Zero();
  for (const Link* l : links) total += l->transport() * l->source->B;
  nlohmann::json strongest = nlohmann::json::array();
  for (std::size_t q = 0; q < std::min(links.size(), static_cast<std::size_t>(top)); ++q) {
    const Link& l = *links[q];
    const Element& so = *l.source;
    nlohmann::json source = {{"kind", so.is_cluster() ? "cluster" : "surface"}};
    if (so.is_cluster())
      source["polygons"] = so.face_end - so.face;
    else
      source["face"] = so.face;
    strongest.push_back({{"source", std::move(source)},
                         {"area", so.area},
                         {"centre", json_vec3(so.center)},
                         {"radiosity", json_rgb(so.B)},
                         {"form_factor", l.form_factor},
                         {"visibility", l.visibility()},
                         {"irradiance", json_rgb(l.transport() * so.B)}});
  }
  return {{"kind", a.is_cluster() ? "cluster" : "surface"},
          {a.is_cluster() ? "polygons" : "face", a.is_cluster() ? a.face_end - a.face : a.face},
          {"depth", a.depth},
          {"area", a.area},
          {"open", open_weight(a)},
          {"push_weight", a.push_weight},
          {"cluster_weight", a.cluster_weight},
          {"radiosity", json_rgb(a.B)},
          {"links", links.size()},
          {"links_irradiance", json_rgb(total)},
          {"strongest_links", std::move(strongest)}};
}

// The cluster tree is built by the calling thread into refiner 0's arena, so the
// thread is bound as refiner 0 while it builds: under first-touch the tree's pages then
// land on refiner 0's node, where the arena counts them.
Hierarchy build_hierarchy(const Scene& scene, int threads, const ArenaPlacement& placement,
                          const Topology& topology, const PinPlan& plan) {
  const ScopedThreadBinding bound(&topology,
                                  plan.refiners.empty() ? ThreadBinding{} : plan.refiners[0]);
  return Hierarchy(scene, threads, placement);
}
// What one Solver::run keeps from stage to stage.
struct RunState {
  RunState(Hierarchy& hierarchy, const Transport& transport, const IOracle& oracle,
           const RefineLimits& l, const SchedulerConfig& s, int pool, int threads)
      : limits(l),
        sched_config(s),
        element_locks(pool, threads),
        link_locks(pool, threads),
        refiner(hierarchy, transport, oracle, limits, element_locks, link_locks) {}
  RunStats stats;
  RefineLimits limits;
  SchedulerConfig sched_config;  ///< each iteration's scheduler is made from it
  LockPool element_locks;
  LockPool link_locks;
  Refiner refiner;
  std::vector<TraceRecord> trace;
  TaskList tasks;
  double reload_s = 0;  ///< building this iteration's tasks (counted in its refinement)
  int max_sweeps = 0;
  bool grey = false;
  /// The propagation's measured contraction (PropagationResult::contraction), handed to
  /// the next iteration's propagation so it accelerates from its first sweep.
  double contraction = 0;
  bool light_scaled = false;  ///< the threshold follows the light (scale_threshold)
};

// Why a scene with several polygons has no link, as far as a look at its faces' centres
// can tell: none faces another (flipped orientations?), or the facing ones are closer
// than the rays' contact tolerance (two plates 1e-9 apart were asked "flipped?"). Looks
// at the first kMaxFaces faces only (all pairs).
std::string no_link_warning(const Scene& scene, double diagonal) {
  constexpr std::size_t kMaxFaces = 3000;
  const std::size_t n = std::min(scene.faces.size(), kMaxFaces);
  std::vector<Vec3> c(n), nrm(n);
  for (std::size_t f = 0; f < n; ++f) {
    c[f] = polygon_centroid(scene.face_vertices(f));
    nrm[f] = scene.face_normal(f);
  }
  const double contact = RayScene::kEndpointEpsilon * diagonal;
  double nearest = std::numeric_limits<double>::infinity();  // of the facing pairs
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      const Vec3 d = c[b] - c[a];
      const double ahead = nrm[a].dot(d), behind = nrm[b].dot(d);
      if (ahead > 0 && behind < 0) nearest = std::min(nearest, std::min(ahead, -behind));
    }
  if (nearest <= contact)
    return fmt::format(
        "no link: the polygons that face each other are closer than the contact tolerance "
        "({:.3g}, 1e-5 of the scene's diagonal), so they count as touching, and touching "
        "faces exchange no light: move them apart, or make them one solid",
        contact);
  if (std::isfinite(nearest))
    return "no link: polygons face each other, but no pair was linked (each hidden from the "
           "others by something between them?), so nothing but emission is seen";
  return "no link: no two polygons face each other, so nothing but emission is seen (a polygon "
         "sends and receives light on the side its normal points to, by the right-hand rule "
         "over its vertex order: are the faces' orientations flipped?)";
}

}  // namespace

struct Solver::Impl {
  const Scene& scene;
  SolverOptions options;
  ProgressFn progress;
  std::unique_ptr<Topology>
      topology;  ///< binds threads and arena memory (core/parallel/topology.h)
  PinPlan plan;  ///< where each refiner runs (core/parallel/pin_plan.h)
  RayScene rays;
  Hierarchy hierarchy;
  Transport transport;
  std::unique_ptr<IOracle> oracle;
  RowSumMode row_sum_mode;
  ClusterReceiver receiver_mode;
  double emitted_power = 0;  ///< sum over faces of area x largest emission channel
  /// Each colour channel judged against its own light: the oracles' and the push
  /// weights' channel weights (channel_weights, oracles/oracle.h).
  Rgb channel_weight = Rgb::Ones();
  double total_area = 0;
  Effects effects;  ///< what the scene needs (core/config/effects.h)
  /// Kept across iterations: with push_visibility = child it holds the children's own
  /// visibilities for the next iteration's update (core/solver/push_weights.h).
  PushWeights push_weights;
  /// Kept across the row sums and propagations while the hierarchy is the same: their
  /// passes' layout and state (core/solver/propagation.h).
  PropagationCache propagation_cache;
  double setup_s = 0;  ///< the constructor's wall time (set by Solver::Solver)

  Impl(const Scene& s, const SolverOptions& o, ProgressFn p)
      : scene(s),
        options(o),
        progress(std::move(p)),
        topology(std::make_unique<Topology>()),
        plan(make_pin_plan(topology->info(), o.pin, o.threads)),
        rays(RayScene::from_scene(s)),
        hierarchy(build_hierarchy(s, o.threads,
                                  ArenaPlacement{o.placement, topology->info().numa_nodes,
                                                 plan.worker_nodes(), topology.get()},
                                  *topology, plan)),
        transport(hierarchy, rays, o.visibility_rays, o.seed, o.cluster_model),
        oracle(make_oracle(o.oracle, plugin_params_of(o, "oracle"))),
        row_sum_mode(o.row_sums),
        receiver_mode(o.cluster_receiver),
        emitted_power(s.max_channel_emitted_power()),
        channel_weight(channel_weights(s.emitted_power())),
        total_area(s.total_area()) {
    throw_if_interrupted();
    effects = analyse_effects(s, o);
    transport.set_visibility_effect(effects.visibility.on);
    transport.set_shaft_culling(o.shaft_culling == ShaftCulling::On &&
                                o.effects == EffectsMode::Auto);
  }

  // The stages of run(), in order (each iteration: refine, prepare, propagate, count).
  void warn_about_scene(RunStats& stats) const;
  void watch_min_area(RunState& r, const IterationStats& is, bool last, RunStats& stats) const;
  RefineCounters refine(RunState& r, int it, IterationStats& is);
  std::vector<Element*> prepare_propagation(IterationStats& is);
  /// Whether probe i sees nothing but the black inside of a solid (closed in by a
  /// contact; core/transport/open_fraction.h, point_closed_in): its irradiance is 0.
  [[nodiscard]] bool probe_closed_in(const Probe& pr, std::size_t i) const {
    return effects.visibility.on &&
           point_closed_in(pr.p, pr.n, hierarchy, rays,
                           child_id(static_cast<std::uint64_t>(i), 0xC105EDu) ^ options.seed);
  }
  /// The final gather at probe i (not closed in) over `leaves`: the sum of each leaf's
  /// form factor x visibility x radiosity (probe_view); see(leaf, view) is called for
  /// every leaf that gives the point light.
  template <class See>
  Rgb gather_probe(const Probe& pr, std::size_t i, const std::vector<const Element*>& leaves,
                   const See& see) const {
    const int k = std::max(options.visibility_rays, 8);
    Rgb sum = Rgb::Zero();
    for (const Element* s : leaves) {
      const ProbeView g = probe_view(transport, pr, i, *s, k);
      if (g.form_factor <= 0) continue;
      sum += g.form_factor * g.visibility * s->B;
      if (g.visibility > 0) see(*s, g);
    }
    return sum;
  }
  void propagate_links(RunState& r, int it, bool last, std::vector<Element*>& elements,
                       IterationStats& is);
  void count_links(int it, const std::vector<Element*>& elements, IterationStats& is,
                   RunStats& stats) const;
  void scale_threshold(RunState& r, const std::vector<Element*>& elements, RunStats& stats);
  void write_run_trace(const std::vector<TraceRecord>& trace) const;
  /// Where each phase sits on the progress line (core/solver/progress_scale.h).
  [[nodiscard]] ProgressScale progress_scale() const { return ProgressScale(options.iterations); }
};

namespace {
// What preparing a scene takes at least, per polygon (ray scene, hierarchy, contacts):
// builtin:cabin?rows=200's 1,078,778 polygons took 0.963 GB, 890 bytes each; the
// estimate errs low, to refuse only what cannot fit.
constexpr double kPrepareBytesPerPolygon = 600;
}  // namespace

std::uint64_t memory_limit_bytes(double gb) {
  // A positive limit stays one (below a byte it read as 0, no limit, and the run went
  // on under three quarters of the machine's memory).
  if (gb > 0) return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(gb * 1e9));
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 0;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) / 4 * 3;
}

std::string memory_limit_text(std::uint64_t limit_bytes) {
  return fmt::format("the limit of {:.3g} GB (max_memory_gb; 0 means 3/4 of this machine's memory)",
                     static_cast<double>(limit_bytes) / 1e9);
}

Solver::Solver(const Scene& scene, const SolverOptions& options, ProgressFn progress) {
  validate_options(options);
  if (!options.trace.empty()) check_trace_target(options.trace);
  // Names are checked before the (possibly long) hierarchy build, against the
  // registries: nothing is built for the check (threads and block_size, which
  // make_scheduler also checks, are validate_options' part).
  check_scheduler_name(options.scheduler);
  check_oracle_name(options.oracle);
  const auto start = Clock::now();
  const MemoryGrowth memory;
  // max_memory_gb bounds the phases before the refinement too (which counts its own
  // elements and links against it): what preparing the scene (ray scene, hierarchy,
  // contacts) would take, before it starts; what it takes, while it runs (its loops
  // poll the budget with the interrupt) and at its end.
  const std::uint64_t limit = memory_limit_bytes(options.max_memory_gb);
  const double need = kPrepareBytesPerPolygon * static_cast<double>(scene.polygon_count());
  if (limit > 0 && need > static_cast<double>(limit))
    throw std::runtime_error(fmt::format(
        "preparing the scene ({} polygons: ray scene, hierarchy, contacts) needs about {:.3g} GB "
        "of memory, above {}: raise max_memory_gb or use a smaller scene",
        scene.polygon_count(), need / 1e9, memory_limit_text(limit)));
  {
    const MemoryBudget budget(
        limit, fmt::format("preparing the scene ({} polygons: ray scene, hierarchy, contacts)",
                           scene.polygon_count()));
    impl_ = std::make_unique<Impl>(scene, options, std::move(progress));
  }
  impl_->setup_s = seconds_since(start);
  throw_if_interrupted();
  if (const std::uint64_t took = memory.grown(); limit > 0 && took > limit)
    throw std::runtime_error(fmt::format(
        "preparing the scene ({} polygons: ray scene, hierarchy, contacts) took {:.3g} GB of "
        "memory, above {}: the refinement would have none left; raise max_memory_gb or use "
        "a smaller scene",
        scene.polygon_count(), static_cast<double>(took) / 1e9, memory_limit_text(limit)));
}

Solver::~Solver() = default;

RunStats Solver::run() {
  Impl& m = *impl_;
  const SolverOptions& o = m.options;
  const auto run_start = Clock::now();
  const RefineLimits limits{o.eps * m.emitted_power,
                            o.min_area * m.total_area,
                            memory_limit_bytes(o.max_memory_gb),
                            m.total_area > 0 ? m.emitted_power / m.total_area : 0.0,
                            o.decision_rays == DecisionRays::Independent,
                            0,
                            o.decision_visibility_rays,
                            m.channel_weight};
  const SchedulerConfig sched_config{o.threads,
                                     o.block_size,
                                     m.topology->info().numa_nodes,
                                     m.plan.worker_nodes(),
                                     o.pool_order,
                                     plugin_params_of(o, "scheduler")};
  RunState r(m.hierarchy, m.transport, *m.oracle, limits, sched_config,
             o.locks_pool > 0 ? o.locks_pool : 2 * o.threads, o.threads);
  RunStats& stats = r.stats;
  r.refiner.set_binding(m.topology.get(), &m.plan);
  add_placement_warnings(m.plan, m.topology->info(), m.hierarchy, o, stats.warnings);
  stats.effects = m.effects;
  const bool auto_effects = o.effects == EffectsMode::Auto;
  const bool solve = m.effects.emission.on;
  m.warn_about_scene(stats);
  if (solve) r.tasks.push_back(Task{&m.hierarchy.root(), &m.hierarchy.root()});
  // Interreflection off (every reflectance 0): one sweep gives B = E exactly.
  r.max_sweeps = m.effects.interreflection.on ? o.max_gather_sweeps : 1;
  r.grey = !m.effects.colour.on;

  for (int it = 1; it <= o.iterations && solve; ++it) {
    IterationStats is;
    is.iteration = it;
    const RefineCounters rc = m.refine(r, it, is);
    const auto t0 = Clock::now();
    std::vector<Element*> elements = m.prepare_propagation(is);
    is.prepare_s = seconds_since(t0);
    // Every task was a reloaded link accepted again (no link created, none split): the
    // link set is the previous iteration's, and the next iterations would repeat this
    // one (up to an oracle decision that the radiosity's last digits could flip). So it
    // is propagated to gather_tolerance as the last iteration would be, and the run
    // stops after it (with --iterations 1000 every later iteration re-ran the same links).
    const bool settled = auto_effects && it < o.iterations && it > 1 && rc.tasks == rc.links_kept &&
                         rc.links_created == 0;
    const bool last = it == o.iterations || settled;
    m.propagate_links(r, it, last, elements, is);
    is.propagate_wall_s = seconds_since(t0);
    if (!last) m.scale_threshold(r, elements, stats);
    m.count_links(it, elements, is, stats);
    m.watch_min_area(r, is, last, stats);
    stats.iterations.push_back(is);
    stats.totals.iterations_run = it;
    if (settled) {
      stats.effects.iterations = {
          false, fmt::format("stopped after iteration {} of {}: it re-accepted every link and "
                             "created none, so the rest would repeat its links (its propagation "
                             "ran to gather_tolerance, as the last one would)",
                             it, o.iterations)};
      break;
    }
    if (it < o.iterations) {
      const auto reload_start = Clock::now();
      Refiner::reload_links(m.hierarchy, elements, o.threads, r.tasks, m.channel_weight);
      r.reload_s = seconds_since(reload_start);
    }
  }
  if (!o.trace.empty()) m.write_run_trace(r.trace);
  if (m.progress) m.progress("done", 1.0);

  RunTotals& t = stats.totals;
  t.wall_s = seconds_since(run_start);
  static_cast<IterationTotals&>(t) = sum_iterations(stats.iterations);
  if (stats.iterations.empty()) t.elements = m.hierarchy.element_count();
  t.peak_rss_bytes = peak_rss_bytes();
  t.setup_s = m.setup_s;
  return std::move(stats);
}

void Solver::Impl::warn_about_scene(RunStats& stats) const {
  const bool solve = effects.emission.on;
  if (emitted_power <= 0)
    stats.warnings.push_back(solve ? "scene has no emitter: the solution is zero (solved anyway: "
                                     "effects = all)"
                                   : "scene has no emitter: the solution is zero; nothing was "
                                     "refined or propagated");
  // Ray tolerances follow the bulk of the scene when a little geometry lies far from
  // the rest (a triangle 30,000 units from a unit room: relative to the bounding box,
  // the room's walls took each other for contacts and lost a third of its light), but
  // single precision resolves the far-off geometry only coarsely (RayScene).
  const double whole = scene.bounds().diagonal(), bulk = scene.bulk_bounds().diagonal();
  if (bulk > 0 && whole > kBulkRatioWarning * bulk)
    stats.warnings.push_back(fmt::format(
        "98 % of the scene's area lies within {:.3g} units, but its bounding box is {:.3g} "
        "across ({:.0f} times more): ray tolerances follow the bulk of the scene, but geometry "
        "far from it is resolved only to about {:.2g} units; remove the far-off geometry if "
        "it matters",
        bulk, whole, whole / bulk,
        RayScene::kPrecisionUlps * std::numeric_limits<float>::epsilon() * whole));
  // B = E + rho K B has no finite solution when rho K can keep all light (rho = 1 in a
  // closed scene): the sweeps then never converge; the propagation reports divergence
  // when the change stops falling (core/solver/propagation.h), or stops at the cap.
  for (const Material& mat : scene.materials)
    if (solve && effects.interreflection.on && mat.reflectance.maxCoeff() >= 1) {
      stats.warnings.push_back(fmt::format(
          "material '{}' reflects all light (reflectance 1): a closed scene with such surfaces "
          "has no finite solution: the propagation stops when its change stops falling, or at "
          "max_gather_sweeps ({})",
          mat.name, options.max_gather_sweeps));
      break;
    }
}

// The refinement stage of iteration `it`: the scheduler and refiners over r.tasks, and
// what they counted into `is` (the stage's wall time includes building its tasks from
// the previous iteration's links).
RefineCounters Solver::Impl::refine(RunState& r, int it, IterationStats& is) {
  const SolverOptions& o = options;
  const ProgressScale scale = progress_scale();
  if (progress) {
    progress(fmt::format("iteration {}/{}: refine", it, o.iterations), scale.refine(it));
    // During the stage: tasks examined and links accepted so far. The share done is
    // estimated from the previous iteration's task count (or the tasks known, when
    // more); iteration 1 starts from one task and finds the rest as it goes, so it
    // claims no share until it ends.
    const std::uint64_t expected = r.stats.iterations.empty() ? 0 : r.stats.iterations.back().tasks;
    r.refiner.set_progress([this, it, scale, expected](const RefineProgress& p) {
      const double known = static_cast<double>(std::max(expected, p.tasks + p.pending));
      const double share = expected > 0 ? static_cast<double>(p.tasks) / known : 0.0;
      progress(fmt::format("iteration {}/{}: refine {} tasks, {} links", it, options.iterations,
                           ProgressReporter::format_count(p.tasks),
                           ProgressReporter::format_count(p.links)),
               scale.refine(it, share));
    });
  }
  r.element_locks.reset_counters();
  r.link_locks.reset_counters();
  auto scheduler = make_scheduler(o.scheduler, r.sched_config);
  const auto t0 = Clock::now();
  RefineCounters rc =
      r.refiner.run(*scheduler, r.tasks, o.threads, o.block_size, o.trace.empty() ? 0 : it);
  throw_if_interrupted();  // the stage was abandoned (core/base/interrupt.h)
  if (rc.over_memory)
    throw std::runtime_error(fmt::format(
        "iteration {}: refinement stopped when its elements and links reached {:.3g} GB, "
        "above {}: raise eps or min_area, or max_memory_gb",
        it, static_cast<double>(rc.arena_bytes) / 1e9, memory_limit_text(r.limits.max_bytes)));
  if (!o.trace.empty()) r.trace.insert(r.trace.end(), rc.trace.begin(), rc.trace.end());
  is.refine_wall_s = seconds_since(t0) + r.reload_s;
  is.refine_cpu_s = rc.busy_s;
  is.refine_thread_cpu_s = rc.cpu_s;
  is.task_cpu_ns = rc.tasks > 0 ? 1e9 * rc.cpu_s / static_cast<double>(rc.tasks) : 0.0;
  is.idle_s = rc.idle_s;
  is.peak_parallelism = rc.peak_parallelism;
  is.load_s = rc.load_s + r.reload_s;
  is.link_compact_s = rc.finish_s;  // the stage's finish: link compaction
  is.stage_start_s = rc.stage_start_s;
  is.stage_end_s = rc.stage_end_s;
  is.tasks = rc.tasks;
  is.links_created = rc.links_created;
  is.min_area_held = rc.held_links;
  is.min_area_held_error = rc.accepted_error > 0 ? rc.held_error / rc.accepted_error : 0.0;
  is.rays_cast = rc.rays_cast;
  is.rays_skipped = rc.rays_skipped;
  for (std::size_t w = 0; w < rc.per_worker.size(); ++w) {
    const RefineCounters& c = rc.per_worker[w];
    const int id = static_cast<int>(w);
    RefinerStats rs;
    rs.tasks = c.tasks;
    rs.takes = c.takes;
    rs.submits = c.submits;
    rs.busy_s = c.busy_s;
    rs.idle_s = c.idle_s;
    rs.cpu_s = c.cpu_s;
    rs.link_bytes = c.link_bytes;
    rs.lock_wait_s = r.element_locks.wait_seconds(id) + r.link_locks.wait_seconds(id);
    rs.rays_cast = c.rays_cast;
    is.refiners.push_back(rs);
  }
  if (std::string w = descheduled_refiner_warning(is); !w.empty()) r.stats.warnings.push_back(w);
  record_numa_stats(is, rc, plan, hierarchy, *topology, r.stats.warnings);
  const SchedulerCounters sc = scheduler->counters();
  is.steals = sc.steals;
  is.scheduler_ops = sc.takes + sc.empty_takes + sc.submits;
  is.lock_wait_s["scheduler"] = sc.lock_wait_s;
  is.lock_wait_s["element"] = r.element_locks.wait_seconds();
  is.lock_wait_s["link"] = r.link_locks.wait_seconds();
  return rc;
}

// eps x the emitted power bounds each link's error by a share of the light put into the
// scene. Where the reflectance is near 1 the light in the scene is hundreds of times the
// emission (a closed furnace of 0.999: a thousand), and that share of the emission a
// minute share of the light: iteration 2 of that furnace made 8.4 M links in 20 s and the
// run took 349 s and 2.1 GB, for an answer whose error its row sums decide (a 0.1 %
// transport error is 50 % of B there). So after each propagation the threshold becomes
// eps x max(emitted power, light / kLightShare), the light being the leaves' area x
// radiosity (largest channel): a scene whose light is under kLightShare times its
// emission keeps eps x emitted power, bit for bit (interiors: 2-3 times; the cluttered
// furnace of 0.9: about 10).
constexpr double kLightShare = 20;

void Solver::Impl::scale_threshold(RunState& r, const std::vector<Element*>& elements,
                                   RunStats& stats) {
  double light = 0;
  for (const Element* e : elements)
    if (!e->is_cluster() && e->child_span().empty()) light += e->area * e->B.maxCoeff();
  if (!(light / kLightShare > emitted_power)) return;
  r.refiner.set_eps_power(options.eps * light / kLightShare);
  r.limits.eps_power = options.eps * light / kLightShare;
  if (r.light_scaled) return;
  r.light_scaled = true;
  stats.warnings.push_back(fmt::format(
      "the light in the scene is {:.3g} times its emission (reflectance near 1): from the next "
      "iteration eps is taken relative to a {:g}th of that light, not to the emission, so that "
      "refinement stays bounded; row sums (row_sums=normalize) decide the accuracy here",
      light / emitted_power, kLightShare));
}

// Before the propagation: the open fractions, the push weights and the row sums of the
// new link set; returns every element, parents before children.
std::vector<Element*> Solver::Impl::prepare_propagation(IterationStats& is) {
  const SolverOptions& o = options;
  const int it = is.iteration;
  const ProgressScale scale = progress_scale();
  const std::string phase = fmt::format("iteration {}/{}: open fractions", it, o.iterations);
  const auto on_open = [&](double share) {
    progress(phase, scale.propagate(it, 0.8 * ProgressScale::prepare_share(it) * share));
  };
  if (progress) on_open(0);
  const auto open_start = Clock::now();
  // The members' exposures within their clusters depend on the geometry alone: once.
  if (it == 1 && o.cluster_members == ClusterMembers::Exposed &&
      receiver_mode == ClusterReceiver::Cosine && effects.visibility.on) {
    const ExposureStats x = compute_cluster_exposure(hierarchy, rays, o.seed, o.threads);
    is.rays_cast += x.rays_cast;
    is.exposure_rays = x.rays_cast;
    is.mean_exposure = x.mean_exposure;
  }
  std::vector<Element*> elements = hierarchy.elements();
  const OpenStats open =
      update_open_fractions(elements, hierarchy, rays, o.seed, o.threads, effects.visibility.on,
                            progress ? std::function<void(double)>(on_open) : nullptr);
  is.open_s = seconds_since(open_start);
  // Row sums measure transport, so their push shares it by geometry; the
  // propagation's push shares light, by the sources' radiosities. A rescale of the
  // row sums (clamp, normalize) must act on the propagation's own operator, so it
  // measures them with the light weights (in a furnace, normalize is then exact).
  const auto push_start = Clock::now();
  is.rays_cast +=
      push_weights.update(elements, transport, o.threads, o.push_visibility, channel_weight);
  const bool geometric_row_sums = row_sum_mode == RowSumMode::Keep;
  push_weights.apply(geometric_row_sums);
  is.push_weights_s = seconds_since(push_start);
  is.rays_cast += open.rays_cast;
  is.open_rays = open.rays_cast;
  is.open_area_fraction = open.area_fraction;
  const auto row_sums_start = Clock::now();
  const RowSumStats rs = apply_row_sums(elements, row_sum_mode, receiver_mode, hierarchy, rays,
                                        o.row_sum_rays, o.seed, o.threads, &propagation_cache);
  is.rays_cast += rs.rays_cast;
  is.row_sum_min = rs.min;
  is.row_sum_max = rs.max;
  is.row_sum_mean = rs.area_mean;
  is.row_sum_within_band = rs.within_band;
  is.row_sum_corrected = rs.corrected;
  is.gather_rows_kept = rs.rows_kept;
  if (geometric_row_sums) push_weights.apply(false);
  is.row_sums_s = seconds_since(row_sums_start);
  return elements;
}

// The gather and push-pull sweeps of iteration `it`, to gather_tolerance when it is
// the last one and to kIntermediateTolerance (or looser) before.
void Solver::Impl::propagate_links(RunState& r, int it, bool last, std::vector<Element*>& elements,
                                   IterationStats& is) {
  const SolverOptions& o = options;
  const ProgressScale scale = progress_scale();
  const double swept = ProgressScale::prepare_share(it);  // the preparation's share
  const auto on_sweep = [&](int sweeps, double change) {
    // The share of the sweeps is a guess: a sweep count of its own (the number of
    // sweeps is known only at the end) that approaches the stage's end.
    if (progress)
      progress(fmt::format("iteration {}/{}: propagate, sweep {} ({:.1e})", it, o.iterations,
                           sweeps, change),
               scale.propagate(it, swept + (1 - swept) * sweeps / (sweeps + 10.0)));
  };
  if (progress)
    progress(fmt::format("iteration {}/{}: propagate", it, o.iterations),
             scale.propagate(it, swept));
  const auto sweeps_start = Clock::now();
  const PropagationResult pr = propagate(
      elements, last ? o.gather_tolerance : std::max(o.gather_tolerance, kIntermediateTolerance),
      r.max_sweeps, o.threads, receiver_mode, r.grey, on_sweep, r.contraction, &propagation_cache);
  is.sweeps_s = seconds_since(sweeps_start);
  r.contraction = pr.contraction;
  is.contraction = pr.accelerated ? pr.contraction : 0.0;
  throw_if_interrupted();
  is.gather_sweeps = pr.sweeps;
  is.max_change = pr.last_change;
  if (pr.diverged)
    r.stats.warnings.push_back(fmt::format(
        "iteration {}: propagation diverged after {} sweeps (transport row sums above 1)", it,
        pr.sweeps));
  else if (!pr.converged && effects.interreflection.on)
    r.stats.warnings.push_back(
        fmt::format("iteration {}: propagation stopped at the cap of {} sweeps (change {:.3g})", it,
                    pr.sweeps, pr.last_change));
}

// min_area is a share of the whole scene's area. Where most of that area lies elsewhere
// (a closed room beside a 200 x 200 ground plane), it keeps the part that is lit from
// the refinement the oracle asks for. When it stopped a noticeable share of the accepted
// links' estimated error in an iteration, the oracle may refine any polygon
// kOracleLevels deep from the next one on (RefineLimits::oracle_levels), and the run says
// so; it warns again if min_area still holds that much at the last iteration. (At the
// defaults it held none in the builtin interiors; the office at eps 1e-5 0.75 %.)
void Solver::Impl::watch_min_area(RunState& r, const IterationStats& is, bool last,
                                  RunStats& stats) const {
  if (!(is.min_area_held_error >= kMinAreaHeldWarning)) return;
  const std::string held = fmt::format(
      "min_area ({:.3g} units^2, {:g} of the scene's {:.3g} units^2) stopped the refinement "
      "the oracle asked for on {} links ({:.1f} % of the accepted links' estimated error)",
      options.min_area * total_area, options.min_area, total_area, is.min_area_held,
      100 * is.min_area_held_error);
  if (!last && r.limits.oracle_levels == 0) {
    r.limits.oracle_levels = kOracleLevels;
    r.refiner.set_oracle_levels(kOracleLevels);
    stats.warnings.push_back(fmt::format(
        "iteration {}: {}: from the next iteration the oracle may refine any polygon {} "
        "levels deep whatever min_area says",
        is.iteration, held, kOracleLevels));
  } else if (last) {
    stats.warnings.push_back(
        fmt::format("{}, on surfaces {} or more levels below their "
                    "polygons; lower min_area",
                    held, r.limits.oracle_levels));
  }
}

// The iteration's links, elements and memory.
void Solver::Impl::count_links(int it, const std::vector<Element*>& elements, IterationStats& is,
                               RunStats& stats) const {
  std::uint64_t links = 0;
  for (const Element* e : elements) links += e->links.size();
  if (it == 1 && links == 0 && scene.faces.size() > 1)
    stats.warnings.push_back(no_link_warning(scene, rays.scale()));
  is.links = links;
  is.elements = elements.size();
  is.bytes["elements"] = hierarchy.element_bytes();
  is.bytes["links"] = hierarchy.link_bytes();
  is.peak_rss_bytes = peak_rss_bytes();
}

void Solver::Impl::write_run_trace(const std::vector<TraceRecord>& trace) const {
  const nlohmann::json header = {
      {"format", "hrad-trace"},
      {"version", 1},
      {"record_bytes", sizeof(TraceRecord)},
      {"records", trace.size()},
      {"fields",
       {"id:u64", "first_child:u64", "start_ns:u64",
        "duration_ns:u32 (top bit: first task of a block)", "children:u16", "worker:u8",
        "iteration:u8"}},
      {"scene", scene.name},
      {"threads", options.threads},
      {"scheduler", options.scheduler},
      {"block_size", options.block_size},
  };
  write_trace(options.trace, header.dump(), trace);
}

const RayScene& Solver::ray_scene() const { return impl_->rays; }

RenderMesh Solver::render_mesh(Shading shading) const {
  // The leaves, shaded as core/output/smooth_shading.h describes (smooth: vertex values
  // shared across leaves and polygons of one surface, T-vertices resolved).
  std::vector<ShadingPatch> patches;
  for (const Element* e : leaf_surfaces(impl_->hierarchy.root())) {
    ShadingPatch p;
    p.corners = e->corners();
    p.centre = e->center;
    p.normal = e->normal;
    p.material = e->material;
    p.area = e->area;
    p.open = open_weight(*e);
    p.radiosity = e->B;
    p.reflectance = e->rho;
    patches.push_back(p);
  }
  return shade_patches(patches, shading, 1e-7 * impl_->scene.bounds().diagonal());
}

std::vector<std::pair<std::uint64_t, std::uint64_t>> Solver::link_ids() const {
  std::vector<std::pair<std::uint64_t, std::uint64_t>> ids;
  for (const Element* e : impl_->hierarchy.elements())
    for (const Link& l : e->links) ids.emplace_back(e->id, l.source->id);
  std::sort(ids.begin(), ids.end());
  return ids;
}

std::vector<Solver::Leaf> Solver::leaves() const {
  std::vector<Leaf> out;
  for (const Element* e : leaf_surfaces(impl_->hierarchy.root()))
    out.push_back(Leaf{e->id, e->face, e->area, e->center, e->B});
  std::sort(out.begin(), out.end(), [](const Leaf& a, const Leaf& b) { return a.id < b.id; });
  return out;
}

std::vector<Rgb> Solver::probe_irradiance(std::span<const Probe> probes,
                                          const ProgressFn& progress) const {
  // Final gather: irradiance = sum over leaf surfaces of B_s x F(point -> s) x V,
  // with the exact point-to-polygon form factor and the kernel-weighted visibility of
  // Transport::visibility_from_point, from rays whose random numbers hash the probe
  // index and the element id; 0 at a point that sees nothing (point_closed_in).
  const Impl& m = *impl_;
  const std::vector<const Element*> leaves = leaf_surfaces(m.hierarchy.root());
  std::vector<Rgb> out(probes.size(), Rgb::Zero());
  const auto n = static_cast<std::ptrdiff_t>(probes.size());
  std::atomic<std::ptrdiff_t> done{0};
#pragma omp parallel for num_threads(m.options.threads) schedule(dynamic, 1)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (interrupted()) continue;  // then abandoned below
    // The progress line is one thread's (ProgressFn is not thread-safe).
    const std::ptrdiff_t finished = done.fetch_add(1, std::memory_order_relaxed);
    if (progress && omp_get_thread_num() == 0)
      progress(fmt::format("probes: {} of {}", finished, n), static_cast<double>(finished) / n);
    const Probe& pr = probes[static_cast<std::size_t>(i)];
    const auto at = static_cast<std::size_t>(i);
    if (m.probe_closed_in(pr, at)) continue;
    out[at] = m.gather_probe(pr, at, leaves, [](const Element&, const ProbeView&) {});
  }
  throw_if_interrupted();
  return out;
}

nlohmann::json Solver::explain_probe(std::size_t i, const Probe& pr, int top) const {
  const Impl& m = *impl_;
  nlohmann::json out = {{"probe", i}, {"point", json_vec3(pr.p)}, {"normal", json_vec3(pr.n)}};
  if (m.probe_closed_in(pr, i)) {
    out["closed_in"] = true;
    out["irradiance"] = json_rgb(Rgb::Zero());
    return out;
  }
  out["closed_in"] = false;
  // The same final gather as probe_irradiance, leaf by leaf.
  struct Part {
    const Element* leaf;
    ProbeView view;
    Rgb irradiance;
  };
  std::vector<Part> parts;
  const Rgb sum = m.gather_probe(pr, i, leaf_surfaces(m.hierarchy.root()),
                                 [&](const Element& s, const ProbeView& g) {
                                   parts.push_back({&s, g, g.form_factor * g.visibility * s.B});
                                 });
  std::sort(parts.begin(), parts.end(), [](const Part& a, const Part& b) {
    const double x = a.irradiance.mean(), y = b.irradiance.mean();
    return x != y ? x > y : a.leaf->id < b.leaf->id;
  });
  out["irradiance"] = json_rgb(sum);
  out["leaves_seen"] = parts.size();
  nlohmann::json seen = nlohmann::json::array();
  for (std::size_t q = 0; q < std::min(parts.size(), static_cast<std::size_t>(top)); ++q) {
    const Element& s = *parts[q].leaf;
    seen.push_back({{"face", s.face},
                    {"depth", s.depth},
                    {"area", s.area},
                    {"centre", json_vec3(s.center)},
                    {"normal", json_vec3(s.normal)},
                    {"radiosity", json_rgb(s.B)},
                    {"reflectance", json_rgb(s.rho)},
                    {"form_factor", parts[q].view.form_factor},
                    {"visibility", parts[q].view.visibility},
                    {"irradiance", json_rgb(parts[q].irradiance)}});
  }
  out["strongest_leaves"] = std::move(seen);
  // Where the strongest leaf's light comes from: it and every element above it.
  nlohmann::json chain = nlohmann::json::array();
  if (!parts.empty())
    for (const Element* a = parts.front().leaf; a != nullptr; a = a->parent)
      chain.push_back(chain_level_json(*a, top));
  out["strongest_leaf_chain"] = std::move(chain);
  return out;
}

}  // namespace hrad
