// Accuracy of the transport estimates (core/transport/transport.h) against exact values: the
// visibility estimate must be the occluded share of the transport (not of the point
// pairs), and the cluster form factor must match the sum over the members where
// cluster links are accepted.
#include "core/hierarchy/hierarchy.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/scene.h"
#include "core/transport/form_factor.h"
#include "core/transport/transport.h"
#include "tests/solver_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

namespace hrad {
namespace {

const Element* surface_of_face(Hierarchy& h, std::uint32_t face) {
  for (const Element* e : h.elements())
    if (!e->is_cluster() && e->face == face) return e;
  return nullptr;
}

using Poly = std::vector<Vec3>;

// Receiver: the floor x in [0.1, 1.1], y in [0, 1], z = 0, facing up. Source: the
// wall x = 0, y in [0, 1], z in [0, 2], facing +x. A plate 1e-4 in front of the
// wall hides its upper half (z > 1) from every receiver point, so the exact
// transport F V is F(floor -> lower half of the wall). The lower half is nearer and
// less oblique, so it carries much more than half of F: the fraction of open point
// pairs (about 1/2) is far from the truth, and the kernel-weighted estimate must
// find it.
TEST(TransportAccuracy, VisibilityIsTheOccludedShareOfTheTransport) {
  SceneBuilder b("plate", "test");
  const auto m = b.add_material(test::material(0.5, 0), {"t", 0});
  const Poly floor{{0.1, 0, 0}, {1.1, 0, 0}, {1.1, 1, 0}, {0.1, 1, 0}};
  const Poly wall{{0, 0, 0}, {0, 1, 0}, {0, 1, 2}, {0, 0, 2}};
  const Poly lower{{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}};
  const Poly plate{{1e-4, -0.5, 1}, {1e-4, 1.5, 1}, {1e-4, 1.5, 2.5}, {1e-4, -0.5, 2.5}};
  ASSERT_GT(polygon_normal(floor).z(), 0);
  ASSERT_GT(polygon_normal(wall).x(), 0);
  b.add_polygon(floor, m, {"t", 1});
  b.add_polygon(wall, m, {"t", 2});
  b.add_polygon(plate, m, {"t", 3});
  const Scene scene = b.finish("t");
  Hierarchy h(scene, 1);
  const RayScene rays = RayScene::from_scene(scene);
  const Element* r = surface_of_face(h, 0);
  const Element* s = surface_of_face(h, 1);
  ASSERT_NE(r, nullptr);
  ASSERT_NE(s, nullptr);

  const double f_all = polygon_to_polygon_ff(floor, wall, 64);
  const double f_lower = polygon_to_polygon_ff(floor, lower, 64);
  // The test discriminates: half of F is at least 20 % away from the truth.
  ASSERT_LT(0.5 * f_all, 0.8 * f_lower);

  // The estimate for one pair depends on the seed; its mean over seeds is the
  // estimator's expectation. 4 rays per link as by default.
  const int seeds = 400;
  const auto mean_fv = [&](int k) {
    double sum = 0;
    std::uint64_t cast = 0;
    for (int seed = 1; seed <= seeds; ++seed) {
      const Transport t(h, rays, k, static_cast<std::uint64_t>(seed));
      sum += t.form_factor(*r, *s) * t.visibility(*r, *s, cast);
    }
    EXPECT_EQ(cast, static_cast<std::uint64_t>(k) * seeds);
    return sum / seeds;
  };
  const double fv4 = mean_fv(4), fv16 = mean_fv(16);
  std::cout << "F(floor->wall) " << f_all << ", exact F V " << f_lower << ", mean estimate " << fv4
            << " with 4 rays (" << fv4 / f_lower << " of exact), " << fv16 << " with 16 ("
            << fv16 / f_lower << ")\n";
  // The estimate is a ratio of kernel-weighted sums, which keeps a bias that falls
  // only slowly with the ray count (the kernel is heavy-tailed near the wall's foot):
  // measured -8.4 % with 4 rays (the default) and -7.1 % with 16 here, where the
  // plain fraction of open segments is 39 % low. Tolerance 10 % at 4 rays; 16 rays
  // must do better.
  EXPECT_NEAR(fv4, f_lower, 0.10 * f_lower);
  EXPECT_GT(fv16, fv4);
}

/// Adds a closed axis-aligned cube (faces outward) of edge a centred at c.
void add_cube(SceneBuilder& b, const Vec3& c, double a, std::uint32_t m) {
  test::add_room(b, c - Vec3::Constant(a / 2), c + Vec3::Constant(a / 2), m, 1, false);
}

/// Exact unoccluded F from cluster r to cluster s, receiver-area normalised: the
/// area-weighted sum of the member polygons' form factors (order 24 quadrature).
void member_faces(const Element& e, std::vector<std::uint32_t>& out) {
  if (!e.is_cluster()) {
    out.push_back(e.face);
    return;
  }
  for (const Element& c : e.child_span()) member_faces(c, out);
}

double exact_cluster_ff(const Scene& scene, const Element& r, const Element& s) {
  std::vector<std::uint32_t> fr, fs;
  member_faces(r, fr);
  member_faces(s, fs);
  double sum = 0, area = 0;
  for (std::uint32_t a : fr) {
    area += scene.face_area(a);
    for (std::uint32_t c : fs)
      sum += scene.face_area(a) *
             polygon_to_polygon_ff(scene.face_vertices(a), scene.face_vertices(c), 24);
  }
  return sum / area;
}

// Two unit cubes (each a cluster of its six faces) side by side along x, diagonal
// offset in y, at several separations. Where cluster links are accepted
// (d just above r_r + r_s) a single centre-to-centre evaluation was 22 % low (CC,
// docs/energy-budget.md); the cluster form factor, opened below twice the radii sum,
// must now be within 6 % of the members' sum there (measured +4 %), and far apart
// (measured -5.4 % at 8x). Not asserted: just beyond the opening distance a single
// evaluation is still low (measured -16 % at 2.5x for these cubes).
TEST(TransportAccuracy, ClusterFormFactorMatchesTheMembers) {
  for (double ratio : {1.05, 1.3, 1.8, 8.0}) {
    SceneBuilder b("cubes", "test");
    const auto m = b.add_material(test::material(0.5, 1), {"t", 0});
    const double radius = std::sqrt(3.0) / 2;  // bounding sphere of a unit cube
    const Vec3 axis = Vec3(1, 0.4, 0).normalized();
    const double d = ratio * 2 * radius;
    add_cube(b, Vec3(0, 0, 0), 1, m);
    add_cube(b, d * axis, 1, m);
    const Scene scene = b.finish("t");
    Hierarchy h(scene, 1);
    const RayScene rays = RayScene::from_scene(scene);
    const Transport t(h, rays, 4, 1);
    const Element& root = h.root();
    ASSERT_EQ(root.child_count, 2u) << "each cube must be a cluster";
    const Element& c0 = root.child_span()[0];
    const Element& c1 = root.child_span()[1];
    ASSERT_TRUE(c0.is_cluster() && c1.is_cluster());
    ASSERT_EQ(t.classify(c0, c1), PairClass::Regular) << ratio;
    const double exact = exact_cluster_ff(scene, c0, c1);
    const double f = t.form_factor(c0, c1);
    std::cout << "d / (r_r + r_s) = " << ratio << ": cluster F " << f << ", members' sum " << exact
              << " (" << f / exact << ")\n";
    EXPECT_NEAR(f, exact, 0.06 * exact) << ratio;
    // Reciprocity holds for the exact sums (equal areas): so must it, to the same
    // tolerance, for the estimate.
    EXPECT_NEAR(t.form_factor(c1, c0), f, 0.06 * exact) << ratio;
  }
}

// A receiver crossing the source's plane: the source is the unit square z = 0 facing
// up; the receiver the wall y = 1.5 facing it (-y), x in [0, 1], z in [-1, 0.2], so
// only its top sixth is in front of the source. Both of the default product rule's
// rows of points (z = -0.75 and -0.05) are behind it, where nothing is received, so
// the rule over the whole wall gives 0. Transport::form_factor integrates over the
// front part only; the reference is the product rule of order 256 over the whole
// wall, whose points behind the source correctly add 0.
TEST(TransportAccuracy, ReceiverCrossingTheSourcePlaneIsIntegratedOverItsFrontPart) {
  SceneBuilder b("crossing", "test");
  const auto m = b.add_material(test::material(0.5, 0), {"t", 0});
  const Poly source{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const Poly wall{{0, 1.5, -1}, {1, 1.5, -1}, {1, 1.5, 0.2}, {0, 1.5, 0.2}};
  ASSERT_GT(polygon_normal(source).z(), 0);
  ASSERT_LT(polygon_normal(wall).y(), 0);
  b.add_polygon(source, m, {"t", 1});
  b.add_polygon(wall, m, {"t", 2});
  const Scene scene = b.finish("t");
  Hierarchy h(scene, 1);
  const RayScene rays = RayScene::from_scene(scene);
  const Element* s = surface_of_face(h, 0);
  const Element* r = surface_of_face(h, 1);
  ASSERT_NE(r, nullptr);
  ASSERT_NE(s, nullptr);
  const Transport t(h, rays, 4, 1);
  const double exact = polygon_to_polygon_ff(wall, source, 256);
  ASSERT_EQ(polygon_to_polygon_ff(wall, source, Transport::kQuadratureOrder), 0.0)
      << "the case no longer shows the whole-element rule's blind spot";
  const double f = t.form_factor(*r, *s);
  std::cout << "F(wall -> floor) exact " << exact << ", estimate " << f << "\n";
  EXPECT_GT(exact, 0.005);
  EXPECT_NEAR(f, exact, 0.03 * exact);
}

}  // namespace
}  // namespace hrad
