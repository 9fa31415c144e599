// Microbenchmarks of the propagation (core/solver/propagation.h) on builtin:office and
// builtin:lab refined once at the default settings (one refinement stage, 1 thread;
// about 300 k and 1 M links).
//  SweepIsotropic: 10 sweeps with cluster_receiver = isotropic, whose gather streams
//             over a matrix built once per propagation (the build is inside the timed
//             region); the rate is per link and sweep;
//  SweepCosine: the same with cluster_receiver = cosine (the solver's default), whose
//             cluster receivers gather along their six axis directions;
//  OneSweep:  a propagation of one sweep: mostly the matrix's build (per link);
//  RowSums:   apply_row_sums in the default mode (per link);
//  RowSumsKept: the same with the run's PropagationCache after a propagation over the
//             same links, as a refinement stage that changed no link leaves it: every
//             row of the gather matrix kept, no source read.
// Isotropic against Cosine shows what gathering by axis direction costs; OneSweep and
// RowSums the costs a propagation pays once per iteration before its sweeps.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "core/hierarchy/hierarchy.h"
#include "core/parallel/lock_pool.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/builtin_scenes.h"
#include "core/solver/propagation.h"
#include "core/solver/push_weights.h"
#include "core/solver/refiner.h"
#include "core/solver/row_sums.h"
#include "core/transport/open_fraction.h"
#include "core/transport/transport.h"
#include "oracles/oracle.h"
#include "schedulers/scheduler.h"

namespace {

using namespace hrad;

struct Refined {
  Scene scene;
  RayScene rays = RayScene::from_scene(scene);
  Hierarchy hierarchy{scene, 1};
  Transport transport{hierarchy, rays, 4, 1};
  std::vector<Element*> elements;
  std::size_t links = 0;

  explicit Refined(const char* name) : scene(make_builtin(name)) {
    const double power = scene.max_channel_emitted_power(), area = scene.total_area();
    const auto oracle = make_oracle("bf");
    LockPool element_locks(2, 1), link_locks(2, 1);
    Refiner refiner(hierarchy, transport, *oracle, RefineLimits{1e-4 * power, 1e-4 * area},
                    element_locks, link_locks);
    const auto scheduler = make_scheduler("stack", SchedulerConfig{1, 1});
    std::vector<Task> tasks{Task{&hierarchy.root(), &hierarchy.root()}};
    refiner.run(*scheduler, tasks, 1, 1);
    elements = hierarchy.elements();
    update_open_fractions(elements, hierarchy, rays, 1, 1, true);
    update_push_weights(elements, transport, 1);
    for (const Element* e : elements) links += e->links.size();
  }
};

// range(0): 0 the office, 1 the lab.
const Refined& refined(std::int64_t which) {
  if (which == 0) {
    static const Refined office("builtin:office");
    return office;
  }
  static const Refined lab("builtin:lab");
  return lab;
}

void per_link(benchmark::State& state, const Refined& r, int passes) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * passes *
                          static_cast<std::int64_t>(r.links));
  state.counters["links"] = static_cast<double>(r.links);
  state.counters["elements"] = static_cast<double>(r.elements.size());
}

void sweeps(benchmark::State& state, ClusterReceiver mode, int count) {
  const Refined& r = refined(state.range(0));
  for (auto _ : state) {
    // From the emission each time: from a converged radiosity the first sweep finds
    // no change and stops.
    state.PauseTiming();
    for (Element* e : r.elements) e->B = e->emission;
    state.ResumeTiming();
    const PropagationResult p = propagate(r.elements, 0.0, count, 1, mode, false);
    if (p.sweeps != count) state.SkipWithError("stopped early");
    benchmark::DoNotOptimize(p.last_change);
  }
  per_link(state, r, count);
}

void BM_PropagationSweepIsotropic(benchmark::State& s) {
  sweeps(s, ClusterReceiver::Isotropic, 10);
}
void BM_PropagationSweepCosine(benchmark::State& s) { sweeps(s, ClusterReceiver::Cosine, 10); }
void BM_PropagationOneSweep(benchmark::State& s) { sweeps(s, ClusterReceiver::Isotropic, 1); }
void BM_PropagationRowSums(benchmark::State& state) {
  const Refined& r = refined(state.range(0));
  for (auto _ : state) {
    const RowSumStats st = apply_row_sums(r.elements, RowSumMode::Keep, ClusterReceiver::Isotropic,
                                          r.hierarchy, r.rays, 0, 1, 1);
    benchmark::DoNotOptimize(st.area_mean);
  }
  per_link(state, r, 1);
}
void BM_PropagationRowSumsKept(benchmark::State& state) {
  const Refined& r = refined(state.range(0));
  PropagationCache cache;
  const auto row_sums = [&] {
    return apply_row_sums(r.elements, RowSumMode::Keep, ClusterReceiver::Isotropic, r.hierarchy,
                          r.rays, 0, 1, 1, &cache);
  };
  // A propagation hands its matrix back to the cache for the next build.
  const auto propagation = [&] {
    propagate(r.elements, 0.0, 1, 1, ClusterReceiver::Isotropic, false, {}, 0, &cache);
  };
  row_sums();  // every row built
  propagation();
  for (auto _ : state) {
    const RowSumStats st = row_sums();
    if (st.rows_kept != r.elements.size()) state.SkipWithError("rows not kept");
    benchmark::DoNotOptimize(st.area_mean);
    state.PauseTiming();
    propagation();
    state.ResumeTiming();
  }
  per_link(state, r, 1);
}
BENCHMARK(BM_PropagationSweepIsotropic)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PropagationSweepCosine)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PropagationOneSweep)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PropagationRowSums)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PropagationRowSumsKept)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
