// The propagation's cache (core/solver/propagation.h): passes that keep their layout and
// dense state between them give the same results, bit for bit, as passes that make
// their own, after what a run changes between passes (push weights, row-sum scales,
// radiosity, some elements' links), on another thread count, and when the elements
// change.
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

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <set>
#include <vector>

namespace hrad {
namespace {

// A builtin scene refined once at eps (links to clusters and between surfaces, input
// polygons subdivided), its open fractions and push weights set.
struct Refined {
  Scene scene;
  RayScene rays = RayScene::from_scene(scene);
  Hierarchy hierarchy{scene, 1};
  Transport transport{hierarchy, rays, 4, 1};
  std::vector<Element*> elements;

  Refined(const char* name, double eps) : scene(make_builtin(name)) {
    const double power = scene.max_channel_emitted_power(), area = scene.total_area();
    const auto oracle = make_oracle("bf");
    LockPool element_locks(2, 1), link_locks(2, 1);
    Refiner refiner(hierarchy, transport, *oracle, RefineLimits{eps * power, eps * area},
                    element_locks, link_locks);
    const auto scheduler = make_scheduler("stack", SchedulerConfig{1, 1});
    std::vector<Task> tasks{Task{&hierarchy.root(), &hierarchy.root()}};
    refiner.run(*scheduler, tasks, 1, 1);
    elements = hierarchy.elements();
    update_open_fractions(elements, hierarchy, rays, 1, 1, true);
    update_push_weights(elements, transport, 1);
  }

