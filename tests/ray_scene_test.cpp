#include "core/raycast/ray_scene.h"
#include "tests/polygon_soup.h"

#include "core/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace hrad {
namespace {

using test::Soup;

/// Unit square in z = 0 (a quad), and a triangle in z = -1 further along -z.
Soup square_and_triangle() {
  Soup s;
  s.add({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  s.add({{0, 0, -1}, {1, 0, -1}, {0, 1, -1}});
  return s;
}

TEST(RayScene, SegmentThroughQuadIsOccluded) {
  const RayScene rs = square_and_triangle().build();
  EXPECT_TRUE(rs.occluded({0.5, 0.5, 1}, {0.5, 0.5, -0.5}));
  EXPECT_TRUE(rs.occluded({0.5, 0.5, -0.5}, {0.5, 0.5, 1}));  // either direction
  EXPECT_TRUE(rs.occluded({0.2, 0.7, 1}, {0.9, 0.1, -0.5}));  // oblique
}

TEST(RayScene, SegmentBesideQuadIsNotOccluded) {
  const RayScene rs = square_and_triangle().build();
  EXPECT_FALSE(rs.occluded({1.5, 0.5, 1}, {1.5, 0.5, -2}));
  EXPECT_FALSE(rs.occluded({0.5, 0.5, 2}, {0.5, 0.5, 1}));      // stops short of it
  EXPECT_FALSE(rs.occluded({0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}));  // empty segment
}

TEST(RayScene, EndPointsOnSurfacesAreExcluded) {
  const RayScene rs = square_and_triangle().build();
  // Ending exactly on the quad, starting exactly on it, or joining the two polygons.
  EXPECT_FALSE(rs.occluded({0.5, 0.5, 1}, {0.5, 0.5, 0}));
  EXPECT_FALSE(rs.occluded({0.3, 0.2, 0}, {0.7, 0.9, 1}));
  EXPECT_FALSE(rs.occluded({0.25, 0.25, -1}, {0.5, 0.5, 0}));
  // ... but a segment reaching 1e-3 past the surface is blocked.
  EXPECT_TRUE(rs.occluded({0.5, 0.5, 1}, {0.5, 0.5, -1e-3}));
}

// Segments between `count` random points on the unit square (z = 0) and points above
// it, at angles to the surface down to 0.1 degree, both ways: how many `rs` reports
// occluded (by the surface carrying the end point).
int grazing_segments_occluded(const RayScene& rs, unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int wrong = 0;
  for (int i = 0; i < count; ++i) {
    const Vec3 on(0.1 + 0.8 * uni(rng), 0.1 + 0.8 * uni(rng), 0);
    const double elevation = (0.1 + 89.9 * uni(rng)) * std::numbers::pi / 180.0;
    const double azimuth = 2 * std::numbers::pi * uni(rng);
    const double len = 0.05 + 2 * uni(rng);
    const Vec3 dir(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                   std::sin(elevation));
    const Vec3 off = on + len * dir;
    wrong += rs.occluded(off, on) ? 1 : 0;
    wrong += rs.occluded(on, off) ? 1 : 0;
  }
  return wrong;
}

TEST(RayScene, EndPointOnSurfaceAtGrazingAnglesIsNotOccluded) {
  // kEndpointEpsilon = 1e-6 fails below about 1 degree. The surface carrying the end
  // point must never count.
  EXPECT_EQ(grazing_segments_occluded(square_and_triangle().build(), 7, 20000), 0);
}

/// Queries with clear answers (no end point or crossing within 1e-3 of an edge).
struct Query {
  Vec3 from, to;
};
std::vector<Query> standard_queries() {
  return {{{0.5, 0.5, 1}, {0.5, 0.5, -0.5}},  {{0.5, 0.5, 1}, {0.5, 0.5, 0}},
          {{1.5, 0.5, 1}, {1.5, 0.5, -2}},    {{0.2, 0.2, 1}, {0.2, 0.2, -2}},
          {{0.2, 0.2, -0.5}, {0.2, 0.2, -1}}, {{0.7, 0.7, -0.5}, {0.7, 0.7, -2}},
          {{0.3, 0.2, 0}, {0.7, 0.9, 1}},     {{0.9, 0.9, 0.5}, {0.1, 0.1, -1.5}}};
}

TEST(RayScene, AnswersDoNotDependOnScaleOrPosition) {
  const Soup base = square_and_triangle();
  const RayScene ref = base.build();
  const auto queries = standard_queries();
  // Down to 1e-30: a unit direction was 1e20 and more long in the normalised frame,
  // past what Embree accepts (its assertion ended the process).
  for (const double s : {1e-30, 1e-20, 1e-3, 1e3, 1e20}) {
    for (const Vec3& shift : {Vec3(0, 0, 0), Vec3(1e4 * s, -3e4 * s, 2e4 * s)}) {
      SCOPED_TRACE(testing::Message() << "scale " << s << " shift " << shift.transpose());
      const RayScene rs = base.transformed(s, shift).build();
      EXPECT_NEAR(rs.scale(), s * ref.scale(), 1e-9 * s);
      for (const Query& q : queries) {
        EXPECT_EQ(rs.occluded(s * q.from + shift, s * q.to + shift), ref.occluded(q.from, q.to))
            << q.from.transpose() << " -> " << q.to.transpose();
      }
      // Hit distances (along a unit direction) scale with the scene; u, v do not change.
      const auto a = ref.intersect({0.3, 0.6, 2}, {0, 0, -1});
      const auto b = rs.intersect(s * Vec3(0.3, 0.6, 2) + shift, {0, 0, -1});
      ASSERT_TRUE(a && b);
      EXPECT_EQ(a->prim, b->prim);
      EXPECT_NEAR(b->t, s * a->t, 1e-9 * s);
      EXPECT_NEAR(a->u, b->u, 1e-5);
      EXPECT_NEAR(a->v, b->v, 1e-5);
    }
  }
}

// A tiny triangle 30,000 units away made the bounding box 5e4 across, and the
// tolerances relative to it (a contact reach of 8 units) swallowed a unit scene. Given
// the bulk of the area, the frame and the tolerances follow it: the answers near the
// bulk are those of the scene without the far triangle, at grazing angles too.
TEST(RayScene, TolerancesFollowTheBulkWhenLittleGeometryIsFarAway) {
  Soup far = square_and_triangle();
  far.add({{3e4, 3e4, 3e4}, {3e4 + 0.1, 3e4, 3e4}, {3e4, 3e4 + 0.1, 3e4}});
  Aabb bulk;
  for (const Vec3& v : square_and_triangle().vertices) bulk.extend(v);
  const RayScene ref = square_and_triangle().build();
  const RayScene rs(far.vertices, far.indices, far.polys, RayScene::Build::Quality, {}, &bulk);
  EXPECT_TRUE(rs.local_frame());
  EXPECT_NEAR(rs.scale(), RayScene::kLocalFrame * bulk.diagonal(), 1e-12);
  EXPECT_FALSE(far.build().local_frame());  // without the bulk: the whole box
  EXPECT_GT(far.build().scale(), 5e4);
  for (const Query& q : standard_queries())
    EXPECT_EQ(rs.occluded(q.from, q.to), ref.occluded(q.from, q.to))
        << q.from.transpose() << " -> " << q.to.transpose();
  EXPECT_TRUE(rs.occluded({0.5, 0.5, 1}, {0.5, 0.5, -1e-3}));
  EXPECT_EQ(grazing_segments_occluded(rs, 11, 5000), 0);
  // The far triangle is still met, from near and from the bulk.
  const auto near = rs.intersect({3e4 + 0.02, 3e4 + 0.02, 3e4 + 1}, {0, 0, -1});
  ASSERT_TRUE(near);
  EXPECT_EQ(near->prim, 2u);
  EXPECT_NEAR(near->t, 1, 1e-2);
  const Vec3 to(3e4 + 0.02, 3e4 + 0.02, 3e4);
  const auto from_bulk = rs.intersect({0.5, 0.5, 1}, to - Vec3(0.5, 0.5, 1));
  ASSERT_TRUE(from_bulk);
  EXPECT_EQ(from_bulk->prim, 2u);
}

TEST(RayScene, IntersectTriangleGivesPrimDistanceAndBarycentrics) {
  Soup s;
  s.add({{5, 5, 5}, {6, 5, 5}, {5, 6, 5}});  // prim 0, out of the way
  s.add({{0, 0, 0}, {2, 0, 0}, {0, 4, 0}});  // prim 1: p = p0 + u (2,0,0) + v (0,4,0)
  const RayScene rs = s.build();
  const auto hit = rs.intersect({0.5, 1.0, 3}, {0, 0, -2});
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->prim, 1u);
  EXPECT_NEAR(hit->t, 1.5, 1e-12);  // t in units of |dir| = 2
  EXPECT_NEAR(hit->u, 0.25, 1e-6);
  EXPECT_NEAR(hit->v, 0.25, 1e-6);
  // From below too: polygons are two-sided.
  const auto below = rs.intersect({0.5, 1.0, -1}, {0, 0, 1});
  ASSERT_TRUE(below);
  EXPECT_EQ(below->prim, 1u);
  EXPECT_NEAR(below->t, 1.0, 1e-12);
}

TEST(RayScene, IntersectQuadUsesCornerZeroWithUTowardsOneAndVTowardsThree) {
  // A parallelogram with skewed edges: p = p0 + u (p1 - p0) + v (p3 - p0).
  const Vec3 p0(1, 1, 0), eu(2, 0.5, 0), ev(-0.5, 1.5, 0);
  Soup s;
  s.add({{9, 9, 9}, {9, 8, 9}, {8, 9, 9}});
  s.add({p0, p0 + eu, p0 + eu + ev, p0 + ev});
  const RayScene rs = s.build();
  // Points in both of Embree's internal triangles (split along p1-p3).
  for (const auto& [u, v] :
       {std::pair{0.2, 0.3}, std::pair{0.8, 0.9}, std::pair{0.9, 0.15}, std::pair{0.1, 0.85}}) {
    const Vec3 target = p0 + u * eu + v * ev;
    const auto hit = rs.intersect(target + Vec3(0, 0, 1), {0, 0, -1});
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->prim, 1u);
    EXPECT_NEAR(hit->t, 1.0, 1e-12);
    EXPECT_NEAR(hit->u, u, 1e-6);
    EXPECT_NEAR(hit->v, v, 1e-6);
  }
}

TEST(RayScene, LargerPolygonsAreFanSplitAndMappedBack) {
  Soup s;
  s.add({{0, 0, 5}, {1, 0, 5}, {0, 1, 5}});
  std::vector<Vec3> penta;
  for (int k = 0; k < 5; ++k) {
    const double a = 2 * std::numbers::pi * k / 5;
    penta.emplace_back(std::cos(a), std::sin(a), 0);
  }
  s.add({penta[0], penta[1], penta[2], penta[3], penta[4]});
  s.add({{0, 0, -5}, {1, 0, -5}, {1, 1, -5}, {0, 1, -5}});
  const RayScene rs = s.build();
  EXPECT_EQ(rs.polygon_count(), 3u);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-0.8, 0.8);
  for (int i = 0; i < 200; ++i) {
    const Vec3 target(uni(rng), uni(rng), 0);
    if (target.norm() > 0.8) continue;  // the pentagon's inscribed radius is 0.809
    const auto hit = rs.intersect(target + Vec3(0, 0, 1), {0, 0, -1});
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->prim, 1u);
    ASSERT_LE(hit->sub, 2u);
    const Vec3 p = (1 - hit->u - hit->v) * penta[0] + hit->u * penta[hit->sub + 1] +
                   hit->v * penta[hit->sub + 2];
    EXPECT_NEAR((p - target).norm(), 0, 1e-6);
  }
  const auto quad = rs.intersect({0.5, 0.5, -1}, {0, 0, -1});
  ASSERT_TRUE(quad);
  EXPECT_EQ(quad->prim, 2u);
}

