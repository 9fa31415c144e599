// Row-sum statistics (core/row_sums.h) on links set by hand, where every leaf's row
// sum is known exactly.
#include "core/hierarchy.h"
#include "core/ray_scene.h"
#include "core/row_sums.h"
#include "tests/solver_test_util.h"

#include <gtest/gtest.h>

#include <vector>

namespace hrad {
namespace {

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

}  // namespace
}  // namespace hrad
