// Polygons compared by their vertex positions, up to where the cycle starts: the key
// SceneBuilder uses to drop a repeated polygon, and the test for a polygon's twin (the
// same positions in the reverse cyclic order: the other side of a sheet, see
// core/raycast/face_twins.h). A cycle is read from its lexicographically smallest (x, y, z)
// vertex, forwards or backwards; -0 and +0 are the same position.
#pragma once

#include "core/base/geometry.h"

#include <cstddef>
#include <span>
#include <vector>

namespace hrad {

/// Index of the lexicographically smallest vertex (the first of equal ones).
std::size_t cycle_start(std::span<const Vec3> p);

/// The flattened coordinates of the cycle read from cycle_start, forwards or
/// (`reversed`) backwards.
std::vector<double> cycle_key(std::span<const Vec3> p, bool reversed = false);

/// Hash of cycle_key(p, reversed) without building it.
std::size_t cycle_hash(std::span<const Vec3> p, bool reversed = false);

/// Whether b, read forwards, is a read `reversed` (backwards) or forwards: the same
/// polygon (reversed false) or its twin (reversed true).
bool same_cycle(std::span<const Vec3> a, std::span<const Vec3> b, bool reversed);

/// Hash of a flattened coordinate list (the key of SceneBuilder's duplicate test).
struct PositionsHash {
  std::size_t operator()(const std::vector<double>& v) const noexcept;
};

}  // namespace hrad