TEST(RayScene, IntersectRespectsTmaxAndMisses) {
  const RayScene rs = square_and_triangle().build();
  EXPECT_FALSE(rs.intersect({0.5, 0.5, 1}, {0, 0, 1}));         // away from everything
  EXPECT_FALSE(rs.intersect({0.5, 0.5, 1}, {0, 0, -1}, 0.99));  // stops short
  const auto first = rs.intersect({0.2, 0.2, 1}, {0, 0, -1});
  ASSERT_TRUE(first);
  EXPECT_EQ(first->prim, 0u);
  EXPECT_NEAR(first->t, 1.0, 1e-12);
  // Starting on the quad, the next surface is the triangle below.
  const auto next = rs.intersect({0.2, 0.2, 0}, {0, 0, -1});
  ASSERT_TRUE(next);
  EXPECT_EQ(next->prim, 1u);
  EXPECT_NEAR(next->t, 1.0, 1e-12);
  EXPECT_THROW((void)rs.intersect({0, 0, 0}, {0, 0, 0}), std::invalid_argument);
}

// A camera 1e30 from a unit scene: 1e30 in the normalised frame is past where Embree's
// rays may start, and its assertion ended the process. The ray starts again near the
// scene, and t still counts from the given origin.
TEST(RayScene, RaysFromFarAwayHitWhatTheyPointAt) {
  const RayScene rs = square_and_triangle().build();
  for (const double far : {10.0, 1e10, 1e30}) {
    const auto hit = rs.intersect({0.2, 0.2, far}, {0, 0, -1});
    ASSERT_TRUE(hit) << far;
    EXPECT_EQ(hit->prim, 0u) << far;
    EXPECT_NEAR(hit->t, far, 1e-9 * far) << far;
    EXPECT_FALSE(rs.intersect({0.2, 0.2, far}, {0, 0, 1})) << far;            // away
    EXPECT_FALSE(rs.intersect({0.2, 5, far}, {0, 0, -1})) << far;             // beside
    EXPECT_FALSE(rs.intersect({0.2, 0.2, far}, {0, 0, -1}, far / 2)) << far;  // short
  }
  const auto slanted = rs.intersect({0.5 - 1e6, 0.3, 1e6}, Vec3(1, 0, -1));
  ASSERT_TRUE(slanted);
  EXPECT_EQ(slanted->prim, 0u);
}

