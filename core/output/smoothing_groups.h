// Which of the leaves that meet at one point are shaded together (core/output/
// smooth_shading.h): those of one material whose normals lie within a given angle of
// each other, closed transitively. Comparing every pair is quadratic in the leaves at
// the point, and a point may hold very many: a fan of 100,000 slivers that share a
// corner took 14 s to shade. Above kPairwiseLeaves, leaves whose normals fall in one
// cell of a grid over the unit sphere are joined at once (the cell's diagonal is under
// the angle's chord), and only leaves of different cells are compared, a pair of cells
// already joined not at all.
#pragma once

#include "core/base/geometry.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace hrad {

/// Up to this many leaves at a point, every pair is compared.
inline constexpr std::size_t kPairwiseLeaves = 64;

/// Sets group[i], for each leaf i, to one leaf of its group (the same one for all the
/// group's members). Leaves i and j are in one group when a chain of leaves joins them in
/// which each step has the same material and normals whose dot product is at least
/// `min_cos` (in (0, 1]). Normals should be unit vectors; one that is not is compared with
/// each of the others.
void smoothing_groups(std::span<const std::uint32_t> material, std::span<const Vec3> normal,
                      double min_cos, std::vector<std::size_t>& group);

}  // namespace hrad
