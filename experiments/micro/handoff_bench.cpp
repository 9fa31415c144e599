// Microbenchmark of what a task costs when the refiner that runs it is not the one that
// created its data: the effect that made `blocked` (one LIFO shared by all refiners)
// 27 % slower per task at 2 threads than at 1 on builtin:office, and that per-refiner
// chunk stacks removed (schedulers/blocked.cpp).
//
// Two threads take turns in rounds. In each round every thread "subdivides": it writes a
// batch of fresh Elements (as Hierarchy::subdivide writes children), then "refines": it
// reads the geometry of a batch and writes its link-list head (as a task classifies,
// samples and stores). With `own` the batch it refines is the one it just wrote (the
// data is in its own cache); with `handoff` it is the one the other thread just wrote
// (every line comes from the other core's cache). Time per element refined, in the
// benchmark's CPU time; compare the two at 2 threads, and each with 1 thread.
#include <benchmark/benchmark.h>

#include <barrier>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

#include "core/hierarchy/element.h"

namespace {

using hrad::Element;

constexpr std::size_t kBatch = 2048;  // elements per batch: 1 MiB, well inside L2

void write_batch(Element* e, std::uint64_t round) {
  for (std::size_t i = 0; i < kBatch; ++i) {
    e[i].id = round * kBatch + i;
    e[i].area = 1.0 + static_cast<double>(i);
    for (auto& c : e[i].corner) c = hrad::Vec3(static_cast<double>(i), 1.0, 2.0);
    e[i].normal = hrad::Vec3(0, 0, 1);
    e[i].center = hrad::Vec3(0.5, 0.5, static_cast<double>(round));
    e[i].B = hrad::Rgb::Constant(0.5);
  }
}

double refine_batch(Element* e) {
  double acc = 0;
  for (std::size_t i = 0; i < kBatch; ++i) {
    const Element& x = e[i];
    acc += x.area * x.B[0] + x.normal.dot(x.center - x.corner[0]) + x.corner[2].x();
    e[i].gather_scale = static_cast<float>(acc);  // a write beside the link head
  }
  return acc;
}

// state.range(0): 1 = each thread refines what it wrote, 0 = what the other wrote.
void BM_Handoff(benchmark::State& state) {
  const bool own = state.range(0) == 1;
  const int threads = static_cast<int>(state.range(1));
  std::vector<std::unique_ptr<Element[]>> batches;
  for (int t = 0; t < threads; ++t) batches.push_back(std::make_unique<Element[]>(kBatch));
  constexpr int kRounds = 64;
  double sink = 0;
  for (auto _ : state) {
    std::barrier sync(threads);
    std::vector<std::thread> pool;
    std::vector<double> acc(static_cast<std::size_t>(threads), 0);
    for (int t = 0; t < threads; ++t) {
      pool.emplace_back([&, t] {
        for (int r = 0; r < kRounds; ++r) {
          write_batch(batches[static_cast<std::size_t>(t)].get(), static_cast<std::uint64_t>(r));
          sync.arrive_and_wait();
          const int from = own ? t : (t + 1) % threads;
          acc[static_cast<std::size_t>(t)] +=
              refine_batch(batches[static_cast<std::size_t>(from)].get());
          sync.arrive_and_wait();
        }
      });
    }
    for (std::thread& th : pool) th.join();
    for (double a : acc) sink += a;
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * kRounds * static_cast<std::int64_t>(kBatch) *
                          threads);
  state.SetLabel(own ? "own data" : "data from the other thread");
}

BENCHMARK(BM_Handoff)
    ->ArgNames({"own", "threads"})
    ->Args({1, 1})
    ->Args({1, 2})
    ->Args({0, 2})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
