// The box tree of the face crossings (core/base/box_tree.h): a box query finds every box
// that meets it, each once, against a brute-force scan, and stops when asked.
#include "core/base/box_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace hrad {
namespace {

bool meet(const Aabb& a, const Aabb& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

// The box of half-widths r round c.
Aabb around(const Vec3& c, const Vec3& r) {
  Aabb b;
  b.extend(c - r);
  b.extend(c + r);
  return b;
}

TEST(BoxTree, FindsEveryBoxThatMeetsTheQueryOnceAsAScanDoes) {
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
    // A point, small and large boxes, and flat ones (a piece of a polygon in a plane).
    const double r = q == 0 ? 0.0 : q % 3 == 0 ? 8 * size(rng) : size(rng);
    const Aabb query = around(c, Vec3(r, q % 7 == 0 ? 0.0 : r, r));
    std::vector<std::uint32_t> want, got;
    for (std::uint32_t i = 0; i < boxes.size(); ++i)
      if (!boxes[i].empty() && meet(boxes[i], query)) want.push_back(i);
    EXPECT_TRUE(tree.for_each_overlapping(query, [&](std::uint32_t i) {
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
  EXPECT_FALSE(tree.for_each_overlapping(around(Vec3::Zero(), Vec3::Constant(0.5)),
                                         [&](std::uint32_t) { return ++calls < 7; }));
  EXPECT_EQ(calls, 7);
  // Nothing in reach, an empty or NaN query, an empty tree: no call, nothing stopped.
  const auto never = [](std::uint32_t) { return false; };
  EXPECT_TRUE(tree.for_each_overlapping(around(Vec3(5, 0, 0), Vec3::Constant(3.9)), never));
  EXPECT_TRUE(tree.for_each_overlapping(Aabb{}, never));
  EXPECT_TRUE(tree.for_each_overlapping(around(Vec3::Zero(), Vec3::Constant(std::nan(""))), never));
  EXPECT_TRUE(BoxTree().for_each_overlapping(around(Vec3::Zero(), Vec3::Ones()), never));
}

}  // namespace
}  // namespace hrad
