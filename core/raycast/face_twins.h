// Twins: two polygons with the same vertex positions in reverse cyclic order, the two
// sides of one sheet (a two-sided material's back face, core/scene/back_faces.h, or a sheet
// modelled twice). RayScene (core/raycast/ray_scene.h) treats a pair as one two-sided sheet: a
// ray reports the one whose front it meets, and ignoring one ignores both.
#pragma once

#include "core/base/geometry.h"

#include <cstdint>
#include <span>
#include <vector>

namespace hrad {

struct Scene;
struct PolygonRange;

/// "No twin".
inline constexpr std::uint32_t kNoTwin = ~std::uint32_t{0};

/// For each polygon the index of its twin, or kNoTwin. Symmetric: twin[twin[i]] == i.
/// A polygon with several reversed copies is paired with the first unpaired one.
std::vector<std::uint32_t> find_twins(std::span<const Vec3> vertices,
                                      std::span<const std::uint32_t> indices,
                                      std::span<const PolygonRange> polygons);

/// find_twins over the scene's faces.
std::vector<std::uint32_t> find_twins(const Scene& scene);

}  // namespace hrad
