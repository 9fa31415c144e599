// Face contacts (core/raycast/face_contacts.h): which polygons lie against another face to
// face, so that the open fractions' contact rays can skip every other polygon.
#include "core/raycast/face_contacts.h"
#include "core/raycast/face_twins.h"
#include "core/raycast/ray_scene.h"
#include "tests/polygon_soup.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace hrad {
namespace {

// The test soup with an axis-aligned square builder and the contact table.
struct Soup : test::Soup {
  // An axis-aligned square at height z, facing up (+z) or down.
  std::uint32_t square(double x0, double y0, double size, double z, bool up) {
    std::vector<Vec3> c = {
        {x0, y0, z}, {x0 + size, y0, z}, {x0 + size, y0 + size, z}, {x0, y0 + size, z}};
    if (!up) std::swap(c[1], c[3]);
    return add(c);
  }
  std::vector<std::uint8_t> contacts(double tolerance = 1e-4,
                                     std::vector<std::uint32_t> twins = {}) const {
    return find_face_contacts(vertices, indices, polys, twins, tolerance);
  }
};

TEST(FaceContacts, BoxBottomOnAFloorAndNothingElse) {
  Soup s;
  const auto floor = s.square(0, 0, 10, 0, true);
  const auto bottom = s.square(2, 2, 1, 0, false);       // a box's bottom standing on it
  const auto floating = s.square(6, 6, 1, 0.5, false);   // a box's bottom in the air
  const auto ceiling = s.square(0, 0, 10, 3, false);     // faces the floor, 3 away
  const auto elsewhere = s.square(20, 20, 1, 0, false);  // in the floor's plane, off it
  const auto c = s.contacts();
  EXPECT_EQ(c[floor], 1);
  EXPECT_EQ(c[bottom], 1);
  EXPECT_EQ(c[floating], 0);
  EXPECT_EQ(c[ceiling], 0);
  EXPECT_EQ(c[elsewhere], 0);
}

TEST(FaceContacts, ToleranceAngleAndOrientation) {
  Soup s;
  const auto floor = s.square(0, 0, 10, 0, true);
  const auto near = s.square(1, 1, 1, 0.5e-4, false);  // within 1e-4 of the floor
  const auto far = s.square(3, 3, 1, 2e-4, false);     // beyond it
  const auto same_way = s.square(5, 5, 1, 0, true);    // coplanar but facing the same way
  // Tilted by 1 degree (within kContactDegrees) and by 5 degrees about the x axis, both
  // touching the floor along one edge.
  const auto tilted = [&](double degrees, double x0) {
    const double a = degrees * std::numbers::pi / 180;
    const Vec3 y(0, std::cos(a), std::sin(a));
    const Vec3 o(x0, 7, 0);
    return s.add({o, o + y, o + Vec3(1, 0, 0) + y, o + Vec3(1, 0, 0)});  // faces down
  };
  const auto one_degree = tilted(1, 1);
  const auto five_degrees = tilted(5, 4);
  const auto c = s.contacts(1e-4);
  EXPECT_EQ(c[floor], 1);
  EXPECT_EQ(c[near], 1);
  EXPECT_EQ(c[far], 0);
  EXPECT_EQ(c[same_way], 0);
  EXPECT_EQ(c[one_degree], 1);
  EXPECT_EQ(c[five_degrees], 0);
}

// A two-sided sheet's twin is the same sheet, not a contact; another sheet against it is.
TEST(FaceContacts, TwinsDoNotCount) {
  Soup s;
  const auto front = s.square(0, 0, 1, 0, true);
  const auto back = s.square(0, 0, 1, 0, false);
  std::vector<std::uint32_t> twins = find_twins(s.vertices, s.indices, s.polys);
  ASSERT_EQ(twins[front], back);
  auto c = s.contacts(1e-4, twins);
  EXPECT_EQ(c[front], 0);
  EXPECT_EQ(c[back], 0);
  EXPECT_EQ(s.contacts()[front], 1);  // without the twin table they are two faces

  const auto other = s.square(0.5, 0.5, 1, 0, false);  // a second sheet against the front
  twins = find_twins(s.vertices, s.indices, s.polys);
  c = s.contacts(1e-4, twins);
  EXPECT_EQ(c[front], 1);
  EXPECT_EQ(c[other], 1);
  EXPECT_EQ(c[back], 0);
}

// Far from the scene's centre the plane offsets of two facing polygons differ by their
// normals' angle times the distance: the window must allow it, in any direction.
TEST(FaceContacts, FoundInEveryOrientationAndFarFromTheCentre) {
  for (int k = 0; k < 24; ++k) {
    const double t = 0.7 * k, p = 0.3 * k;
    const Vec3 n(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
    const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
    Soup s;
    const Vec3 at = 100 * u;                                 // far from the centre of the scene
    const auto a = s.add({at, at + u, at + u + v, at + v});  // faces n
    const double tilt = 1.5 * std::numbers::pi / 180;        // within kContactDegrees
    const Vec3 v2 = std::cos(tilt) * v + std::sin(tilt) * n;
    const auto b = s.add({at, at + v2, at + u + v2, at + u});  // faces about -n
    s.square(-100, -100, 1, -100, true);                       // widens the scene
    const auto c = s.contacts(1e-3);
    EXPECT_EQ(c[a], 1) << "orientation " << k;
    EXPECT_EQ(c[b], 1) << "orientation " << k;
  }
}

TEST(FaceContacts, DegenerateAndCrowdedPolygonsAreMarked) {
  Soup s;
  const auto line = s.add({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
  const auto lone = s.add({{5, 0, 0}, {5, 1, 0}, {5, 1, 1}, {5, 0, 1}});  // faces +x
  // More downward candidates in the plane z = 0 than are tested: the upward face is
  // marked although none of them overlaps it.
  const auto crowded = s.square(0, 0, 1, 0, true);
  for (int i = 0; i < kContactCandidates + 8; ++i) s.square(10 + 2 * i, 0, 1, 0, false);
  const auto c = s.contacts();
  EXPECT_EQ(c[line], 1);
  EXPECT_EQ(c[lone], 0);
  EXPECT_EQ(c[crowded], 1);
}

// The ray scene carries the table; a box standing on a floor marks its bottom and the floor.
TEST(FaceContacts, RaySceneLiesAgainst) {
  Soup s;
  const auto floor = s.square(-5, -5, 10, 0, true);
  const auto bottom = s.square(0, 0, 1, 0, false);
  const auto top = s.square(0, 0, 1, 1, true);
  const RayScene rays(s.vertices, s.indices, s.polys);
  EXPECT_TRUE(rays.lies_against(floor));
  EXPECT_TRUE(rays.lies_against(bottom));
  EXPECT_FALSE(rays.lies_against(top));
}

}  // namespace
}  // namespace hrad