TEST(RayScene, EmptySceneNeverHits) {
  const RayScene rs(std::span<const Vec3>{}, {}, {});
  EXPECT_EQ(rs.scale(), 0.0);
  EXPECT_FALSE(rs.occluded({0, 0, 0}, {1, 1, 1}));
  EXPECT_FALSE(rs.intersect({0, 0, 0}, {1, 1, 1}));
}

TEST(RayScene, RejectsBadInput) {
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<std::uint32_t> idx = {0, 1, 2};
  EXPECT_THROW(RayScene(v, idx, std::vector<PolygonRange>{{0, 2}}), std::invalid_argument);
  EXPECT_THROW(RayScene(v, idx, std::vector<PolygonRange>{{1, 3}}), std::invalid_argument);
  const std::vector<std::uint32_t> far = {0, 1, 7};
  EXPECT_THROW(RayScene(v, far, std::vector<PolygonRange>{{0, 3}}), std::invalid_argument);
  std::vector<Vec3> nan = v;
  nan[1].x() = std::nan("");
  EXPECT_THROW(RayScene(nan, idx, std::vector<PolygonRange>{{0, 3}}), std::invalid_argument);
}

TEST(RayScene, FromSceneUsesFaceIndices) {
  Scene sc;
  sc.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  sc.indices = {4, 5, 6, 0, 1, 2, 3};
  sc.faces = {{0, 3, 0}, {3, 4, 0}};
  sc.materials = {Material{}};
  const RayScene rs = RayScene::from_scene(sc);
  EXPECT_NEAR(rs.scale(), std::sqrt(3.0), 1e-12);
  const auto top = rs.intersect({0.2, 0.2, 2}, {0, 0, -1});
  ASSERT_TRUE(top);
  EXPECT_EQ(top->prim, 0u);
  const auto bottom = rs.intersect({0.8, 0.8, 2}, {0, 0, -1});
  ASSERT_TRUE(bottom);
  EXPECT_EQ(bottom->prim, 1u);
}

