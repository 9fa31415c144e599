// Placement arenas (core/parallel/node_arena.h) and the hierarchy's use of them: memory is
// handed out by the right refiner's arena, counted on the node the placement
// promises, and binding is applied on this machine and only planned on a synthetic
// topology.
#include "core/hierarchy/hierarchy.h"
#include "core/parallel/node_arena.h"
#include "core/parallel/topology.h"
#include "core/scene/builtin_scenes.h"
#include "tests/env_guard.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>

namespace hrad {
namespace {

std::uint64_t sum(const std::vector<std::uint64_t>& v) {
  return std::accumulate(v.begin(), v.end(), std::uint64_t{0});
}

TEST(NodeArena, FirstTouchCountsEverythingOnTheOwnersNode) {
  const ArenaPlacement place{MemBind::FirstTouch, 2, {0, 1}, nullptr};
  NodeArena a0(0, place), a1(1, place);
  EXPECT_EQ(a1.node(), 1);
  std::vector<std::pair<unsigned char*, std::size_t>> blocks;
  for (std::size_t i = 0; i < 2000; ++i) {  // about 3 chunks of 256 KiB
    const std::size_t n = 100 + (i * 37) % 700;
    auto* p = static_cast<unsigned char*>(a1.allocate(n, 8));
    ASSERT_EQ(reinterpret_cast<std::uintptr_t>(p) % 8, 0u);
    std::memset(p, static_cast<int>(i & 0xff), n);
    blocks.emplace_back(p, n);
  }
  EXPECT_GE(a1.chunk_count(), 3u);
  std::size_t used = 0;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const auto [p, n] = blocks[i];
    used += n;
    // Nothing overlapped: every block still holds its own pattern.
    EXPECT_EQ(p[0], static_cast<unsigned char>(i & 0xff));
    EXPECT_EQ(p[n - 1], static_cast<unsigned char>(i & 0xff));
    EXPECT_EQ(a1.node_of(p), 1);
    EXPECT_TRUE(a1.owns(p + n - 1));
    EXPECT_FALSE(a0.owns(p));
  }
  // Used = requests plus alignment padding (under 8 bytes each).
  EXPECT_GE(a1.bytes_used(), used);
  EXPECT_LT(a1.bytes_used(), used + 8 * blocks.size());
  EXPECT_EQ(a1.bytes_per_node(), (std::vector<std::uint64_t>{0, a1.bytes_used()}));
  EXPECT_EQ(a0.bytes_per_node(), (std::vector<std::uint64_t>{0, 0}));
  int local = 0;
  EXPECT_EQ(a1.node_of(&local), -1);              // not arena memory
  EXPECT_EQ(a1.binding(), BindOutcome::Applied);  // first touch: nothing to bind
}

TEST(NodeArena, InterleaveSpreadsPagesNode0KeepsThemOnNodeZero) {
  const ArenaPlacement inter{MemBind::Interleave, 3, {1}, nullptr};
  NodeArena a(0, inter);
  auto* p = static_cast<unsigned char*>(a.allocate(10 * NodeArena::kPageBytes + 100, 64));
  const auto base = reinterpret_cast<std::uintptr_t>(p);
  ASSERT_EQ(base % NodeArena::kPageBytes, 0u);  // a fresh chunk starts on a page
  for (std::size_t k = 0; k < 11; ++k)
    EXPECT_EQ(a.node_of(p + k * NodeArena::kPageBytes),
              static_cast<int>(((base / NodeArena::kPageBytes) + k) % 3));
  const std::vector<std::uint64_t> b = a.bytes_per_node();
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(sum(b), a.bytes_used());
  for (std::uint64_t x : b) {  // 10 pages + 100 bytes over 3 nodes: 3 or 4 pages each
    EXPECT_GE(x, 3 * NodeArena::kPageBytes);
    EXPECT_LE(x, 4 * NodeArena::kPageBytes);
  }
  const ArenaPlacement node0{MemBind::Node, 2, {1, 1}, nullptr};
  NodeArena z(1, node0);
  void* q = z.allocate(5000, 16);
  EXPECT_EQ(z.node_of(q), 0);
  EXPECT_EQ(z.bytes_per_node(), (std::vector<std::uint64_t>{5000, 0}));
}

TEST(NodeArena, ResetHandsTheSameChunksOutAgain) {
  const ArenaPlacement place{MemBind::FirstTouch, 2, {1}, nullptr};
  NodeArena a(0, place);
  std::vector<void*> first;
  for (int i = 0; i < 300; ++i) first.push_back(a.allocate(2000, 16));  // about 3 chunks
  const std::size_t chunks = a.chunk_count();
  ASSERT_GE(chunks, 3u);
  a.reset();
  EXPECT_EQ(a.bytes_used(), 0u);
  EXPECT_EQ(a.bytes_per_node(), (std::vector<std::uint64_t>{0, 0}));
  EXPECT_FALSE(a.owns(first[0]));  // forgotten until handed out again
  // The same sequence of requests gets the same addresses, in the same chunks.
  for (std::size_t i = 0; i < 300; ++i) ASSERT_EQ(a.allocate(2000, 16), first[i]) << i;
  EXPECT_EQ(a.chunk_count(), chunks);
  EXPECT_EQ(a.node_of(first[0]), 1);
  EXPECT_EQ(a.node_of(first.back()), 1);
  // Past the old chunks, new ones are mapped.
  for (int i = 0; i < 200; ++i) (void)a.allocate(2000, 16);
  EXPECT_GT(a.chunk_count(), chunks);
  EXPECT_EQ(a.bytes_used(), 500u * 2000u);
}

TEST(NodeArena, SamplePagesSpreadsOverWhatWasHandedOut) {
  NodeArena a(0, ArenaPlacement{MemBind::Interleave, 3, {0}, nullptr});
  EXPECT_TRUE(a.sample_pages(8).empty());
  auto* p = static_cast<unsigned char*>(a.allocate(10 * NodeArena::kPageBytes + 100, 64));
  const auto all = a.sample_pages(100);  // 11 pages in use: every one
  ASSERT_EQ(all.size(), 11u);
  for (std::size_t k = 0; k < all.size(); ++k) {
    EXPECT_EQ(all[k].first, p + k * NodeArena::kPageBytes);
    EXPECT_EQ(all[k].second, a.node_of(p + k * NodeArena::kPageBytes));
  }
  const auto some = a.sample_pages(4);  // every third page: 0, 3, 6, 9
  ASSERT_EQ(some.size(), 4u);
  EXPECT_EQ(some[1].first, p + 3 * NodeArena::kPageBytes);
  EXPECT_EQ(some[3].first, p + 9 * NodeArena::kPageBytes);
}

TEST(NodeArena, BadAlignmentAndUnknownPlacementAreErrors) {
  NodeArena a(0, ArenaPlacement{});
  EXPECT_THROW((void)a.allocate(10, 3), std::invalid_argument);
  EXPECT_THROW((void)a.allocate(10, 2 * NodeArena::kPageBytes), std::invalid_argument);
  EXPECT_THROW((void)parse_enum<MemBind>("node1", "placement"), std::invalid_argument);
  EXPECT_EQ(parse_enum<MemBind>("interleave", "placement"), MemBind::Interleave);
  // An owner outside the placement's node list is counted on node 0.
  NodeArena b(5, ArenaPlacement{MemBind::FirstTouch, 2, {1}, nullptr});
  EXPECT_EQ(b.node(), 0);
}

TEST(NodeArena, HierarchyElementsComeFromTheSubdividingWorkersArena) {
  const Scene scene = make_builtin("builtin:cornell");
  Hierarchy h(scene, 2, ArenaPlacement{MemBind::FirstTouch, 2, {0, 1}, nullptr});
  EXPECT_TRUE(h.arena(0).owns(&h.root()));  // the cluster tree: worker 0
  EXPECT_EQ(h.root().home_node, 0);
  // Find a surface element and subdivide it as worker 1, then a child as worker 0.
  Element* surface = nullptr;
  for (Element* e : h.elements())
    if (!e->is_cluster()) {
      surface = e;
      break;
    }
  ASSERT_NE(surface, nullptr);
  LockPool locks(4, 2);
  const auto kids = h.subdivide(*surface, 1, locks);
  ASSERT_FALSE(kids.empty());
  for (const Element& k : kids) {
    EXPECT_TRUE(h.arena(1).owns(&k));
    EXPECT_FALSE(h.arena(0).owns(&k));
    EXPECT_EQ(k.home_node, 1);
    EXPECT_EQ(k.parent, surface);
  }
  const auto grandkids = h.subdivide(kids[0], 0, locks);
  for (const Element& g : grandkids) EXPECT_EQ(g.home_node, 0);
  const std::vector<std::uint64_t> b = h.element_bytes_per_node();
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(sum(b), h.element_count() * sizeof(Element));
  EXPECT_EQ(b[1], kids.size() * sizeof(Element));
}

TEST(NodeArena, BindingIsPlannedOnSyntheticAppliedHere) {
  {
    EnvGuard env("HWLOC_SYNTHETIC", "node:2 core:2 pu:1");
    const Topology topo;
    NodeArena a(0, ArenaPlacement{MemBind::Interleave, 2, {0}, &topo});
    (void)a.allocate(100, 8);
    EXPECT_EQ(a.binding(), BindOutcome::Planned);
  }
  if (std::getenv("HWLOC_SYNTHETIC") || std::getenv("HWLOC_XMLFILE")) return;
  const Topology topo;
  ASSERT_FALSE(topo.info().synthetic);
  NodeArena a(0, ArenaPlacement{MemBind::Node, topo.info().numa_nodes, {0}, &topo});
  auto* p = static_cast<unsigned char*>(a.allocate(3 * NodeArena::kPageBytes, 8));
  std::string why;
  EXPECT_EQ(a.bind_failures(&why), 0) << why;
  EXPECT_EQ(a.binding(), BindOutcome::Applied);
  std::memset(p, 1, 3 * NodeArena::kPageBytes);                   // touch: the pages now exist
  EXPECT_EQ(topo.node_of_address(p + NodeArena::kPageBytes), 0);  // bound to node 0
}

}  // namespace
}  // namespace hrad