  // From the emission, the clusters' directional sums not yet made.
  void restart() {
    for (Element* e : elements) {
      e->B = e->emission;
      if (e->light) e->light->leaving_made = false;
    }
  }
  [[nodiscard]] std::vector<Rgb> radiosity() const {
    std::vector<Rgb> b;
    for (const Element* e : elements) b.push_back(e->B);
    return b;
  }
  // The radiosity of a propagation to 1e-6 from the emission, with `cache` (none: its
  // own).
  std::vector<Rgb> propagated(ClusterReceiver mode, PropagationCache* cache = nullptr) {
    restart();
    propagate(elements, 1e-6, 100, 1, mode, false, {}, 0, cache);
    return radiosity();
  }
  [[nodiscard]] std::vector<Rgb> pushed() const {
    std::vector<Rgb> n;
    for (const Element* e : elements) n.push_back(e->next);
    return n;
  }
};

// Elements whose values differ (a and b of one size).
std::size_t differing(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i) differ += (a[i] != b[i]).any() ? 1 : 0;
  return differ;
}

void expect_same(const std::vector<Rgb>& a, const std::vector<Rgb>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(differing(a, b), 0u) << what << ": elements that differ, of " << a.size();
}

TEST(PropagationCache, KeptStateGivesWhatAFreshOneGives) {
  Refined r("builtin:cornell", 1e-3);
  ASSERT_GT(r.elements.size(), 100u);
  PropagationCache cache;
  for (ClusterReceiver mode : {ClusterReceiver::Isotropic, ClusterReceiver::Cosine}) {
    SCOPED_TRACE(mode == ClusterReceiver::Isotropic ? "isotropic" : "cosine");
    push_transport(r.elements, mode, 1, &cache);
    const std::vector<Rgb> kept_push = r.pushed();
    push_transport(r.elements, mode, 1);
    expect_same(kept_push, r.pushed(), "push_transport");

    const std::vector<Rgb> first = r.propagated(mode, &cache);

    // What a run changes between passes: the leaves' row-sum scales and the push
    // weights; the radiosity starts again from the emission.
    for (Element* e : r.elements) {
      if (e->child_span().empty()) e->gather_scale = 0.9f;
      e->push_weight *= 0.95f;
    }
    const std::vector<Rgb> kept = r.propagated(mode, &cache);
    const std::vector<Rgb> fresh = r.propagated(mode);
    expect_same(kept, fresh, "propagate after the scales changed");
    EXPECT_GT(differing(fresh, first), fresh.size() / 2) << "the changes must change the answer";

    for (Element* e : r.elements) {
      e->gather_scale = 1;
      e->push_weight /= 0.95f;
    }
  }
}

// The gather matrix push_transport leaves serves the one propagation that follows it:
// a later one, after the links changed, gathers over the new links.
TEST(PropagationCache, TheRowSumsMatrixServesOnePropagation) {
  Refined r("builtin:cornell", 1e-3);
  PropagationCache cache;
  push_transport(r.elements, ClusterReceiver::Cosine, 1, &cache);
  const std::vector<Rgb> lit = r.propagated(ClusterReceiver::Cosine, &cache);
  r.hierarchy.release_links(r.elements);
  const std::vector<Rgb> kept = r.propagated(ClusterReceiver::Cosine, &cache);
  expect_same(kept, r.propagated(ClusterReceiver::Cosine), "propagate after the links went");
  EXPECT_GT(differing(lit, kept), lit.size() / 2) << "without links nothing is reflected";
}

// Every element's links, in order.
std::vector<std::vector<Link>> links_of(const std::vector<Element*>& elements) {
  std::vector<std::vector<Link>> links(elements.size());
  for (std::size_t i = 0; i < elements.size(); ++i)
    links[i].assign(elements[i]->links.begin(), elements[i]->links.end());
  return links;
}

// Stores `links` as every element's links (all released first), as a refinement stage
// leaves them.
void store_all(Refined& r, const std::vector<std::vector<Link>>& links) {
  r.hierarchy.release_links(r.elements);
  for (std::size_t i = 0; i < r.elements.size(); ++i) {
    if (links[i].empty()) continue;
    r.hierarchy.store_links(*r.elements[i], links[i], 0);
    r.hierarchy.compact_links(*r.elements[i], 0);
  }
}

// After a stage that changed a few elements' links (a link's visibility, a link gone)
// and stored the others' again in another order, the next pass over the same elements
// gathers the changed elements' links again and keeps every other element's rows of
// the last propagation's matrix, and gives what a fresh pass gives: bit for bit with the
// links in their old order, and within rounding in a new one.
TEST(PropagationCache, OnlyChangedLinksAreGatheredAgain) {
  Refined r("builtin:cornell", 1e-3);
  for (ClusterReceiver mode : {ClusterReceiver::Isotropic, ClusterReceiver::Cosine}) {
    SCOPED_TRACE(mode == ClusterReceiver::Isotropic ? "isotropic" : "cosine");
    PropagationCache cache;
    EXPECT_EQ(push_transport(r.elements, mode, 1, &cache), 0u) << "no matrix to keep rows from";
    r.propagated(mode, &cache);

    const std::vector<std::vector<Link>> before = links_of(r.elements);
    std::vector<std::vector<Link>> after = before;
    // A surface with several links and a cluster with several links.
    std::size_t surface = after.size(), cluster = after.size();
    for (std::size_t i = 0; i < after.size(); ++i) {
      if (after[i].size() < 3) continue;
      if (r.elements[i]->is_cluster() && cluster == after.size()) cluster = i;
      if (!r.elements[i]->is_cluster() && surface == after.size()) surface = i;
    }
    ASSERT_LT(surface, after.size());
    ASSERT_LT(cluster, after.size());
    after[surface][1].set_visibility(after[surface][1].visibility() * 0.5);
    after[cluster].pop_back();

    // The same links: every row kept.
    store_all(r, before);
    EXPECT_EQ(push_transport(r.elements, mode, 1, &cache), r.elements.size());
    const std::vector<Rgb> same = r.propagated(mode, &cache);

    store_all(r, after);
    EXPECT_EQ(push_transport(r.elements, mode, 1, &cache), r.elements.size() - 2);
    const std::vector<Rgb> kept = r.propagated(mode, &cache);
    expect_same(kept, r.propagated(mode), "two elements' links changed");
    EXPECT_GT(differing(kept, same), 0u) << "the changed links must change the answer";

    // The others stored again in reverse order: rows kept (in their old order), the
    // sums within rounding of a fresh pass's.
    std::vector<std::vector<Link>> reversed = after;
    for (std::vector<Link>& l : reversed) std::reverse(l.begin(), l.end());
    store_all(r, reversed);
    EXPECT_EQ(push_transport(r.elements, mode, 1, &cache), r.elements.size());
    const std::vector<Rgb> reordered = r.propagated(mode, &cache);
    const std::vector<Rgb> fresh = r.propagated(mode);
    for (std::size_t i = 0; i < fresh.size(); ++i)
      EXPECT_LE((reordered[i] - fresh[i]).abs().maxCoeff(), 1e-12 * (1 + fresh[i].abs().maxCoeff()))
          << "element " << i;
    store_all(r, before);
  }
}

// After a stage that split some leaves (new elements, so new positions and slots; the
// split leaves' ancestors' open areas change), the next pass keeps the rows of the
// elements whose links and whose sources' areas are unchanged, renumbered, and gives
// what a fresh pass gives, bit for bit (no link was stored again).
TEST(PropagationCache, RowsAreRenumberedWhenElementsAreAdded) {
  for (ClusterReceiver mode : {ClusterReceiver::Isotropic, ClusterReceiver::Cosine}) {
    SCOPED_TRACE(mode == ClusterReceiver::Isotropic ? "isotropic" : "cosine");
    Refined r("builtin:cornell", 1e-3);
    PropagationCache cache;
    push_transport(r.elements, mode, 1, &cache);
    r.propagated(mode, &cache);

    // Leaves under a cluster that some link comes from.
    std::set<const Element*> sources;
    for (const Element* e : r.elements)
      for (const Link& l : e->links)
        if (l.source->is_cluster()) sources.insert(l.source);
    const auto under_source = [&](const Element& e) {
      for (const Element* a = e.parent; a != nullptr; a = a->parent)
        if (sources.count(a) != 0) return true;
      return false;
    };
    LockPool locks(2, 1);
    std::vector<Element*> split;
    for (Element* e : r.elements)
      if (split.size() < 8 && !e->is_cluster() && e->child_span().empty() && !e->links.empty() &&
          under_source(*e) && Hierarchy::can_subdivide(*e) &&
          !r.hierarchy.subdivide(*e, 0, locks).empty())
        split.push_back(e);
    ASSERT_EQ(split.size(), 8u);
    const std::size_t before = r.elements.size();
    r.elements = r.hierarchy.elements();
    ASSERT_GT(r.elements.size(), before);
    update_open_fractions(r.elements, r.hierarchy, r.rays, 1, 1, true);
    // A piece of one split leaf closed in (as a contact would): its ancestors' open
    // areas change, and so do the entries of every link from their clusters.
    split.front()->child_span().front().open = 0;
    update_open_fractions(r.elements, r.hierarchy, r.rays, 1, 1, true);
    update_push_weights(r.elements, r.transport, 1);

    const std::size_t kept = push_transport(r.elements, mode, 1, &cache);
    EXPECT_GT(kept, before / 2);
    EXPECT_LT(kept, before) << "the split leaves' clusters' rows must be made again";
    const std::vector<Rgb> renumbered = r.propagated(mode, &cache);
    expect_same(renumbered, r.propagated(mode), "elements added");
  }
}

// A cache made for one thread count, or for other elements, is made again.
TEST(PropagationCache, OtherThreadsOrElementsMakeItAgain) {
  Refined cornell("builtin:cornell", 1e-3);
  Refined office("builtin:office", 1e-2);
  PropagationCache cache;
  propagate(cornell.elements, 1e-6, 100, 1, ClusterReceiver::Isotropic, false, {}, 0, &cache);
  const std::vector<Rgb> one = cornell.radiosity();

  cornell.restart();
  propagate(cornell.elements, 1e-6, 100, 2, ClusterReceiver::Isotropic, false, {}, 0, &cache);
  expect_same(cornell.radiosity(), one, "two threads");

  propagate(office.elements, 1e-6, 100, 2, ClusterReceiver::Isotropic, false, {}, 0, &cache);
  const std::vector<Rgb> kept = office.radiosity();
  office.restart();
  propagate(office.elements, 1e-6, 100, 2);
  expect_same(kept, office.radiosity(), "other elements");
}

}  // namespace
}  // namespace hrad
