// Link lists (core/hierarchy/link_list.h) and the hierarchy's link arenas: links keep their
// order, blocks grow geometrically and never move while stored, compaction leaves one
// full block, the memory is counted on the node of the refiner that stored (and
// compacted) the links, and release_links() hands it out again.
#include "core/hierarchy/link_list.h"
#include "core/hierarchy/hierarchy.h"
#include "core/parallel/node_arena.h"
#include "core/scene/builtin_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <mutex>
#include <numeric>
#include <thread>
#include <vector>

namespace hrad {
namespace {

// A link that says where it came from: source pointer = index, form factor = tag.
Link tagged(std::uint32_t i, float tag = 0) {
  return Link{reinterpret_cast<Element*>(static_cast<std::uintptr_t>(i + 1) * 16), tag, 1.0f};
}
std::uint32_t index_of(const Link& l) {
  return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(l.source) / 16 - 1);
}

std::vector<std::uint32_t> indices(const LinkList& list) {
  std::vector<std::uint32_t> out;
  for (const Link& l : list) out.push_back(index_of(l));
  return out;
}

// A link's visibility is kept in 16 bits: 0 and 1 exactly (the oracles tell hidden,
// partly and wholly visible links apart by them), anything else within half a step
// (1/131070); the visibility an independent decision was made on is kept beside it, and
// a link that has none says so.
TEST(Link, KeepsVisibilityAndTheDecisionsOwnIn16BitsEach) {
  static_assert(sizeof(Link) == 16);
  const Link plain{nullptr, 0.5f, 0.3};
  EXPECT_FALSE(plain.has_decided());
  EXPECT_NEAR(plain.visibility(), 0.3, 0.5 / Link::kOne);
  EXPECT_NEAR(plain.transport(), 0.15, 0.5 / Link::kOne);
  EXPECT_EQ(Link(nullptr, 1, 0.0).visibility(), 0.0);
  EXPECT_EQ(Link(nullptr, 1, 1.0).visibility(), 1.0);
  EXPECT_EQ(Link(nullptr, 1, 1e-6).visibility(), 0.0);
  EXPECT_GT(Link(nullptr, 1, 1e-4).visibility(), 0.0);
  EXPECT_LT(Link(nullptr, 1, 1 - 1e-4).visibility(), 1.0);
  EXPECT_EQ(Link(nullptr, 1, std::nan("")).visibility(), 0.0);
  EXPECT_EQ(Link(nullptr, 1, 2.0).visibility(), 1.0);
  for (const double d : {0.0, 1e-3, 0.25, 0.7, 1.0}) {
    const Link l{nullptr, 1, 0.5, d};
    ASSERT_TRUE(l.has_decided()) << d;
    EXPECT_NEAR(l.decided(), d, 0.5 / (Link::kOne - 1)) << d;
    EXPECT_NEAR(l.visibility(), 0.5, 0.5 / Link::kOne) << d;
  }
  EXPECT_EQ(Link(nullptr, 1, 0.5, 0.0).decided(), 0.0);
  EXPECT_EQ(Link(nullptr, 1, 0.5, 1.0).decided(), 1.0);
  Link l{nullptr, 1, 0.5, 0.25};
  l.set_visibility(0.75);
  EXPECT_NEAR(l.visibility(), 0.75, 0.5 / Link::kOne);
  EXPECT_NEAR(l.decided(), 0.25, 0.5 / (Link::kOne - 1));
}

TEST(LinkList, KeepsStoreOrderAcrossBatchesOfAnySize) {
  NodeArena arena(0, ArenaPlacement{});
  LinkList list;
  EXPECT_TRUE(list.empty());
  EXPECT_EQ(list.begin(), list.end());
  std::vector<std::uint32_t> expect;
  std::uint32_t next = 0;
  for (std::uint32_t batch : {1u, 1u, 3u, 2u, 7u, 1u, 40u, 5u, 300u, 2u, 600u, 1u}) {
    std::vector<Link> links;
    for (std::uint32_t k = 0; k < batch; ++k) {
      links.push_back(tagged(next));
      expect.push_back(next++);
    }
    list.append(links, arena);
    ASSERT_EQ(list.size(), expect.size());
    ASSERT_EQ(indices(list), expect) << "after a batch of " << batch;
  }
  // Every block is in the arena, and the arena holds nothing else.
  EXPECT_EQ(list.bytes(), arena.bytes_used());
  EXPECT_EQ(std::distance(list.begin(), list.end()), static_cast<std::ptrdiff_t>(list.size()));
  list.append({}, arena);  // nothing to store: nothing changes
  EXPECT_EQ(list.size(), expect.size());
}

TEST(LinkList, OneAtATimeGrowsGeometricallyUpToTheCap) {
  NodeArena arena(0, ArenaPlacement{});
  LinkList list;
  const std::uint32_t n = 1000;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Link l = tagged(i);
    list.append({&l, 1}, arena);
  }
  // Capacities 1, 1, 2, 4, ..., 128, then blocks of kMaxBlockLinks = 256.
  std::size_t expect_blocks = 0;
  std::size_t capacity = 0;
  for (std::size_t c = 1; capacity < n;
       c = std::min<std::size_t>(std::max<std::size_t>(capacity, 1), LinkList::kMaxBlockLinks)) {
    capacity += c;
    ++expect_blocks;
  }
  EXPECT_EQ(list.block_count(), expect_blocks);
  EXPECT_EQ(list.bytes(), (capacity + expect_blocks) * sizeof(Link));
  // At most one header per block and the last block's free slots on top of the links.
  EXPECT_LE(list.bytes(), (n + expect_blocks + LinkList::kMaxBlockLinks) * sizeof(Link));
  std::vector<std::uint32_t> expect(n);
  std::iota(expect.begin(), expect.end(), 0u);
  EXPECT_EQ(indices(list), expect);
}

