// Face crossings (core/raycast/face_crossings.h): which pieces of a polygon another
// polygon reaches into, so that the open fractions can decide every other piece from a
// few points.
#include "core/raycast/face_crossings.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/scene.h"

#include <gtest/gtest.h>

#include <vector>

namespace hrad {
namespace {

// A 10 x 10 floor at z = 0 facing up, a wall along its edge x = 0 facing +x, and a
// closed unit box standing on the floor over [2, 3] x [2, 3].
struct Room {
  Scene scene;
  std::uint32_t add(std::vector<Vec3> c) {
    Face f;
    f.first = static_cast<std::uint32_t>(scene.indices.size());
    f.count = static_cast<std::uint32_t>(c.size());
    for (const Vec3& p : c) {
      scene.indices.push_back(static_cast<std::uint32_t>(scene.vertices.size()));
      scene.vertices.push_back(p);
    }
    scene.faces.push_back(f);
    return static_cast<std::uint32_t>(scene.faces.size() - 1);
  }
  // An axis-aligned box's six faces, facing out.
  void box(const Vec3& lo, const Vec3& hi) {
    const auto at = [&](int x, int y, int z) {
      return Vec3(x ? hi.x() : lo.x(), y ? hi.y() : lo.y(), z ? hi.z() : lo.z());
    };
    add({at(0, 0, 0), at(0, 1, 0), at(1, 1, 0), at(1, 0, 0)});  // bottom, facing -z
    add({at(0, 0, 1), at(1, 0, 1), at(1, 1, 1), at(0, 1, 1)});  // top
    add({at(0, 0, 0), at(1, 0, 0), at(1, 0, 1), at(0, 0, 1)});  // -y
    add({at(0, 1, 0), at(0, 1, 1), at(1, 1, 1), at(1, 1, 0)});  // +y
    add({at(0, 0, 0), at(0, 0, 1), at(0, 1, 1), at(0, 1, 0)});  // -x
    add({at(1, 0, 0), at(1, 1, 0), at(1, 1, 1), at(1, 0, 1)});  // +x
  }
  std::uint32_t floor = add({{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}});
  std::uint32_t wall = add({{0, 0, 0}, {0, 10, 0}, {0, 10, 3}, {0, 0, 3}});
};

// A piece [x0, x1] x [y0, y1] of the floor, counter-clockwise seen from above.
std::vector<Vec3> piece(double x0, double y0, double x1, double y1) {
  return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
}

constexpr double kTol = 1e-3;

bool crossed(const Room& r, const RayScene& rays, const std::vector<Vec3>& corners,
             std::uint32_t own, const Vec3& n = Vec3(0, 0, 1)) {
  return crossed_inside(rays, r.scene, corners, n, own, kTol);
}

TEST(FaceCrossings, OnlyThePiecesAStandingBoxsSidesRunThrough) {
  Room r;
  r.box({2, 2, 0}, {3, 3, 1});
  const RayScene rays = RayScene::from_scene(r.scene);
  EXPECT_TRUE(crossed(r, rays, piece(0, 0, 10, 10), r.floor));        // the whole floor
  EXPECT_TRUE(crossed(r, rays, piece(1.5, 1.5, 3.5, 3.5), r.floor));  // round the box
  EXPECT_TRUE(crossed(r, rays, piece(2.5, 2.5, 4, 4), r.floor));      // partly under it
  // The box's side 2 kTol inside the piece's edge runs through it; 0.5 kTol inside, it
  // closes in a strip narrower than the tolerance, which does not count.
  EXPECT_TRUE(crossed(r, rays, piece(3 - 2 * kTol, 2.5, 4, 4), r.floor));
  EXPECT_FALSE(crossed(r, rays, piece(3 - 0.5 * kTol, 2.5, 4, 4), r.floor));
  // Wholly under the box (closed in all over) or clear of it (open all over).
  EXPECT_FALSE(crossed(r, rays, piece(2.2, 2.2, 2.8, 2.8), r.floor));
  EXPECT_FALSE(crossed(r, rays, piece(3.01, 2, 5, 3), r.floor));
  // The wall meets the floor along the floor's edge, which is no piece's inside.
  EXPECT_FALSE(crossed(r, rays, piece(0, 0, 1, 1), r.floor));
  EXPECT_FALSE(
      crossed(r, rays, {{0, 0, 0}, {0, 10, 0}, {0, 10, 3}, {0, 0, 3}}, r.wall, Vec3(1, 0, 0)));
}

TEST(FaceCrossings, ABoxJustAboveTheFloorAndOneSunkIntoIt) {
  Room above;
  above.box({2, 2, 3 * kTol}, {3, 3, 1});
  const RayScene a = RayScene::from_scene(above.scene);
  EXPECT_FALSE(crossed(above, a, piece(1.5, 1.5, 3.5, 3.5), above.floor));
  Room sunk;  // passes through the floor: its sides cross it
  sunk.box({2, 2, -0.5}, {3, 3, 1});
  const RayScene s = RayScene::from_scene(sunk.scene);
  EXPECT_TRUE(crossed(sunk, s, piece(1.5, 1.5, 3.5, 3.5), sunk.floor));
  EXPECT_FALSE(crossed(sunk, s, piece(4, 4, 5, 5), sunk.floor));
}

TEST(FaceCrossings, TheNextTileOfOneSurfaceDoesNotCrossButAFacingOneDoes) {
  Room r;
  r.add({{10, 0, 0}, {20, 0, 0}, {20, 10, 0}, {10, 10, 0}});  // next tile, facing up
  const RayScene rays = RayScene::from_scene(r.scene);
  EXPECT_FALSE(crossed(r, rays, piece(5, 0, 10, 10), r.floor));
  Room c;
  c.add({{4, 4, 0}, {4, 6, 0}, {6, 6, 0}, {6, 4, 0}});  // a plate's underside on the floor
  const RayScene cr = RayScene::from_scene(c.scene);
  EXPECT_TRUE(crossed(c, cr, piece(3, 3, 5, 5), c.floor));           // its edge runs through
  EXPECT_FALSE(crossed(c, cr, piece(4.5, 4.5, 5.5, 5.5), c.floor));  // wholly under it
}

TEST(FaceCrossings, ANonConvexPieceCountsAsCrossed) {
  Room r;
  const RayScene rays = RayScene::from_scene(r.scene);
  EXPECT_TRUE(crossed(r, rays, {{1, 1, 0}, {4, 1, 0}, {2, 2, 0}, {1, 4, 0}}, r.floor));
  EXPECT_FALSE(crossed(r, rays, {{1, 1, 0}, {4, 1, 0}, {1, 4, 0}}, r.floor));
}

}  // namespace
}  // namespace hrad
