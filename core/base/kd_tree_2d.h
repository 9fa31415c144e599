// A static k-d tree over points in the plane, for region queries: the ear clipping of
// large polygons (core/scene/scene_builder.cpp) asks it which reflex corners may lie in
// an ear. A uniform grid of them answered for the ear's bounding box, in time
// proportional to the cells and corners the box covers: a comb's long slanted ears
// over its base cover most of its corners without holding any (a comb of 200,002
// corners took minutes). The tree visits only the nodes whose points' bounds meet the
// region.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hrad {

class KdTree2 {
 public:
  using Point = Eigen::Vector2d;

  /// Indexes the points `at[i]` for i in `ids` (`at` must outlive the tree).
  KdTree2(const std::vector<Point>& at, std::vector<std::size_t> ids)
      : at_(at), ids_(std::move(ids)) {
    if (!ids_.empty()) build(0, ids_.size());
  }

  /// Calls visit(i) for every indexed point i inside the closed box [lo, hi] (and perhaps
  /// a few others near it: the caller tests each) until visit returns false; returns
  /// whether every call returned true.
  template <class Visit>
  bool for_each_in_box(const Point& lo, const Point& hi, const Visit& visit) const {
    return for_each_where(
        [&](const Point& node_lo, const Point& node_hi) {
          return !((node_hi.array() < lo.array()).any() || (node_lo.array() > hi.array()).any());
        },
        visit);
  }

  /// The same for the points of the nodes whose bounds [lo, hi] may(lo, hi) accepts: it
  /// must accept every box that holds a point the caller wants (a region's test: does
  /// the box meet it?), and prunes the rest.
  template <class May, class Visit>
  bool for_each_where(const May& may, const Visit& visit) const {
    if (nodes_.empty()) return true;
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!may(node.lo, node.hi)) continue;
      if (node.left == kLeaf) {
        for (std::uint32_t k = node.begin; k < node.end; ++k)
          if (!visit(ids_[k])) return false;
        continue;
      }
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
    return true;
  }

 private:
  static constexpr std::uint32_t kLeaf = 0;  // the root is node 0, never a child
  static constexpr std::size_t kLeafPoints = 8;
  struct Node {
    Point lo, hi;                               // bounds of the node's points
    std::uint32_t left = kLeaf, right = kLeaf;  // children, or kLeaf
    std::uint32_t begin = 0, end = 0;           // leaves: ids_[begin .. end)
  };

  // Builds the node of ids_[begin, end) and those below it; returns its index. The
  // halves split at the median of the wider side, so the depth is about
  // log2(n / kLeafPoints) + 1 and a query's stack holds at most one node per level
  // (plus one) of the 64 it has.
  std::uint32_t build(std::size_t begin, std::size_t end) {
    const auto self = static_cast<std::uint32_t>(nodes_.size());
    nodes_.emplace_back();
    Point lo = at_[ids_[begin]], hi = lo;
    for (std::size_t k = begin + 1; k < end; ++k) {
      lo = lo.cwiseMin(at_[ids_[k]]);
      hi = hi.cwiseMax(at_[ids_[k]]);
    }
    nodes_[self].lo = lo;
    nodes_[self].hi = hi;
    if (end - begin <= kLeafPoints) {
      nodes_[self].begin = static_cast<std::uint32_t>(begin);
      nodes_[self].end = static_cast<std::uint32_t>(end);
      return self;
    }
    const int axis = (hi - lo).x() >= (hi - lo).y() ? 0 : 1;
    const std::size_t mid = begin + (end - begin) / 2;
    std::nth_element(ids_.begin() + static_cast<std::ptrdiff_t>(begin),
                     ids_.begin() + static_cast<std::ptrdiff_t>(mid),
                     ids_.begin() + static_cast<std::ptrdiff_t>(end),
                     [&](std::size_t a, std::size_t b) { return at_[a][axis] < at_[b][axis]; });
    const std::uint32_t left = build(begin, mid);
    const std::uint32_t right = build(mid, end);
    nodes_[self].left = left;
    nodes_[self].right = right;
    return self;
  }

  const std::vector<Point>& at_;
  std::vector<std::size_t> ids_;
  std::vector<Node> nodes_;
};

}  // namespace hrad