TEST(LinkList, ABigBatchIsOneBlockAndBlocksNeverMove) {
  NodeArena arena(0, ArenaPlacement{});
  LinkList list;
  std::vector<Link> big;
  for (std::uint32_t i = 0; i < 1000; ++i) big.push_back(tagged(i));
  list.append(big, arena);
  EXPECT_EQ(list.block_count(), 1u);
  const Link* first = &*list.begin();
  for (std::uint32_t i = 1000; i < 3000; ++i) {
    const Link l = tagged(i);
    list.append({&l, 1}, arena);
  }
  EXPECT_EQ(&*list.begin(), first);  // stored links stay where they are
  EXPECT_EQ(index_of(*first), 0u);
  EXPECT_EQ(list.size(), 3000u);
}

TEST(LinkList, ListsSharingAnArenaStaySeparate) {
  NodeArena arena(0, ArenaPlacement{});
  LinkList a, b;
  std::vector<std::uint32_t> ea, eb;
  for (std::uint32_t i = 0; i < 500; ++i) {
    const Link l = tagged(i);
    (i % 3 == 0 ? a : b).append({&l, 1}, arena);
    (i % 3 == 0 ? ea : eb).push_back(i);
  }
  EXPECT_EQ(indices(a), ea);
  EXPECT_EQ(indices(b), eb);
  EXPECT_EQ(a.bytes() + b.bytes(), arena.bytes_used());
  a.clear();
  EXPECT_TRUE(a.empty());
  EXPECT_EQ(a.begin(), a.end());
  EXPECT_EQ(indices(b), eb);  // clearing one list leaves the other alone
}

TEST(LinkList, CompactMovesEveryLinkIntoOneBlockInOrder) {
  NodeArena staging(0, ArenaPlacement{}), final_arena(0, ArenaPlacement{});
  LinkList list;
  std::vector<std::uint32_t> expect;
  for (std::uint32_t i = 0; i < 700; ++i) {
    const Link l = tagged(i);
    list.append({&l, 1}, staging);
    expect.push_back(i);
  }
  ASSERT_GT(list.block_count(), 5u);
  list.compact(final_arena);
  EXPECT_EQ(list.block_count(), 1u);
  EXPECT_EQ(list.size(), 700u);
  EXPECT_EQ(indices(list), expect);
  EXPECT_EQ(list.bytes(), (700u + 1u) * sizeof(Link));  // no free slot left
  EXPECT_EQ(final_arena.bytes_used(), list.bytes());
  EXPECT_TRUE(final_arena.owns(&*list.begin()));
  staging.reset();  // the old blocks are no longer used
  const Link more = tagged(700);
  list.append({&more, 1}, staging);  // appending after compaction starts a new block
  expect.push_back(700);
  EXPECT_EQ(indices(list), expect);
  LinkList empty;
  empty.compact(final_arena);
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(final_arena.bytes_used(), (700u + 1u) * sizeof(Link));  // nothing allocated
}

