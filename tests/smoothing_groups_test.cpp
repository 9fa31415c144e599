// The smoothing groups at one point (core/output/smoothing_groups.h): the grid over the
// normals that many leaves take gives the partition that comparing every pair gives.
#include "core/output/smoothing_groups.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace hrad {
namespace {

// The groups by a flood over every pair: label[i] is the smallest leaf of i's group.
std::vector<std::size_t> by_pairs(const std::vector<std::uint32_t>& material,
                                  const std::vector<Vec3>& normal, double min_cos) {
  const std::size_t n = material.size();
  std::vector<std::size_t> label(n, n);
  for (std::size_t s = 0; s < n; ++s) {
    if (label[s] != n) continue;
    std::vector<std::size_t> todo{s};
    label[s] = s;
    while (!todo.empty()) {
      const std::size_t i = todo.back();
      todo.pop_back();
      for (std::size_t j = 0; j < n; ++j)
        if (label[j] == n && material[i] == material[j] && normal[i].dot(normal[j]) >= min_cos) {
          label[j] = s;
          todo.push_back(j);
        }
    }
  }
  return label;
}

void expect_same_partition(const std::vector<std::uint32_t>& material,
                           const std::vector<Vec3>& normal, double min_cos, const char* what) {
  std::vector<std::size_t> group;
  smoothing_groups(material, normal, min_cos, group);
  const std::vector<std::size_t> want = by_pairs(material, normal, min_cos);
  ASSERT_EQ(group.size(), material.size()) << what;
  for (std::size_t i = 0; i < group.size(); ++i) {
    ASSERT_EQ(group[group[i]], group[i]) << what << ": a group names a leaf of another";
    for (std::size_t j = i + 1; j < group.size(); ++j)
      ASSERT_EQ(group[i] == group[j], want[i] == want[j]) << what << ": leaves " << i << ", " << j;
  }
}

const double kMinCos = std::cos(30 * std::numbers::pi / 180);

TEST(SmoothingGroups, ManyLeavesAtAPointGroupAsEveryPairSays) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0, 1);
  for (const std::size_t n :
       {std::size_t{10}, std::size_t{64}, std::size_t{65}, std::size_t{700}}) {
    // Random directions, two materials, one normal that is not a unit vector.
    std::vector<std::uint32_t> material(n);
    std::vector<Vec3> normal(n);
    for (std::size_t i = 0; i < n; ++i) {
      material[i] = u(rng) < 0.3 ? 7 : 2;
      normal[i] = Vec3(g(rng), g(rng), g(rng)).normalized();
    }
    normal[n / 2] *= 0.5;
    expect_same_partition(material, normal, kMinCos, "random");
    // A cone's apex: normals 35 degrees from its axis, around it (neighbours close,
    // opposite sides not), and a fan of coplanar slivers whose normals differ by rounding.
    for (std::size_t i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
      const double t = 35 * std::numbers::pi / 180;
      normal[i] = i % 2 == 0
                      ? Vec3(std::sin(t) * std::cos(a), std::sin(t) * std::sin(a), std::cos(t))
                      : Vec3(1e-16 * u(rng), 0, -1).normalized();
      material[i] = 2;
    }
    expect_same_partition(material, normal, kMinCos, "cone and fan");
  }
}

// The three faces of a box's corner, each a fan of slivers from it: three groups, and no
// comparison of the leaves of two faces (90 degrees apart) one by one (3 x 10^8 here).
TEST(SmoothingGroups, ABoxCornerOfFansIsThreeGroups) {
  const std::size_t per_face = 10000;
  std::vector<std::uint32_t> material(3 * per_face, 1);
  std::vector<Vec3> normal;
  for (const Vec3& n : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)})
    normal.insert(normal.end(), per_face, n);
  std::vector<std::size_t> group;
  smoothing_groups(material, normal, kMinCos, group);
  for (std::size_t i = 0; i < group.size(); ++i)
    ASSERT_EQ(group[i], group[i / per_face * per_face]);
  EXPECT_NE(group[0], group[per_face]);
  EXPECT_NE(group[per_face], group[2 * per_face]);
  EXPECT_NE(group[0], group[2 * per_face]);
}

TEST(SmoothingGroups, AFanOfSliversIsOneGroup) {
  std::vector<std::uint32_t> material(100000, 1);
  std::vector<Vec3> normal(100000, Vec3(0, 1, 0));
  std::vector<std::size_t> group;
  smoothing_groups(material, normal, kMinCos, group);
  for (const std::size_t gi : group) ASSERT_EQ(gi, group[0]);
}

}  // namespace
}  // namespace hrad
