// Row-sum statistics (core/solver/row_sums.h) on links set by hand, where every leaf's row
// sum is known exactly.
#include "core/solver/row_sums.h"
#include "core/hierarchy/hierarchy.h"
#include "core/raycast/ray_scene.h"
#include "core/transport/form_factor.h"
#include "tests/solver_test_util.h"

#include <gtest/gtest.h>

#include <vector>

namespace hrad {
namespace {

// A unit square at z = 0 facing up and one at height z facing down: towards the first
// for z > 0, away from it (back to back) for z < 0.
Scene two_squares(double z) {
  SceneBuilder b("two", "test");
  const auto m = b.add_material(test::material(0.5, 0), {"t", 0});
  using Poly = std::vector<Vec3>;
  b.add_polygon(Poly{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, m, {"t", 1});
  b.add_polygon(Poly{{0, 0, z}, {0, 1, z}, {1, 1, z}, {1, 0, z}}, m, {"t", 2});
  return b.finish("t");
}

// The element of each input face, by face index (a hierarchy not yet refined).
std::vector<Element*> face_elements(const std::vector<Element*>& els, std::size_t faces) {
  std::vector<Element*> face(faces, nullptr);
  for (Element* e : els)
    if (!e->is_cluster()) face[e->face] = e;
  return face;
}

// Each of two elements gets a link to the other with form factor f and visibility 1.
void link_each_other(Hierarchy& h, const std::vector<Element*>& face, float f) {
  const Link l0{face[1], f, 1.0f}, l1{face[0], f, 1.0f};
  h.store_links(*face[0], {&l0, 1}, 0);
  h.store_links(*face[1], {&l1, 1}, 0);
}

// Three leaves of areas 1, 2 and 1 with row sums 1.0, 1.1 and 0.98: the first and
// the third lie within 0.97-1.03, so the share within the band is (1 + 1) / 4.
TEST(RowSums, WithinBandIsTheOpenAreaShareNearOne) {
  SceneBuilder b("three", "test");
  const auto m = b.add_material(test::material(0.5, 0), {"t", 0});
  using Poly = std::vector<Vec3>;
  b.add_polygon(Poly{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, m, {"t", 1});
  b.add_polygon(Poly{{0, 0, 1}, {0, 2, 1}, {1, 2, 1}, {1, 0, 1}}, m, {"t", 2});
  b.add_polygon(Poly{{3, 0, 0}, {3, 1, 0}, {3, 1, 1}, {3, 0, 1}}, m, {"t", 3});
  const Scene scene = b.finish("t");
  Hierarchy h(scene, 1);
  const RayScene rays = RayScene::from_scene(scene);
  std::vector<Element*> els = h.elements();
  std::vector<Element*> face(3, nullptr);
  for (Element* e : els)
    if (!e->is_cluster()) face[e->face] = e;
  ASSERT_TRUE(face[0] && face[1] && face[2]);
  const float f[3] = {1.0f, 1.1f, 0.98f};
  for (int i = 0; i < 3; ++i) {
    const Link l{face[static_cast<std::size_t>((i + 1) % 3)], f[i], 1.0f};
    h.store_links(*face[static_cast<std::size_t>(i)], {&l, 1}, 0);
  }
  const RowSumStats st =
      apply_row_sums(els, RowSumMode::Keep, ClusterReceiver::Isotropic, h, rays, 1, 1, 1);
  EXPECT_NEAR(st.within_band, 0.5, 1e-9);
  EXPECT_NEAR(st.min, 0.98, 1e-6);
  EXPECT_NEAR(st.max, 1.1, 1e-6);
  EXPECT_NEAR(st.area_mean, (1.0 + 2 * 1.1 + 0.98) / 4, 1e-6);
}

// Four leaves with row sums 1.0, 1.1, 0.98 and 0 (no links), by mode: keep leaves every
// gather_scale at 1; clamp scales only the leaf above 1, to exactly 1; normalize scales
// each leaf with links to its own target 1 - escape (the escapes set here by hand, so
// no ray is cast), and leaves the leaf with nothing to scale alone. The statistics are
// of the uncorrected sums in every mode. Row sums come from float form factors and
// gather_scale is a float: compared to 1e-6 relative.
TEST(RowSums, ModesScaleTheLeavesAsDocumented) {
  SceneBuilder b("four", "test");
  const auto m = b.add_material(test::material(0.5, 0), {"t", 0});
  using Poly = std::vector<Vec3>;
  b.add_polygon(Poly{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, m, {"t", 1});
  b.add_polygon(Poly{{0, 0, 1}, {0, 2, 1}, {1, 2, 1}, {1, 0, 1}}, m, {"t", 2});
  b.add_polygon(Poly{{3, 0, 0}, {3, 1, 0}, {3, 1, 1}, {3, 0, 1}}, m, {"t", 3});
  b.add_polygon(Poly{{5, 0, 0}, {6, 0, 0}, {6, 1, 0}, {5, 1, 0}}, m, {"t", 4});
  const Scene scene = b.finish("t");
  const RayScene rays = RayScene::from_scene(scene);
  const double sums[4] = {1.0f, 1.1f, 0.98f, 0};
  const float escape[4] = {0.0f, 0.25f, 0.5f, 0.125f};

  struct Run {
    RowSumStats st;
    float scale[4];
  };
  const auto run = [&](RowSumMode mode) {
    Hierarchy h(scene, 1);
    std::vector<Element*> els = h.elements();
    const std::vector<Element*> face = face_elements(els, 4);
    for (int i = 0; i < 3; ++i) {
      const Link l{face[static_cast<std::size_t>((i + 1) % 3)], static_cast<float>(sums[i]), 1.0f};
      h.store_links(*face[static_cast<std::size_t>(i)], {&l, 1}, 0);
    }
    for (int i = 0; i < 4; ++i) face[static_cast<std::size_t>(i)]->uncovered = escape[i];
    Run r;
    r.st = apply_row_sums(els, mode, ClusterReceiver::Isotropic, h, rays, 16, 1, 1);
    for (int i = 0; i < 4; ++i) r.scale[i] = face[static_cast<std::size_t>(i)]->gather_scale;
    return r;
  };

  const Run keep = run(RowSumMode::Keep);
  for (const float s : keep.scale) EXPECT_EQ(s, 1.0f);
  EXPECT_EQ(keep.st.corrected, 0u);

  const Run clamp = run(RowSumMode::Clamp);
  EXPECT_EQ(clamp.scale[0], 1.0f);  // exactly 1: not above
  EXPECT_NEAR(clamp.scale[1] * sums[1], 1.0, 1e-6);
  EXPECT_EQ(clamp.scale[2], 1.0f);  // below 1: never raised
  EXPECT_EQ(clamp.scale[3], 1.0f);
  EXPECT_EQ(clamp.st.corrected, 1u);

  const Run norm = run(RowSumMode::Normalize);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(norm.scale[i] * sums[i], 1.0 - escape[i], 1e-6 * (1.0 - escape[i])) << i;
  EXPECT_EQ(norm.scale[0], 1.0f);  // its sum is its target already
  EXPECT_EQ(norm.scale[3], 1.0f);  // row sum 0: nothing to scale
  EXPECT_EQ(norm.st.corrected, 2u);
  EXPECT_EQ(norm.st.rays_cast, 0u);  // every escape was known

  for (const Run* r : {&keep, &clamp, &norm}) {
    EXPECT_EQ(r->st.min, 0.0);
    EXPECT_NEAR(r->st.max, 1.1, 1e-6);
    EXPECT_NEAR(r->st.area_mean, (1.0 + 2 * 1.1 + 0.98 + 0) / 5, 1e-6);
    EXPECT_EQ(r->st.open_capped, 0u);
  }
}

// normalize estimates a leaf's escape with `rays` rays when it is not known yet (once:
// it is kept in the element), and scales the leaf to 1 - that estimate. The lone
// square sees nothing, so every ray escapes: escape 1, target 0. Exact: tolerance 0.
TEST(RowSums, NormalizeCastsEscapeRaysOnlyForUnknownEscapes) {
  const Scene scene = two_squares(-1);  // back to back: every ray escapes
  const RayScene rays = RayScene::from_scene(scene);
  Hierarchy h(scene, 1);
  std::vector<Element*> els = h.elements();
  const std::vector<Element*> face = face_elements(els, 2);
  link_each_other(h, face, 0.5f);
  RowSumStats st =
      apply_row_sums(els, RowSumMode::Normalize, ClusterReceiver::Isotropic, h, rays, 16, 1, 1);
  EXPECT_EQ(st.rays_cast, 32u);
  for (const Element* e : face) {
    EXPECT_EQ(e->uncovered, 1.0f);
    EXPECT_EQ(e->gather_scale, 0.0f);
  }
  st = apply_row_sums(els, RowSumMode::Normalize, ClusterReceiver::Isotropic, h, rays, 16, 1, 1);
  EXPECT_EQ(st.rays_cast, 0u);  // known now
  EXPECT_EQ(st.corrected, 2u);
}

// normalize targets the share of a leaf's hemisphere that meets a lit surface. A unit
// floor square under a wider square 0.5 above it: when the cover faces the floor, the
// target is the floor's form factor to it (256 rays: 4 standard errors of a share are
// at most 4 x 0.5 / 16 = 0.125); when it turns its back to the floor, it is black there
// (as in `hrad reference`): every ray from an open point meets nothing lit, so the
// uncovered share is exactly 1 (the points whose rays mostly meet the back are taken
// as closed in and not counted, and the others' rays all meet the back or escape).
TEST(RowSums, NormalizeCountsBackFacesAsUncovered) {
  using Poly = std::vector<Vec3>;
  const Poly floor{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const Poly down{{-0.25, -0.25, 0.5}, {-0.25, 1.25, 0.5}, {1.25, 1.25, 0.5}, {1.25, -0.25, 0.5}};
  const Poly up{down[3], down[2], down[1], down[0]};
  for (const bool facing : {true, false}) {
    SceneBuilder b("cover", "test");
    const auto m = b.add_material(test::material(0.5, 0), {"t", 0});
    b.add_polygon(floor, m, {"t", 1});
    b.add_polygon(facing ? down : up, m, {"t", 2});
    const Scene scene = b.finish("t");
    const RayScene rays = RayScene::from_scene(scene);
    Hierarchy h(scene, 1);
    std::vector<Element*> els = h.elements();
    Element* leaf = nullptr;
    for (Element* e : els)
      if (!e->is_cluster() && e->face == 0) leaf = e;
    ASSERT_NE(leaf, nullptr);
    apply_row_sums(els, RowSumMode::Normalize, ClusterReceiver::Isotropic, h, rays, 256, 1, 1);
    if (facing) {
      EXPECT_NEAR(1.0 - leaf->uncovered, polygon_to_polygon_ff(floor, down, 6), 0.125);
      // Its standard error, from the spread over 64 points of 4 rays: near
      // sqrt(u (1 - u) / 256) = 0.03 for independent rays (u about 0.36), and not 0.
      EXPECT_GT(leaf->uncovered_se, 0.015f);
      EXPECT_LT(leaf->uncovered_se, 0.06f);
    } else {
      EXPECT_EQ(leaf->uncovered, 1.0f);
      EXPECT_EQ(leaf->uncovered_se, 0.0f);  // every point agrees
    }
  }
}

// The rays' target is noisy where part of a leaf's hemisphere is open; normalize shrinks
// a correction by d^2 / (d^2 + se^2), d the target less the row sum: a leaf with row
// sum 0.8 and target 1 is scaled to 1 (gather_scale 1.25) when its uncovered share is
// exact (se 0), to 0.8 + 0.2 / 2 = 0.9 when its standard error is 0.2, and to
// 0.8 + 0.2 / 17 when it is 0.8. Compared to 1e-6 (float scales).
TEST(RowSums, NormalizeShrinksACorrectionWithinTheTargetsNoise) {
  const Scene scene = two_squares(1);
  const RayScene rays = RayScene::from_scene(scene);
  for (const double se : {0.0, 0.2, 0.8}) {
    Hierarchy h(scene, 1);
    std::vector<Element*> els = h.elements();
    const std::vector<Element*> face = face_elements(els, 2);
    link_each_other(h, face, 0.8f);
    for (Element* e : face) {
      e->uncovered = 0;
      e->uncovered_se = static_cast<float>(se);
    }
    apply_row_sums(els, RowSumMode::Normalize, ClusterReceiver::Isotropic, h, rays, 16, 1, 1);
    const double d = 1 - 0.8, target = 0.8 + d * d * d / (d * d + se * se);
    for (const Element* e : face) EXPECT_NEAR(e->gather_scale * 0.8, target, 1e-6) << se;
  }
}

// normalize leaves a closed-in leaf (open fraction 0: it gathers nothing) alone, and
// lifts a leaf at most kNormalizeGainCap = 2 times: two facing unit squares 1 apart
// (nothing else), one closed in, the other with a link of F = 0.1 whose target, with
// its uncovered share set to 0, would be 10 times that.
TEST(RowSums, NormalizeLeavesClosedInLeavesAloneAndCapsTheGain) {
  const Scene scene = two_squares(1);
  const RayScene rays = RayScene::from_scene(scene);
  Hierarchy h(scene, 1);
  std::vector<Element*> els = h.elements();
  const std::vector<Element*> face = face_elements(els, 2);
  link_each_other(h, face, 0.1f);
  face[0]->uncovered = 0;
  face[1]->uncovered = 0;
  face[1]->open = 0;
  const RowSumStats st =
      apply_row_sums(els, RowSumMode::Normalize, ClusterReceiver::Isotropic, h, rays, 16, 1, 1);
  EXPECT_EQ(face[0]->gather_scale, 2.0f);
  EXPECT_EQ(face[1]->gather_scale, 1.0f);
  EXPECT_EQ(st.rays_cast, 0u);
}

// normalize takes a leaf's surplus out of what it inherits from cluster receivers first
// (a cluster hands its members light whether or not they see the source). Two facing
// squares under one cluster, each with its own link (F = 0.9, then 1.3) and the cluster
// a link of F = 0.3 that it hands to both (isotropic receiver), targets 1: a surplus of
// 0.2 leaves the cluster's part a third (gather_scale 1); a surplus of 0.6, more than
// the cluster's part, removes that part and scales the leaf's own by 1 / 1.3.
TEST(RowSums, NormalizeTakesASurplusFromClusterLightFirst) {
  for (const float own : {0.9f, 1.3f}) {
    const Scene scene = two_squares(1);
    const RayScene rays = RayScene::from_scene(scene);
    Hierarchy h(scene, 1);
    std::vector<Element*> els = h.elements();
    const std::vector<Element*> face = face_elements(els, 2);
    ASSERT_TRUE(h.root().is_cluster());
    link_each_other(h, face, own);
    const Link up{face[0], 0.3f, 1.0f};
    h.store_links(h.root(), {&up, 1}, 0);
    face[0]->uncovered = 0;
    face[1]->uncovered = 0;
    apply_row_sums(els, RowSumMode::Normalize, ClusterReceiver::Isotropic, h, rays, 16, 1, 1);
    for (const Element* e : face) {
      if (own < 1) {
        EXPECT_NEAR(e->cluster_scale, 1.0 / 3, 1e-6);
        EXPECT_EQ(e->gather_scale, 1.0f);
      } else {
        EXPECT_EQ(e->cluster_scale, 0.0f);
        EXPECT_NEAR(e->gather_scale, 1 / 1.3, 1e-6);
      }
    }
  }
}

}  // namespace
}  // namespace hrad