// The hierarchy's link arenas: a worker's links are counted on its node (in its
// staging arena while stored, in its link arena once compacted), every placement
// accounts for all link bytes, and release_links() empties every list and lets the
// next stage reuse the memory.
TEST(LinkList, HierarchyCountsLinksOnTheStoringWorkersNode) {
  const Scene scene = make_builtin("builtin:cornell");
  for (MemBind how : {MemBind::FirstTouch, MemBind::Interleave, MemBind::Node}) {
    Hierarchy h(scene, 2, ArenaPlacement{how, 2, {0, 1}, nullptr});
    std::vector<Element*> els = h.elements();
    ASSERT_GE(els.size(), 4u);
    // Worker 1 stores many links at the first elements; worker 0 a few at the last.
    std::vector<Link> links;
    for (std::uint32_t i = 0; i < 2000; ++i) links.push_back(tagged(i));
    for (std::size_t e = 0; e < 3; ++e) EXPECT_TRUE(h.store_links(*els[e], links, 1));
    EXPECT_FALSE(h.store_links(*els[0], std::span<const Link>(links).first(10), 0));  // not first
    EXPECT_TRUE(h.store_links(*els.back(), std::span<const Link>(links).first(5), 0));
    auto listed = [&] {
      std::size_t n = 0;
      for (const Element* e : els) n += e->links.bytes();
      return n;
    };
    std::vector<std::uint64_t> b = h.link_bytes_per_node();
    ASSERT_EQ(b.size(), 2u);
    EXPECT_EQ(b[0] + b[1], listed());
    EXPECT_EQ(h.link_bytes(), listed());
    EXPECT_EQ(h.link_staging_arena(1).bytes_used(), 3 * els[1]->links.bytes());
    if (how == MemBind::FirstTouch) {
      EXPECT_EQ(b[1], 3 * els[1]->links.bytes());
    }
    // Compaction as a refinement stage ends: each list by the worker that started it.
    for (std::size_t e = 0; e < 3; ++e) h.compact_links(*els[e], 1);
    h.compact_links(*els.back(), 0);
    h.reset_link_staging(0);
    h.reset_link_staging(1);
    EXPECT_EQ(h.link_staging_arena(0).bytes_used(), 0u);
    EXPECT_EQ(els[0]->links.size(), 2010u);
    EXPECT_EQ(els[0]->links.block_count(), 1u);
    b = h.link_bytes_per_node();
    EXPECT_EQ(b[0] + b[1], listed());
    EXPECT_EQ(h.link_bytes(), listed());
    EXPECT_EQ(h.link_arena(0).bytes_used(), 6 * sizeof(Link));  // 5 links and a header
    if (how == MemBind::FirstTouch) {
      EXPECT_EQ(b[1], (2010u + 2000u + 2000u + 3u) * sizeof(Link));
      EXPECT_EQ(b[0], 6 * sizeof(Link));
    } else if (how == MemBind::Node) {
      EXPECT_EQ(b[1], 0u);
    } else {  // about 94 KiB over 2 nodes, page by page
      EXPECT_NEAR(static_cast<double>(b[0]) / static_cast<double>(listed()), 0.5, 0.1);
    }
    const void* reused = &*els[0]->links.begin();
    h.release_links(els);
    for (const Element* e : els) EXPECT_TRUE(e->links.empty());
    EXPECT_EQ(h.link_bytes(), 0u);
    EXPECT_EQ(h.link_bytes_per_node(), (std::vector<std::uint64_t>{0, 0}));
    (void)h.store_links(*els[1], links, 1);
    h.compact_links(*els[1], 1);
    EXPECT_EQ(static_cast<const void*>(&*els[1]->links.begin()), reused);  // same memory again
    EXPECT_EQ(els[1]->links.size(), links.size());
  }
}

// Two workers append to the same receivers at once, each under the receiver's lock
// and from its own arena (as refiners do): every link arrives exactly once.
TEST(LinkList, ConcurrentAppendsUnderReceiverLocksLoseNothing) {
  const ArenaPlacement place{MemBind::FirstTouch, 2, {0, 1}, nullptr};
  NodeArena arenas[2] = {NodeArena(0, place), NodeArena(1, place)};
  constexpr int kReceivers = 8;
  constexpr std::uint32_t kPerWorker = 20000;
  LinkList lists[kReceivers];
  std::mutex locks[kReceivers];
  auto work = [&](int w) {
    for (std::uint32_t i = 0; i < kPerWorker; ++i) {
      const int r = static_cast<int>((i * 7 + static_cast<std::uint32_t>(w)) % kReceivers);
      const Link l = tagged(i, static_cast<float>(w));
      const std::lock_guard<std::mutex> g(locks[r]);
      lists[r].append({&l, 1}, arenas[w]);
    }
  };
  std::thread t0(work, 0), t1(work, 1);
  t0.join();
  t1.join();
  std::vector<int> seen(2 * kPerWorker, 0);
  std::size_t bytes = 0;
  for (const LinkList& list : lists) {
    bytes += list.bytes();
    for (const Link& l : list)
      ++seen[static_cast<std::size_t>(l.form_factor) * kPerWorker + index_of(l)];
  }
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << i;
  EXPECT_EQ(bytes, arenas[0].bytes_used() + arenas[1].bytes_used());
}

}  // namespace
}  // namespace hrad
