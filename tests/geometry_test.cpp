#include "core/base/geometry.h"

#include <gtest/gtest.h>

namespace hrad {
namespace {

TEST(Geometry, UnitSquareAreaNormalCentroid) {
  const std::vector<Vec3> sq = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_DOUBLE_EQ(polygon_area(sq), 1.0);
  EXPECT_TRUE(polygon_normal(sq).isApprox(Vec3(0, 0, 1)));
  EXPECT_TRUE(polygon_centroid(sq).isApprox(Vec3(0.5, 0.5, 0)));
  EXPECT_TRUE(is_convex(sq));
  EXPECT_DOUBLE_EQ(relative_nonplanarity(sq), 0.0);
}

TEST(Geometry, ConcaveAndNonPlanarDetected) {
  const std::vector<Vec3> arrow = {{0, 0, 0}, {2, 0, 0}, {1, 0.5, 0}, {2, 2, 0}, {0, 2, 0}};
  EXPECT_FALSE(is_convex(arrow));
  const std::vector<Vec3> bent = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.2}, {0, 1, 0}};
  EXPECT_GT(relative_nonplanarity(bent), 0.01);
}

TEST(Geometry, AabbGrowsAndReportsDiagonal) {
  Aabb b;
  EXPECT_TRUE(b.empty());
  b.extend(Vec3(0, 0, 0));
  b.extend(Vec3(3, 4, 0));
  EXPECT_FALSE(b.empty());
  EXPECT_DOUBLE_EQ(b.diagonal(), 5.0);
}

}  // namespace
}  // namespace hrad
