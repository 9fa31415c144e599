// Push weights (core/solver/push_weights.h): how an element's irradiance is shared among its
// children. Checked on the empty furnace room (six walls, each one input polygon).
#include "core/solver/push_weights.h"
#include "core/hierarchy/hierarchy.h"
#include "core/parallel/lock_pool.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/builtin_scenes.h"
#include "core/transport/transport.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

namespace hrad {
namespace {

struct Room {
  Scene scene = make_builtin("builtin:furnace?objects=0");
  Hierarchy h{scene, 1};
  RayScene rays = RayScene::from_scene(scene);
  Transport transport{h, rays, 4, 1};
  LockPool locks{2, 1};

  std::vector<Element*> walls() {
    std::vector<Element*> w;
    for (Element* e : h.elements())
      if (!e->is_cluster() && e->depth == 0) w.push_back(e);
    return w;
  }
  // Links at `p` from each of `sources`, with F from the transport and V = 1; every
  // source shows radiosity 1.
  void link(Element& p, const std::vector<Element*>& sources) {
    std::vector<Link> links;
    for (Element* s : sources) {
      s->B = Rgb::Ones();
      links.push_back(Link{s, static_cast<float>(transport.form_factor(p, *s)), 1.0f});
    }
    h.store_links(p, links, 0);
  }
};

double area_weighted_sum(std::span<const Element> kids) {
  double s = 0;
  for (const Element& c : kids) s += c.area * static_cast<double>(c.push_weight);
  return s;
}

double area_weighted_cluster_sum(std::span<const Element> kids) {
  double s = 0;
  for (const Element& c : kids) s += c.area * static_cast<double>(c.cluster_weight);
  return s;
}

// A floor element linked to all five other walls of the closed room: every point of it
// sees the whole hemisphere, so every child gets the same share (weight 1, to the
// accuracy of one point form factor per child), and the weights conserve energy.
TEST(PushWeights, ClosedRoomSharesEvenly) {
  Room room;
  std::vector<Element*> w = room.walls();
  ASSERT_EQ(w.size(), 6u);
  Element& floor = *w[0];
  std::vector<Element*> others(w.begin() + 1, w.end());
  room.link(floor, others);
  const auto kids = room.h.subdivide(floor, 0, room.locks);
  ASSERT_EQ(kids.size(), 4u);
  update_push_weights(room.h.elements(), room.transport, 1);
  EXPECT_NEAR(area_weighted_sum(kids), floor.area, 1e-6 * floor.area);
  for (const Element& c : kids) EXPECT_NEAR(c.push_weight, 1.0, 0.02);
  // The chain covers the whole hemisphere: nothing comes from clusters, nothing to share.
  for (const Element& c : kids) EXPECT_EQ(c.cluster_weight, 1.0f);
}

// Linked to one adjacent wall only, the children along the shared edge see much more
// of it than the far ones: their weights are above 1, the others' below, and the
// area-weighted mean is 1.
TEST(PushWeights, AdjacentWallFavoursTheNearChildren) {
  Room room;
  std::vector<Element*> w = room.walls();
  Element& floor = *w[0];
  // A wall that shares an edge with the floor (any of the four perpendicular ones).
  Element* side = nullptr;
  for (Element* e : w)
    if (e != &floor && std::abs(e->normal.dot(floor.normal)) < 0.5) side = e;
  ASSERT_NE(side, nullptr);
  room.link(floor, {side});
  const auto kids = room.h.subdivide(floor, 0, room.locks);
  update_push_weights(room.h.elements(), room.transport, 1);
  EXPECT_NEAR(area_weighted_sum(kids), floor.area, 1e-6 * floor.area);
  // With one link, each child's weight is its centre's form factor to the wall over
  // the area-weighted mean of those: 1.47 along the edge, 0.53 away from it.
  double lo = 1e9, hi = 0, mean_f = 0;
  for (const Element& c : kids) {
    const double f = room.transport.form_factor_from_point(c.center, c.normal, *side);
    mean_f += c.area * f / floor.area;
  }
  for (const Element& c : kids) {
    const double f = room.transport.form_factor_from_point(c.center, c.normal, *side);
    EXPECT_NEAR(c.push_weight, f / mean_f, 1e-5);
    lo = std::min(lo, static_cast<double>(c.push_weight));
    hi = std::max(hi, static_cast<double>(c.push_weight));
  }
  EXPECT_GT(hi, 1.4);
  EXPECT_LT(lo, 0.6);
  // The rest of each child's view (1 - its form factor to the wall) is what the
  // clusters above would fill: the children along the edge, which see more of the
  // wall, get less of that light, by 1 - f over its area-weighted mean.
  EXPECT_NEAR(area_weighted_cluster_sum(kids), floor.area, 1e-6 * floor.area);
  for (const Element& c : kids) {
    const double f = room.transport.form_factor_from_point(c.center, c.normal, *side);
    EXPECT_NEAR(c.cluster_weight, (1 - f) / (1 - mean_f), 1e-5);
    EXPECT_EQ(c.cluster_weight<1, c.push_weight> 1);
  }
  // Below the linked element its links go on shaping the shares: the floor's links are
  // in the chain of kids[0], which has none of its own, so kids[0]'s children are
  // weighed by their own centres' form factors to the wall relative to their siblings
  // (before, they got 1 and a leaf in the corner kept its ancestors' mean).
  Element& quarter = kids[0];
  const auto grandkids = room.h.subdivide(quarter, 0, room.locks);
  update_push_weights(room.h.elements(), room.transport, 1);
  double mean_g = 0;
  for (const Element& g : grandkids)
    mean_g +=
        g.area * room.transport.form_factor_from_point(g.center, g.normal, *side) / quarter.area;
  EXPECT_NEAR(area_weighted_sum(grandkids), quarter.area, 1e-6 * quarter.area);
  for (const Element& g : grandkids)
    EXPECT_NEAR(g.push_weight,
                room.transport.form_factor_from_point(g.center, g.normal, *side) / mean_g, 1e-5);
  // Children of an element with no link on it or on a surface ancestor, and of
  // clusters, get 1.
  Element* other = nullptr;
  for (Element* e : w)
    if (e != &floor && e != side) other = e;
  const auto unlinked = room.h.subdivide(*other, 0, room.locks);
  update_push_weights(room.h.elements(), room.transport, 1);
  for (const Element& c : unlinked) EXPECT_EQ(c.push_weight, 1.0f);
  for (Element* e : room.h.elements()) {
    if (!e->is_cluster()) continue;
    for (const Element& c : e->child_span()) EXPECT_EQ(c.push_weight, 1.0f);
  }
}

// A chain longer than kPushExactChain: the floor linked to each of the ceiling's 4,096
// pieces (weak links, radiosity 0.2) and to one adjacent wall (strong). Only the
// strongest kPushExactChain links are evaluated at each child, the others add their
// link's value to every child alike: the evaluations stay bounded, energy is kept, and
// the weights are within 1 % of those from every link (the ceiling's pieces vary
// little over the floor's quarters; the wall decides the shares).
TEST(PushWeights, LongChainsEvaluateTheirStrongestLinks) {
  Room room;
  std::vector<Element*> w = room.walls();
  Element& floor = *w[0];
  Element *ceiling = nullptr, *side = nullptr;
  for (Element* e : w) {
    if (e->normal.dot(floor.normal) < -0.5) ceiling = e;
    if (e != &floor && std::abs(e->normal.dot(floor.normal)) < 0.5) side = e;
  }
  ASSERT_NE(ceiling, nullptr);
  ASSERT_NE(side, nullptr);
  std::vector<Element*> pieces{ceiling};
  for (int level = 0; level < 6; ++level) {
    std::vector<Element*> next;
    for (Element* e : pieces)
      for (Element& c : room.h.subdivide(*e, 0, room.locks)) next.push_back(&c);
    pieces = next;
  }
  ASSERT_EQ(pieces.size(), 4096u);
  std::vector<Element*> sources = pieces;
  sources.push_back(side);
  room.link(floor, sources);
  for (Element* e : pieces) e->B = Rgb::Constant(0.2);
  const auto kids = room.h.subdivide(floor, 0, room.locks);
  PushWeights weights;
  weights.update(room.h.elements(), room.transport, 2);
  weights.apply(false);
  // Only the floor's children have a chain (the ceiling's pieces have no links).
  EXPECT_EQ(weights.evaluations(), kids.size() * kPushExactChain);
  EXPECT_NEAR(area_weighted_sum(kids), floor.area, 1e-6 * floor.area);
  // Every link at every child: the side's, and the pieces' (differential form factor,
  // as the weights weigh a source farther than 3 of its radii).
  std::vector<double> exact;
  double mean = 0;
  for (const Element& c : kids) {
    double f = room.transport.form_factor_from_point(c.center, c.normal, *side) * side->B.sum();
    for (const Element* s : pieces) {
      const Vec3 d = s->center - c.center;
      const double d2 = d.squaredNorm();
      f +=
          s->area * c.normal.dot(d) * -s->normal.dot(d) / (std::numbers::pi * d2 * d2) * s->B.sum();
    }
    exact.push_back(f);
    mean += c.area * f / floor.area;
  }
  double lo = 1e9, hi = 0;
  for (std::size_t k = 0; k < kids.size(); ++k) {
    EXPECT_NEAR(kids[k].push_weight, exact[k] / mean, 0.01 * exact[k] / mean) << k;
    lo = std::min(lo, static_cast<double>(kids[k].push_weight));
    hi = std::max(hi, static_cast<double>(kids[k].push_weight));
  }
  EXPECT_GT(hi, 1.2);  // the children along the wall's edge
  EXPECT_LT(lo, 0.8);
}

// push_visibility = child: a child behind an occluder gets its own, lower visibility to
// the source instead of its parent's mean. The floor of the room with a floating cube
// and octahedron, linked to the ceiling with the visibility its rays see (partly
// blocked): with the link's visibility every child's weight is its centre's form factor
// relative to the others' (as above); with the children's own, the child that sees the
// least of the ceiling loses most, the one that sees the most gains, and the
// area-weighted mean stays 1 in both modes.
TEST(PushWeights, ChildVisibilityMovesLightAwayFromTheShadowedChildren) {
  const Scene scene = make_builtin("builtin:furnace?objects=1");
  Hierarchy h{scene, 1};
  const RayScene rays = RayScene::from_scene(scene);
  const Transport transport{h, rays, 16, 1};
  LockPool locks{2, 1};
  Element *floor = nullptr, *ceiling = nullptr;
  for (Element* e : h.elements()) {
    if (e->is_cluster() || e->depth != 0 || e->area < 0.5) continue;  // the room's walls
    if (e->normal.y() > 0.5) floor = e;
    if (e->normal.y() < -0.5) ceiling = e;
  }
  ASSERT_NE(floor, nullptr);
  ASSERT_NE(ceiling, nullptr);
  std::uint64_t cast = 0;
  const double v = transport.visibility(*floor, *ceiling, cast);
  ASSERT_GT(v, 0.5);
  ASSERT_LT(v, 1.0) << "the floating objects should hide part of the ceiling";
  ceiling->B = Rgb::Ones();
  const std::vector<Link> links{Link{
      ceiling, static_cast<float>(transport.form_factor(*floor, *ceiling)), static_cast<float>(v)}};
  h.store_links(*floor, links, 0);
  const auto kids = h.subdivide(*floor, 0, locks);
  ASSERT_EQ(kids.size(), 4u);
  PushWeights weights;
  EXPECT_EQ(weights.update(h.elements(), transport, 1, PushVisibility::Link), 0u);
  weights.apply(false);
  std::vector<double> by_link;
  for (const Element& c : kids) by_link.push_back(c.push_weight);
  EXPECT_NEAR(area_weighted_sum(kids), floor->area, 1e-6 * floor->area);
  EXPECT_EQ(weights.update(h.elements(), transport, 1, PushVisibility::Child), 4u * 16u)
      << "one visibility estimate per child of the partly visible link";
  weights.apply(false);
  EXPECT_NEAR(area_weighted_sum(kids), floor->area, 1e-6 * floor->area);
  std::size_t darkest = 0, brightest = 0;
  std::vector<double> own;
  for (const Element& c : kids) {
    std::uint64_t r = 0;
    own.push_back(transport.visibility(c, *ceiling, r));
  }
  for (std::size_t k = 0; k < kids.size(); ++k) {
    if (own[k] < own[darkest]) darkest = k;
    if (own[k] > own[brightest]) brightest = k;
  }
  ASSERT_GT(own[brightest] - own[darkest], 0.1) << "the occluders should shade one child more";
  EXPECT_LT(kids[darkest].push_weight / by_link[darkest], 0.95);
  EXPECT_GT(kids[brightest].push_weight / by_link[brightest], 1.02);
  // The next update on the same hierarchy reuses the children's visibilities: no rays,
  // the same weights. A new level below (the children of one child, which inherit the
  // floor's link) casts rays for its own children only.
  std::vector<float> first;
  for (const Element& c : kids) first.push_back(c.push_weight);
  EXPECT_EQ(weights.update(h.elements(), transport, 1, PushVisibility::Child), 0u);
  weights.apply(false);
  for (std::size_t k = 0; k < kids.size(); ++k) EXPECT_EQ(kids[k].push_weight, first[k]);
  const auto grandkids = h.subdivide(kids[darkest], 0, locks);
  EXPECT_EQ(weights.update(h.elements(), transport, 1, PushVisibility::Child),
            grandkids.size() * 16u);
  weights.apply(false);
  for (std::size_t k = 0; k < kids.size(); ++k) EXPECT_EQ(kids[k].push_weight, first[k]);
}

}  // namespace
}  // namespace hrad
