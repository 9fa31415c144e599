// A static tree over axis-aligned boxes, for "which boxes may meet this box" queries
// that stop as soon as the caller has seen enough. The face crossings of the open
// fractions (core/raycast/face_crossings.cpp) ask it for the polygons near a piece and
// give up after a few hundred. Embree's point query could not stop: after the last
// wanted candidate it still visited every box holding the query's centre, and in a fan
// of slivers that share a corner (a 100,000-corner disc) that is most of them, for
// every piece: quadratic in the slivers.
#pragma once

#include "core/base/geometry.h"

#include <cstdint>
#include <vector>

namespace hrad {

class BoxTree {
 public:
  BoxTree() = default;
  /// Indexes boxes[i] as i. Empty boxes are never reported.
  explicit BoxTree(std::vector<Aabb> boxes);

  /// Calls visit(i) for every indexed box i that meets `query` (closed: touching
  /// counts), each once, in no set order, until visit returns false; returns whether
  /// every call returned true. A query box rather than a sphere: the face crossings ask
  /// for the polygons near a piece, and a sphere round a long thin piece held many more
  /// (the cabin's crossing tests took 1.5 times as long with spheres).
  template <class Visit>
  bool for_each_overlapping(const Aabb& query, const Visit& visit) const {
    if (nodes_.empty() || query.empty()) return true;
    const auto meets = [&](const Aabb& b) {
      return (b.lo.array() <= query.hi.array()).all() && (b.hi.array() >= query.lo.array()).all();
    };
    if (!meets(nodes_[0].box)) return true;
    // Only nodes that meet the query are pushed.
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (node.left == kLeaf) {
        for (std::uint32_t k = node.begin; k < node.end; ++k)
          if (meets(boxes_[ids_[k]]) && !visit(ids_[k])) return false;
        continue;
      }
      if (meets(nodes_[node.left].box)) stack[top++] = node.left;
      if (meets(nodes_[node.right].box)) stack[top++] = node.right;
    }
    return true;
  }

  [[nodiscard]] std::size_t size() const { return ids_.size(); }
  /// Box i as given.
  [[nodiscard]] const Aabb& box(std::uint32_t i) const { return boxes_[i]; }

 private:
  static constexpr std::uint32_t kLeaf = 0;  // the root is node 0, never a child
  static constexpr std::size_t kLeafBoxes = 4;
  struct Node {
    Aabb box;                                   // union of the node's boxes
    std::uint32_t left = kLeaf, right = kLeaf;  // children, or kLeaf
    std::uint32_t begin = 0, end = 0;           // leaves: ids_[begin .. end)
  };

  // Builds the node of ids_[begin, end) and those below; returns its index. Halves
  // split at the median box centre along the axis its centres spread most, so the depth is
  // about log2(n / kLeafBoxes) + 1 and a query's stack holds at most one node a level
  // (plus one) of its 64.
  std::uint32_t build(std::size_t begin, std::size_t end);

  std::vector<Aabb> boxes_;
  std::vector<std::uint32_t> ids_;
  std::vector<Node> nodes_;
};

}  // namespace hrad
