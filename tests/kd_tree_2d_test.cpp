// The k-d tree of the ear clipping (core/base/kd_tree_2d.h): a box query finds every
// indexed point in the box, against a brute-force scan.
#include "core/base/kd_tree_2d.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace hrad {
namespace {

TEST(KdTree2, FindsEveryPointInABoxAsAScanDoes) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-10, 10);
  std::vector<KdTree2::Point> at;
  for (int i = 0; i < 5000; ++i) at.emplace_back(u(rng), i % 7 == 0 ? 3.0 : u(rng));
  at.insert(at.end(), 40, KdTree2::Point(1, 1));  // many copies of one point
  std::vector<std::size_t> ids;
  for (std::size_t i = 0; i < at.size(); i += 2) ids.push_back(i);  // every other one
  const KdTree2 tree(at, ids);
  for (int q = 0; q < 300; ++q) {
    KdTree2::Point a(u(rng), u(rng)), b(u(rng), u(rng));
    if (q % 3 == 0) b = a + KdTree2::Point(0.01, 15);  // long and thin, as a comb's ears
    if (q == 1) a = b = KdTree2::Point(1, 1);          // a point box on the copies
    const KdTree2::Point lo = a.cwiseMin(b), hi = a.cwiseMax(b);
    std::vector<std::size_t> want, got;
    for (const std::size_t i : ids)
      if ((at[i].array() >= lo.array()).all() && (at[i].array() <= hi.array()).all())
        want.push_back(i);
    EXPECT_TRUE(tree.for_each_in_box(lo, hi, [&](std::size_t i) {
      if ((at[i].array() >= lo.array()).all() && (at[i].array() <= hi.array()).all())
        got.push_back(i);
      return true;
    }));
    std::sort(want.begin(), want.end());
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want) << "query " << q;
  }
}

TEST(KdTree2, StopsWhenTheVisitorSaysSo) {
  std::vector<KdTree2::Point> at;
  for (int i = 0; i < 100; ++i) at.emplace_back(i, 0);
  std::vector<std::size_t> ids(at.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
  const KdTree2 tree(at, ids);
  int seen = 0;
  EXPECT_FALSE(tree.for_each_in_box({-1, -1}, {200, 1}, [&](std::size_t) { return ++seen < 5; }));
  EXPECT_EQ(seen, 5);
  const KdTree2 empty(at, {});
  EXPECT_TRUE(empty.for_each_in_box({-1, -1}, {200, 1}, [](std::size_t) { return false; }));
}

}  // namespace
}  // namespace hrad
