// Microbenchmark of reading link lists (core/hierarchy/link_list.h) the way the propagation's
// gather does, on lists stored as refiners store them (one link at a time, receivers
// interleaved, so each list is several small blocks scattered in the arena) and on the
// same lists after compaction (one block each). The time per link backs the claim that
// compacting when a refinement stage ends makes the gather faster.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "core/hierarchy/element.h"
#include "core/hierarchy/link_list.h"
#include "core/parallel/node_arena.h"

namespace {

using hrad::Element;
using hrad::Link;
using hrad::LinkList;
using hrad::NodeArena;

struct Lists {
  static constexpr int kReceivers = 20000;
  std::unique_ptr<Element[]> sources = std::make_unique<Element[]>(kReceivers);
  std::vector<LinkList> lists = std::vector<LinkList>(kReceivers);
  NodeArena staging{0, hrad::ArenaPlacement{}};
  NodeArena compacted{0, hrad::ArenaPlacement{}};
  std::size_t links = 0;

  explicit Lists(bool compact) {
    // List lengths as on builtin:office (median about 16, a few hundred at most), stored
    // one link at a time in a random order of receivers.
    std::mt19937 rng(7);
    std::geometric_distribution<int> length(1.0 / 16);
    std::vector<int> order;
    for (int r = 0; r < kReceivers; ++r)
      for (int k = 1 + length(rng); k > 0; --k) order.push_back(r);
    std::shuffle(order.begin(), order.end(), rng);
    std::uniform_int_distribution<int> source(0, kReceivers - 1);
    for (int r : order) {
      const Link l{&sources[static_cast<std::size_t>(source(rng))], 0.01f, 1.0f};
      lists[static_cast<std::size_t>(r)].append({&l, 1}, staging);
    }
    for (int r = 0; r < kReceivers; ++r)
      sources[static_cast<std::size_t>(r)].B = hrad::Rgb(1, 2, 3);
    links = order.size();
    if (compact)
      for (LinkList& l : lists) l.compact(compacted);
  }
};

void gather(benchmark::State& state, bool compact) {
  const Lists data(compact);
  for (auto _ : state) {
    hrad::Rgb total = hrad::Rgb::Zero();
    for (const LinkList& list : data.lists) {
      hrad::Rgb g = hrad::Rgb::Zero();
      for (const Link& l : list) g += l.transport() * l.source->B;
      total += g;
    }
    benchmark::DoNotOptimize(total);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * data.links));
  std::size_t blocks = 0;
  for (const LinkList& l : data.lists) blocks += l.block_count();
  state.counters["blocks_per_list"] =
      static_cast<double>(blocks) / static_cast<double>(data.lists.size());
}

void BM_GatherStoredLists(benchmark::State& s) { gather(s, false); }
void BM_GatherCompactedLists(benchmark::State& s) { gather(s, true); }
BENCHMARK(BM_GatherStoredLists);
BENCHMARK(BM_GatherCompactedLists);

}  // namespace
