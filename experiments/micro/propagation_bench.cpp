// Microbenchmark of the propagation's sweeps (core/solver/propagation.h) on builtin:office
// refined once at the default settings (one refinement stage, 1 thread; about
// 300 k links). Each iteration runs 10 sweeps; the rate is per link and sweep.
//  Isotropic: the default, whose gather streams over a matrix built once per
//             propagation (the build is inside the timed region);
//  Cosine:    cluster_receiver = cosine, which still reads every link's source
//             element (and a cluster source's directional sums) in every sweep.
// The two back the claim that the gather matrix made a sweep several times cheaper
// per link than reading the sources through the links.
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
#include "core/transport/open_fraction.h"
#include "core/transport/transport.h"
#include "oracles/oracle.h"
#include "schedulers/scheduler.h"

namespace {

using namespace hrad;

struct Refined {
  Scene scene = make_builtin("builtin:office");
  RayScene rays = RayScene::from_scene(scene);
  Hierarchy hierarchy{scene, 1};
  Transport transport{hierarchy, rays, 4, 1};
  std::vector<Element*> elements;
  std::size_t links = 0;

  Refined() {
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

const Refined& office() {
  static const Refined r;
  return r;
}

void sweeps(benchmark::State& state, ClusterReceiver mode) {
  const Refined& r = office();
  constexpr int kSweeps = 10;
  for (auto _ : state) {
    const PropagationResult p = propagate(r.elements, 0.0, kSweeps, 1, mode, false);
    benchmark::DoNotOptimize(p.last_change);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kSweeps *
                          static_cast<std::int64_t>(r.links));
  state.counters["links"] = static_cast<double>(r.links);
  state.counters["elements"] = static_cast<double>(r.elements.size());
}

void BM_PropagationSweepIsotropic(benchmark::State& s) { sweeps(s, ClusterReceiver::Isotropic); }
void BM_PropagationSweepCosine(benchmark::State& s) { sweeps(s, ClusterReceiver::Cosine); }
BENCHMARK(BM_PropagationSweepIsotropic)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PropagationSweepCosine)->Unit(benchmark::kMillisecond);

}  // namespace