/// An axis-aligned box [lo, hi] of six quads facing out; returns its first face (-x;
/// then +x, -y, +y, -z, +z).
std::uint32_t add_box(Soup& s, const Vec3& lo, const Vec3& hi) {
  const auto first = static_cast<std::uint32_t>(s.polys.size());
  for (int a = 0; a < 3; ++a) {
    // Corners around the face in the plane of axes b and c (b x c = +a), reversed on the
    // low side so that each face's normal points out.
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (const bool high : {false, true}) {
      std::vector<Vec3> q(4, high ? hi : lo);
      for (int k = 0; k < 4; ++k) {
        q[k][b] = k == 1 || k == 2 ? hi[b] : lo[b];
        q[k][c] = k >= 2 ? hi[c] : lo[c];
      }
      if (!high) std::swap(q[1], q[3]);
      s.add(q);
    }
  }
  return first;
}

// Two keys of a keyboard (1.6 cm boxes 3 mm apart) in a scene 283 units across: the
// coincidence window beyond a hit was 4e-5 of the scene (11 mm), so a ray that met a
// key's side within that of its top edge found the top's back "coinciding" and counted
// as inside a solid (black bands along every small box's edges, in the solver's open
// fractions and probes and in `hrad reference`). The window now follows the polygon's
// own size; a box pushed against a wall still lies against it.
TEST(RayScene, CoincidenceFollowsThePolygonsOwnSize) {
  Soup s;
  s.add({{-100, -50, -100}, {100, -50, -100}, {100, -50, 100}, {-100, -50, 100}});  // far, down
  add_box(s, {0, 0, 0}, {0.016, 0.015, 0.016});
  const std::uint32_t b = add_box(s, {0.019, 0, 0}, {0.035, 0.015, 0.016});
  const std::uint32_t wall =
      s.add({{0, -0.01, -0.01}, {0, 0.03, -0.01}, {0, 0.03, 0.03}, {0, -0.01, 0.03}});
  const RayScene rs = s.build();
  ASSERT_GT(rs.scale(), 280);
  ASSERT_TRUE(rs.lies_against(b));  // the other key's side, 3 mm away, faces it
  // Its own share, or single precision's resolution there (about 0.1 mm: the key is 25
  // units from the frame's centre), far under the scene's 3e-5 x 283 (8.5 mm).
  EXPECT_GE(rs.coincidence(b), RayScene::kCoincidentShare * std::hypot(0.015, 0.016));
  EXPECT_LT(rs.coincidence(b), 1e-4);
  EXPECT_NEAR(rs.coincidence(0), 3 * RayScene::kEndpointEpsilon * rs.scale(), 1e-9);
  // From the gap, up onto the second key's side 0.5 mm under its top edge.
  const Vec3 from(0.0175, 0.005, 0.008), dir(0.0015, 0.0095, 0);
  const auto hit = rs.intersect(from, dir);
  ASSERT_TRUE(hit);
  ASSERT_EQ(hit->prim, b);
  EXPECT_FALSE(rs.back_coincides(from, dir, hit->t, hit->prim));
  // From inside the first key through its side, which lies in the wall's plane.
  ASSERT_TRUE(rs.lies_against(wall));
  EXPECT_TRUE(rs.back_coincides({0.008, 0.0075, 0.008}, {-1, 0, 0}, 0.008, wall));
}

