// Faces that lie in one plane, face the same way and overlap: the same surface given
// twice (a floor given again as two triangles), which the solver treats as two surfaces
// that each reflect and emit (probes came out 35-48 % too bright, without a word; the
// path tracer, which meets only one of them, was right). Exact repeats are dropped by
// SceneBuilder; these are reported by it (core/scene/scene_builder.h).
#pragma once

#include "core/base/geometry.h"
#include "core/scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <span>

namespace hrad {

struct CoplanarOverlaps {
  std::size_t pairs = 0;      ///< pairs of faces that share area
  double area = 0;            ///< the area they share, summed over the pairs
  Vec3 first = Vec3::Zero();  ///< the centroid of the first pair's first face
};

/// Pairs of faces in one plane (normals within 1e-6, offsets within 1e-7 of the scene's
/// diagonal), facing the same way, sharing more than 1e-6 of the smaller one's area.
/// Faces are convex (SceneBuilder's invariant). `source`, when not empty, gives each
/// face's input polygon: the triangles of one triangulated polygon are not compared.
/// Sorted sweeps per plane, each stopped after kMaxOverlapChecks candidate pairs (a
/// polygon of 20,000 corners triangulated into long thin triangles made the sweep
/// quadratic: 3.4 s), so the test is bounded and may miss overlaps in such a plane.
inline constexpr std::size_t kMaxOverlapChecks = 20'000'000;
CoplanarOverlaps find_coplanar_overlaps(const Scene& scene,
                                        std::span<const std::uint32_t> source = {});

}  // namespace hrad
