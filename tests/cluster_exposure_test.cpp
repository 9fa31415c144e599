// Cluster members' exposure (core/transport/cluster_exposure.h, cluster_members =
// exposed): the factors are shares of rays, a member hidden under another is exposed
// little, and the propagation keeps the light a cluster receives. (A furnace stays
// exact: SolverClusterReceiver in solver_test.cpp.)
#include "core/transport/cluster_exposure.h"
#include "core/hierarchy/hierarchy.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/builtin_scenes.h"
#include "core/solver/solver.h"
#include "tests/lit_room.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hrad {
namespace {

// A unit room lit from a lamp under its ceiling, a slab [0.3, 0.7] x [0.50, 0.52] x
// [0.3, 0.7] (a table top) and a small plate 1 cm under the slab facing up, hidden
// from the lamp by it. (Material 0: white; face 0 .. 5: room; 6: lamp; 7 .. 12: slab;
// 13: the hidden plate.)
Scene room_with_hidden_plate() {
  test::LitRoom r(0.6);
  const auto w = r.white;
  const auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d, std::uint32_t m) { r.quad(a, b, c, d, m); };
  const double y0 = 0.50, y1 = 0.52;
  quad({0.3, y1, 0.3}, {0.3, y1, 0.7}, {0.7, y1, 0.7}, {0.7, y1, 0.3}, w);  // slab top, +y
  quad({0.3, y0, 0.3}, {0.7, y0, 0.3}, {0.7, y0, 0.7}, {0.3, y0, 0.7}, w);  // bottom, -y
  quad({0.3, y0, 0.3}, {0.3, y0, 0.7}, {0.3, y1, 0.7}, {0.3, y1, 0.3}, w);  // x-
  quad({0.7, y0, 0.3}, {0.7, y1, 0.3}, {0.7, y1, 0.7}, {0.7, y0, 0.7}, w);  // x+
  quad({0.3, y0, 0.3}, {0.3, y1, 0.3}, {0.7, y1, 0.3}, {0.7, y0, 0.3}, w);  // z-
  quad({0.3, y0, 0.7}, {0.7, y0, 0.7}, {0.7, y1, 0.7}, {0.3, y1, 0.7}, w);  // z+
  quad({0.45, 0.49, 0.45}, {0.45, 0.49, 0.55}, {0.55, 0.49, 0.55}, {0.55, 0.49, 0.45}, w);
  return r.finish();
}

// The exposure of face f's top element along axis direction k, multiplied along its
// chain of clusters below the root (the root's box is the room: nothing leaves it).
double chain_exposure(const Hierarchy& h, std::uint32_t f, std::size_t k) {
  std::vector<const Element*> stack{&h.root()};
  while (!stack.empty()) {
    const Element* c = stack.back();
    stack.pop_back();
    for (const Element& e : c->child_span()) {
      if (e.is_cluster()) {
        stack.push_back(&e);
        continue;
      }
      if (e.face != f) continue;
      double x = 1;
      for (const Element* m = &e; m->parent && m->parent->parent; m = m->parent)
        x *= static_cast<double>(exposure_within_parent(*m)[k]);
      return x;
    }
  }
  return -1;
}

TEST(ClusterExposure, AMemberUnderAnotherIsHidden) {
  const Scene scene = room_with_hidden_plate();
  Hierarchy h(scene, 1);
  const RayScene rays = RayScene::from_scene(scene);
  const ExposureStats st = compute_cluster_exposure(h, rays, 1, 2);
  EXPECT_GT(st.rays_cast, 0u);
  EXPECT_GT(st.mean_exposure, 0.0);
  EXPECT_LE(st.mean_exposure, 1.0);
  constexpr std::size_t kUp = 2;  // +y
  const double top = chain_exposure(h, 7, kUp), hidden = chain_exposure(h, 13, kUp);
  EXPECT_GT(top, 0.7);     // the slab's top: its rays reach the ceiling
  EXPECT_LT(hidden, 0.3);  // the plate under it: most meet the slab's bottom 1 cm up
  EXPECT_GE(hidden, 0.0);
}

// The factors share the light a cluster receives out among its members: the power
// the leaves gather is the same as with every member alike (one sweep from the
// emission, so the same links and the same sources), and it goes elsewhere (the
// cluttered furnace: boxes stacked, plates lying on boxes, a cube in a narrow gap).
// Same up to the open-gain cap (core/solver/row_sums.cpp), which cuts the few leaves
// whose share passes 1.2 times their hemisphere: 1.2e-4 of the power here. (Light
// arriving along a direction in which no member is exposed was lost at first: 4.3e-4.)
TEST(ClusterExposure, ExposedSharesButKeepsTheGatheredPower) {
  const Scene scene = make_builtin("builtin:furnace?objects=2&rho=0.5");
  const auto solve = [&](ClusterMembers mode, std::vector<Solver::Leaf>* leaves) {
    SolverOptions o;
    o.iterations = 1;
    o.eps = 1e-2;
    o.max_gather_sweeps = 1;
    o.threads = 1;
    o.cluster_members = mode;
    Solver s(scene, o);
    s.run();
    *leaves = s.leaves();
    double power = 0;
    for (const Solver::Leaf& l : *leaves) {
      const Material& m = scene.materials[scene.faces[l.face].material];
      power += l.area * (l.radiosity[1] - m.emission[1]) / m.reflectance[1];
    }
    return power;
  };
  std::vector<Solver::Leaf> a, x;
  const double alike = solve(ClusterMembers::Alike, &a);
  const double exposed = solve(ClusterMembers::Exposed, &x);
  EXPECT_GT(alike, 0);
  EXPECT_NEAR(exposed, alike, 2e-4 * alike);
  ASSERT_EQ(a.size(), x.size());
  double moved = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    moved = std::max(moved, std::abs(a[i].radiosity[1] - x[i].radiosity[1]));
  EXPECT_GT(moved, 1e-3 * alike / 6) << "exposure changed nothing: no cluster receives light?";
}

}  // namespace
}  // namespace hrad