/// Random small triangles in the unit cube.
Soup random_triangles(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0), off(-0.05, 0.05);
  Soup s;
  for (int i = 0; i < n; ++i) {
    const Vec3 c(uni(rng), uni(rng), uni(rng));
    s.add({c + Vec3(off(rng), off(rng), off(rng)), c + Vec3(off(rng), off(rng), off(rng)),
           c + Vec3(off(rng), off(rng), off(rng))});
  }
  return s;
}

/// Double-precision reference: does triangle (a,b,c) cross the open segment p->q, and
/// is the answer clear (crossing further than `margin` from the triangle's edges, in
/// barycentric terms, and from the segment's end points, in t)?
std::pair<bool, bool> crosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                              const Vec3& c, double margin) {
  const Vec3 d = q - p, e1 = b - a, e2 = c - a;
  const Vec3 h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-14) return {false, true};
  const Vec3 s = p - a;
  const double u = s.dot(h) / det;
  const Vec3 k = s.cross(e1);
  const double v = d.dot(k) / det;
  const double t = e2.dot(k) / det;
  const bool inside = u > 0 && v > 0 && u + v < 1 && t > 0 && t < 1;
  const bool clear = std::min({std::abs(u), std::abs(v), std::abs(1 - u - v), std::abs(t),
                               std::abs(1 - t)}) > margin;
  return {inside, clear};
}

