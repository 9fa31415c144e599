#include "core/base/box_tree.h"

#include <algorithm>
#include <stdexcept>

namespace hrad {

BoxTree::BoxTree(std::vector<Aabb> boxes) : boxes_(std::move(boxes)) {
  if (boxes_.size() >= std::size_t{1} << 32)
    throw std::length_error("BoxTree: more than 2^32 - 1 boxes");
  ids_.reserve(boxes_.size());
  for (std::size_t i = 0; i < boxes_.size(); ++i)
    if (!boxes_[i].empty()) ids_.push_back(static_cast<std::uint32_t>(i));
  if (!ids_.empty()) {
    nodes_.reserve(2 * (ids_.size() / kLeafBoxes + 1));
    build(0, ids_.size());
  }
}

std::uint32_t BoxTree::build(std::size_t begin, std::size_t end) {
  const auto self = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Aabb box, centres;
  for (std::size_t k = begin; k < end; ++k) {
    box.extend(boxes_[ids_[k]]);
    centres.extend(boxes_[ids_[k]].center());
  }
  nodes_[self].box = box;
  if (end - begin <= kLeafBoxes) {
    nodes_[self].begin = static_cast<std::uint32_t>(begin);
    nodes_[self].end = static_cast<std::uint32_t>(end);
    return self;
  }
  int axis = 0;
  centres.extent().maxCoeff(&axis);
  const std::size_t mid = begin + (end - begin) / 2;
  std::nth_element(ids_.begin() + static_cast<std::ptrdiff_t>(begin),
                   ids_.begin() + static_cast<std::ptrdiff_t>(mid),
                   ids_.begin() + static_cast<std::ptrdiff_t>(end),
                   [&](std::uint32_t a, std::uint32_t b) {
                     return boxes_[a].center()[axis] < boxes_[b].center()[axis];
                   });
  const std::uint32_t left = build(begin, mid);
  const std::uint32_t right = build(mid, end);
  nodes_[self].left = left;
  nodes_[self].right = right;
  return self;
}

}  // namespace hrad
