// Open fractions (core/transport/open_fraction.h): the parts of faces closed in by contacts.
#include "core/transport/open_fraction.h"
#include "core/hierarchy/hierarchy.h"
#include "core/parallel/lock_pool.h"
#include "core/raycast/ray_scene.h"
#include "core/reference/path_tracer.h"
#include "core/scene/builtin_scenes.h"
#include "core/scene/probes.h"
#include "core/solver/solver.h"
#include "tests/lit_room.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>

namespace hrad {
namespace {

// In the cluttered furnace, a box stands in the floor's corner on [0.8, 1] x [0, 1]
// in x and z. Floor elements three levels down (cells of 0.125 m of the 1 m floor)
// wholly under it are closed in (w = 0), those far from every box are open (w = 1),
// and an interior element's w is the area-weighted mean of its children's.
TEST(OpenFraction, FloorUnderABoxIsClosedInAndOpenElsewhere) {
  const Scene scene = make_builtin("builtin:furnace?objects=2");
  Hierarchy h(scene, 1);
  const RayScene rays = RayScene::from_scene(scene);
  LockPool locks(2, 1);
  Element* floor = nullptr;
  for (Element* e : h.elements())
    if (!e->is_cluster() && e->depth == 0 && e->normal.y() > 0.99 && e->center.y() < 1e-9 &&
        e->area > 0.99)
      floor = e;
  ASSERT_NE(floor, nullptr);
  std::vector<Element*> grand;
  for (Element& k : h.subdivide(*floor, 0, locks))
    for (Element& g : h.subdivide(k, 0, locks))
      for (Element& c : h.subdivide(g, 0, locks)) grand.push_back(&c);
  ASSERT_EQ(grand.size(), 64u);
  int under = 0, clear = 0;
  for (const Element* g : grand) {
    const double w = estimate_open_fraction(*g, h, rays, 1);
    EXPECT_GE(w, 0.0);
    EXPECT_LE(w, 1.0);
    if (g->box.lo.x() >= 0.8 - 1e-9 && g->box.lo.z() >= 0.8 - 1e-9) {
      ++under;  // wholly under the corner box ([0.8, 1]^2 footprint)
      EXPECT_EQ(w, 0.0) << "centre " << g->center.transpose();
    }
    if (g->box.hi.x() <= 0.125 + 1e-9 && g->box.lo.z() >= 0.25 - 1e-9 &&
        g->box.hi.z() <= 0.375 + 1e-9) {
      ++clear;  // [0, 0.125] x [0.25, 0.375]: no box stands there
      EXPECT_EQ(w, 1.0) << "centre " << g->center.transpose();
    }
  }
  EXPECT_EQ(clear, 1);
  EXPECT_EQ(under, 1);

  std::vector<Element*> all = h.elements();
  // Its progress (for the progress line) rises to 1 on the calling thread, two threads
  // or one giving the same fractions.
  std::vector<double> shares;
  const OpenStats st =
      update_open_fractions(all, h, rays, 1, 2, true, [&](double s) { shares.push_back(s); });
  ASSERT_FALSE(shares.empty());
  EXPECT_TRUE(std::is_sorted(shares.begin(), shares.end()));
  EXPECT_EQ(shares.front(), 0.0);
  EXPECT_EQ(shares.back(), 1.0);
  std::vector<float> two;
  for (const Element* e : all) two.push_back(e->open);
  for (Element* e : all) e->open = -1;
  EXPECT_EQ(update_open_fractions(all, h, rays, 1, 1, true).rays_cast, st.rays_cast);
  for (std::size_t i = 0; i < all.size(); ++i) ASSERT_EQ(all[i]->open, two[i]);
  EXPECT_GT(st.rays_cast, 0u);
  EXPECT_LT(st.area_fraction, 1.0);
  EXPECT_GT(st.area_fraction, 0.85);
  for (const Element* e : all) {
    ASSERT_GE(e->open, 0.0f);
    ASSERT_LE(e->open, 1.0f);
    const auto kids = e->child_span();
    if (kids.empty()) continue;
    double a = 0;
    for (const Element& k : kids) a += k.area * static_cast<double>(k.open);
    EXPECT_NEAR(e->open, a / e->area, 1e-6);
  }
  // Nothing can be closed in: every element open, no ray.
  const OpenStats none = update_open_fractions(all, h, rays, 1, 1, false);
  EXPECT_EQ(none.rays_cast, 0u);
  for (const Element* e : all) ASSERT_EQ(e->open, 1.0f);
}

// The bottom face of the box standing in the floor's corner lies in the floor's plane
// facing it: both are in contact, so the bottom is closed in (w = 0). Its rays see
// only the void under the floor: before the contact ray it counted as open (w = 1).
// The underside of a floating box (at y = 0.40 over (0.16, 0.16)) stays open.
TEST(OpenFraction, ABoxBottomOnTheFloorIsClosedInAFloatingOneOpen) {
  const Scene scene = make_builtin("builtin:furnace?objects=2");
  Hierarchy h(scene, 1);
  const RayScene rays = RayScene::from_scene(scene);
  const Element* standing = nullptr;
  const Element* floating = nullptr;
  for (const Element* e : h.elements()) {
    if (e->is_cluster() || e->depth != 0 || e->normal.y() > -0.99) continue;
    if (std::abs(e->center.y()) < 1e-9 && e->center.x() > 0.8 && e->center.z() > 0.8) standing = e;
    if (std::abs(e->center.y() - 0.40) < 1e-6 && std::abs(e->center.x() - 0.16) < 0.05 &&
        std::abs(e->center.z() - 0.16) < 0.05)
      floating = e;
  }
  ASSERT_NE(standing, nullptr);
  ASSERT_NE(floating, nullptr);
  EXPECT_EQ(estimate_open_fraction(*standing, h, rays, 1), 0.0);
  EXPECT_EQ(estimate_open_fraction(*floating, h, rays, 1), 1.0);
}

// The shortcut for pieces that nothing crosses (core/raycast/face_crossings.h) gives
// what the full estimate gives, with far fewer rays: every face of the cluttered
// furnace (boxes and plates in contact and apart) cut into 16 pieces. In this
// watertight scene an uncrossed piece is wholly open or wholly closed in, and both
// estimates must say which.
TEST(OpenFraction, TheShortcutForUncrossedPiecesAgreesWithTheFullEstimate) {
  const Scene scene = make_builtin("builtin:furnace?objects=2");
  Hierarchy h(scene, 1);
  const RayScene rays = RayScene::from_scene(scene);
  LockPool locks(2, 1);
  std::vector<Element*> pieces;
  for (Element* e : h.elements()) {
    if (e->is_cluster() || e->depth != 0) continue;
    for (Element& k : h.subdivide(*e, 0, locks))
      for (Element& g : h.subdivide(k, 0, locks)) pieces.push_back(&g);
  }
  ASSERT_GT(pieces.size(), 1000u);
  std::uint64_t quick_rays = 0, full_rays = 0;
  int closed = 0, partly = 0;
  for (const Element* g : pieces) {
    const double quick = estimate_open_fraction(*g, h, rays, 7, &quick_rays);
    const double full = estimate_open_fraction(*g, h, rays, 7, &full_rays, false);
    if (quick == 0) ++closed;
    if (full > 0 && full < 1) {
      ++partly;  // crossed: the shortcut was not taken
      EXPECT_EQ(quick, full) << "centre " << g->center.transpose();
    } else {
      EXPECT_EQ(quick, full) << "centre " << g->center.transpose();
    }
  }
  EXPECT_GT(closed, 10);  // pieces under boxes and of the boxes' bottoms
  EXPECT_GT(partly, 10);  // pieces that a box's side runs through
  EXPECT_LT(3 * quick_rays, full_rays);
}

// Probes {closed in, lit}: the solver (with `o`) and the path tracer both give the first
// exactly 0 and the second more than `lit`.
void expect_dark_and_lit(const Scene& scene, const std::vector<Probe>& probes,
                         const SolverOptions& o, double lit) {
  Solver solver(scene, o);
  solver.run();
  const std::vector<Rgb> e = solver.probe_irradiance(probes);
  EXPECT_EQ(e[0][0], 0.0);
  EXPECT_GT(e[1][0], lit);
  const PathTracer pt(scene);
  PathTracerOptions po;
  po.max_samples = 1u << 12;
  const ReferenceResult r = pt.estimate(probes, po);
  EXPECT_EQ(r.probes[0].irradiance[0], 0.0);
  EXPECT_GT(r.probes[1].irradiance[0], lit);
}

// A probe point closed in by a contact (on the floor under the cluttered furnace's
// corner box, [0.8, 1]^2, lifted 1e-6 off it as `hrad reference --random-probes` lifts
// its points) sees only the box's black inside: its irradiance is 0, in the solver as in
// the path tracer. Before the rule the final gather read the radiosity of the box's
// bottom, closed in too but emitting like every face of the furnace (B = E = 1), and
// the path tracer's shadow rays reached the walls the box is pushed against through the
// box's coincident faces (0.37). A probe on the clear floor is lit (about 2).
TEST(OpenFraction, AProbeClosedInByAContactReadsZero) {
  const Scene scene = make_builtin("builtin:furnace?objects=2");
  const std::vector<Probe> probes = {{Vec3(0.9, 1e-6, 0.9), Vec3::UnitY()},    // under the box
                                     {Vec3(0.06, 1e-6, 0.3), Vec3::UnitY()}};  // clear floor
  const RayScene rays = RayScene::from_scene(scene);
  const Hierarchy h(scene, 1);
  std::uint64_t cast = 0;
  EXPECT_TRUE(point_closed_in(probes[0].p, probes[0].n, h, rays, 7, &cast));
  EXPECT_FALSE(point_closed_in(probes[1].p, probes[1].n, h, rays, 7, &cast));
  EXPECT_GT(cast, 0u);
  // Each direction: a ray and a second look at a coincident face; the clear floor stops
  // at its first front (with the 3 rays that find the point it meets open).
  EXPECT_LE(cast, 2u * 2u * kProbeOpenRays);
  SolverOptions o;
  o.eps = 1e-3;
  o.threads = 1;
  expect_dark_and_lit(scene, probes, o, 1.0);
}

// A point above a one-sided sheet is not closed in although most of its rays meet the
// sheet's back: the cabin's ceiling 12 cm above its central lamp strip (0.5 m wide,
// facing down), 6.5 cm from the strip's edge, gets light past the edge (the path
// tracer: about 0.65 W/m^2, a quarter of the lit ceiling's).
TEST(OpenFraction, APointAboveAOneSidedSheetIsOpen) {
  const Scene scene = make_builtin("builtin:cabin?rows=1");
  const Probe above{Vec3(0.185074, 2.7353962, 2.4), Vec3(-0.0878003, -0.9961381, 0)};
  const RayScene rays = RayScene::from_scene(scene);
  const Hierarchy h(scene, 1);
  EXPECT_FALSE(point_closed_in(above.p, above.n, h, rays, 7));
  const PathTracer pt(scene);
  PathTracerOptions po;
  po.max_samples = 1u << 12;
  EXPECT_GT(pt.estimate(std::span<const Probe>(&above, 1), po).probes[0].irradiance[0], 0.1);
}

// A point that looks mostly out of the Cornell box's open side (z < 0) sees nothing in
// most directions, and a little of the lit box in some: it is not closed in, whatever
// share of its rays leaves the scene.
TEST(OpenFraction, APointLookingOutOfAnOpenBoxIsOpen) {
  const Scene scene = make_builtin("builtin:cornell");
  const RayScene rays = RayScene::from_scene(scene);
  const Hierarchy h(scene, 1);
  const Vec3 p(2.78, 1e-5, 0.02), n = Vec3(0, 0.05, -1).normalized();
  for (std::uint64_t key = 0; key < 16; ++key)
    EXPECT_FALSE(point_closed_in(p, n, h, rays, key)) << key;
}

// A unit room lit from its ceiling, and a cabinet without a bottom pushed into the
// corner of the floor and the x+ wall (its back coincides with the wall). A probe on the
// wall inside the cabinet meets the cabinet's inside (back faces) and the floor inside
// it: a front, but one that is itself closed in. It sees nothing lit: 0, in the solver
// as in the path tracer. A probe on the wall above the cabinet is lit.
Scene room_with_open_bottom_cabinet() {
  test::LitRoom r(0.7);
  const auto w = r.white;
  const auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d, std::uint32_t m) { r.quad(a, b, c, d, m); };
  // The cabinet [0.6, 1] x [0, 0.3] x [0.3, 0.7], faces outward, no bottom.
  quad({0.6, 0, 0.3}, {0.6, 0, 0.7}, {0.6, 0.3, 0.7}, {0.6, 0.3, 0.3}, w);  // x-
  quad({1, 0, 0.3}, {1, 0.3, 0.3}, {1, 0.3, 0.7}, {1, 0, 0.7}, w);          // x+ (on the wall)
  quad({0.6, 0.3, 0.3}, {0.6, 0.3, 0.7}, {1, 0.3, 0.7}, {1, 0.3, 0.3}, w);  // top
  quad({0.6, 0, 0.3}, {0.6, 0.3, 0.3}, {1, 0.3, 0.3}, {1, 0, 0.3}, w);      // z-
  quad({0.6, 0, 0.7}, {1, 0, 0.7}, {1, 0.3, 0.7}, {0.6, 0.3, 0.7}, w);      // z+
  return r.finish();
}

TEST(OpenFraction, AProbeInsideACabinetWithoutABottomSeesNothing) {
  const Scene scene = room_with_open_bottom_cabinet();
  const std::vector<Probe> probes = {{Vec3(1 - 1e-6, 0.15, 0.5), -Vec3::UnitX()},  // inside
                                     {Vec3(1 - 1e-6, 0.6, 0.5), -Vec3::UnitX()}};  // above
  const RayScene rays = RayScene::from_scene(scene);
  const Hierarchy h(scene, 1);
  EXPECT_TRUE(point_closed_in(probes[0].p, probes[0].n, h, rays, 7));
  EXPECT_FALSE(point_closed_in(probes[1].p, probes[1].n, h, rays, 7));
  SolverOptions o;
  o.threads = 1;
  expect_dark_and_lit(scene, probes, o, 0.1);
}

}  // namespace
}  // namespace hrad