TEST(RayScene, AgreesWithDoublePrecisionReferenceOnRandomSoup) {
  const Soup s = random_triangles(300, 11);
  const RayScene rs = s.build();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(-0.1, 1.1);
  int compared = 0, disagree = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p(uni(rng), uni(rng), uni(rng)), q(uni(rng), uni(rng), uni(rng));
    bool blocked = false, clear = true;
    for (const PolygonRange& r : s.polys) {
      const auto [in, ok] =
          crosses(p, q, s.vertices[s.indices[r.first]], s.vertices[s.indices[r.first + 1]],
                  s.vertices[s.indices[r.first + 2]], 1e-4);
      blocked = blocked || in;
      clear = clear && ok;
    }
    if (!clear) continue;
    ++compared;
    disagree += rs.occluded(p, q) != blocked ? 1 : 0;
  }
  EXPECT_GT(compared, 2500);
  EXPECT_EQ(disagree, 0);
}

TEST(RayScene, FastBuildGivesTheSameHitsAndNormalsFollowVertexOrder) {
  const Soup s = random_triangles(300, 13);
  const RayScene quality = s.build();
  const RayScene fast(s.vertices, s.indices, s.polys, RayScene::Build::Fast);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-0.1, 1.1);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(uni(rng), uni(rng), uni(rng)), d = Vec3(uni(rng), uni(rng), uni(rng)) - p;
    const auto a = quality.intersect(p, d), b = fast.intersect(p, d);
    ASSERT_EQ(a.has_value(), b.has_value()) << i;
    if (!a) continue;
    ++hits;
    EXPECT_EQ(a->prim, b->prim) << i;
    EXPECT_NEAR(a->t, b->t, 1e-9) << i;
  }
  EXPECT_GT(hits, 250);
  // normal(): the unit normal by the right-hand rule over the vertex order.
  const RayScene two = square_and_triangle().build();
  EXPECT_NEAR((two.normal(0) - Vec3::UnitZ()).norm(), 0, 1e-15);
  EXPECT_NEAR((two.normal(1) - Vec3::UnitZ()).norm(), 0, 1e-15);
  const auto hit = two.intersect({0.5, 0.5, 1}, {0, 0, -1});
  ASSERT_TRUE(hit);
  EXPECT_LT(Vec3(0, 0, -1).dot(two.normal(hit->prim)), 0);  // the front, from above
}

TEST(RayScene, ConcurrentQueriesGiveTheSerialAnswers) {
  const Soup s = random_triangles(2000, 21);
  const RayScene rs = s.build();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<Query> queries(4000);
  for (Query& q : queries) {
    q.from = Vec3(uni(rng), uni(rng), uni(rng));
    q.to = Vec3(uni(rng), uni(rng), uni(rng));
  }
  std::vector<char> occ_ref(queries.size());
  std::vector<double> t_ref(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    occ_ref[i] = rs.occluded(queries[i].from, queries[i].to);
    const auto h = rs.intersect(queries[i].from, queries[i].to - queries[i].from);
    t_ref[i] = h ? h->t : -1;
  }
  const std::uint64_t serial_rays = rs.rays_cast();
  EXPECT_EQ(serial_rays, 2 * queries.size());

  constexpr int kThreads = 4;
  std::vector<int> mismatches(kThreads, 0);
  std::vector<std::thread> threads;
  for (int th = 0; th < kThreads; ++th) {
    threads.emplace_back([&, th] {
      for (std::size_t j = 0; j < queries.size(); ++j) {
        const std::size_t i = (j * 7 + static_cast<std::size_t>(th) * 1000) % queries.size();
        const auto h = rs.intersect(queries[i].from, queries[i].to - queries[i].from);
        if (rs.occluded(queries[i].from, queries[i].to) != static_cast<bool>(occ_ref[i]) ||
            (h ? h->t : -1) != t_ref[i])
          ++mismatches[th];
      }
    });
  }
  for (auto& t : threads) t.join();
  for (int th = 0; th < kThreads; ++th) EXPECT_EQ(mismatches[th], 0) << "thread " << th;
  EXPECT_EQ(rs.rays_cast(), serial_rays + kThreads * 2 * queries.size());
}

// One thread's occlusion-ray throughput is measured in experiments/micro/scene_bench.cpp
// (BM_RayOcclusion), not bounded here.

}  // namespace
}  // namespace hrad
