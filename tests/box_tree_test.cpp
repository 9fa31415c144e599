// The box tree of the face crossings (core/base/box_tree.h): a sphere query finds every
// box within reach, each once, against a brute-force scan, and stops when asked.
#include "core/base/box_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace hrad {
namespace {

double distance(const Aabb& b, const Vec3& c) {
  return ((b.lo - c).cwiseMax(0.0) + (c - b.hi).cwiseMax(0.0)).norm();
}

TEST(BoxTree, FindsEveryBoxWithinReachOnceAsAScanDoes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-10, 10), size(0, 0.5);
  std::vector<Aabb> boxes;
  for (int i = 0; i < 3000; ++i) {
    Aabb b;
    const Vec3 c(u(rng), u(rng), i % 5 == 0 ? 0.0 : u(rng));  // some in one plane
    b.extend(c);
    b.extend(c + Vec3(size(rng), size(rng), i % 5 == 0 ? 0.0 : size(rng)));
    boxes.push_back(b);
  }
  // A fan of slivers from one corner: every box holds the origin.
  for (int i = 0; i < 500; ++i) {
    Aabb b;
    b.extend(Vec3::Zero());
    b.extend(Vec3(8 * std::cos(i * 0.01), 8 * std::sin(i * 0.01), 0));
    boxes.push_back(b);
  }
  boxes.emplace_back();  // an empty box: never reported
  const BoxTree tree(boxes);
  EXPECT_EQ(tree.size(), boxes.size() - 1);
  for (int q = 0; q < 300; ++q) {
    const Vec3 c(u(rng), u(rng), q % 4 == 0 ? 0.0 : u(rng));
    const double r = q == 0 ? 0.0 : q % 3 == 0 ? 8 * size(rng) : size(rng);
    std::vector<std::uint32_t> want, got;
    for (std::uint32_t i = 0; i < boxes.size(); ++i)
      if (!boxes[i].empty() && distance(boxes[i], c) <= r) want.push_back(i);
    EXPECT_TRUE(tree.for_each_near(c, r, [&](std::uint32_t i) {
      got.push_back(i);
      return true;
    }));
    std::sort(got.begin(), got.end());
    EXPECT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end()) << "query " << q;
    EXPECT_EQ(got, want) << "query " << q;
  }
}

TEST(BoxTree, StopsWhenTheVisitorSaysSo) {
  std::vector<Aabb> boxes(1000);
  for (Aabb& b : boxes) {
    b.extend(Vec3(-1, -1, -1));
    b.extend(Vec3(1, 1, 1));
  }
  const BoxTree tree(boxes);
  int calls = 0;
  EXPECT_FALSE(tree.for_each_near(Vec3::Zero(), 0.5, [&](std::uint32_t) { return ++calls < 7; }));
  EXPECT_EQ(calls, 7);
  // Nothing in reach, a negative or NaN radius, an empty tree: no call, nothing stopped.
  EXPECT_TRUE(tree.for_each_near(Vec3(5, 0, 0), 3.9, [](std::uint32_t) { return false; }));
  EXPECT_TRUE(tree.for_each_near(Vec3::Zero(), -1, [](std::uint32_t) { return false; }));
  EXPECT_TRUE(tree.for_each_near(Vec3::Zero(), std::nan(""), [](std::uint32_t) { return false; }));
  EXPECT_TRUE(BoxTree().for_each_near(Vec3::Zero(), 1, [](std::uint32_t) { return false; }));
}

}  // namespace
}  // namespace hrad
