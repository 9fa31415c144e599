#include "core/solver.h"
#include "tests/solver_test_util.h"

#include <gtest/gtest.h>

namespace hrad {
namespace {

Scene furnace(double rho, double e, bool object) {
  SceneBuilder b("furnace", "test");
  const auto m = b.add_material(test::material(rho, e), {"t", 0});
  test::add_room(b, Vec3(0, 0, 0), Vec3(1, 1, 1), m, 2, true);
  if (object) test::add_room(b, Vec3(0.3, 0.2, 0.35), Vec3(0.6, 0.5, 0.7), m, 1, false);
  return b.finish("t");
}

void expect_uniform(const Solver& s, double expected, double rel) {
  const RenderMesh mesh = s.render_mesh();
  ASSERT_FALSE(mesh.radiosity.empty());
  for (const Rgb& b : mesh.radiosity)
    ASSERT_NEAR(b[0], expected, rel * expected) << "radiosity differs from E/(1-rho)";
}

TEST(SolverFurnace, EmptyRoomReachesClosedForm) {
  for (double rho : {0.5, 0.9}) {
    const Scene scene = furnace(rho, 1.0, false);
    SolverOptions o;
    o.iterations = 2;
    Solver s(scene, o);
    const RunStats st = s.run();
    EXPECT_GT(st.iterations.back().links, 0u);
    expect_uniform(s, 1.0 / (1 - rho), 1e-3);
  }
}

}  // namespace
}  // namespace hrad
