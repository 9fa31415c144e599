// Whether an input polygon covers part of its area more than once: its boundary crosses
// itself (a bow-tie quad, a pentagram) or runs along one of its edges twice in the same
// direction (a face listed as "1 2 3 4 1 2 3 4" winds round twice). Such a polygon has no
// one area or orientation: its vector area counts the twice-covered part twice (a
// pentagram emitter gave 31 % more light than the area it covers, a doubly wound face of
// a closed box made the probes about 50x too bright) or cancels the oppositely wound
// lobes (a bow-tie passed as a zero-area sliver). SceneBuilder drops it with a warning
// naming its place (core/scene/scene_builder.h).
//
// Not an overlap: edges that only touch, and edges that run along each other in opposite
// directions (the seam by which MGF writes a polygon with a hole as one loop, whose
// hole's corners repeat).
#pragma once

#include "core/base/geometry.h"

#include <cstddef>
#include <span>
#include <string>

namespace hrad {

struct SelfOverlap {
  bool found = false;
  /// What was found, for the message: "edges 1 and 3 cross" (1-based, edge i runs from
  /// vertex i to vertex i + 1) or "edge 5 runs along edge 1 again".
  std::string what;
};

/// Tests the polygon in its own plane (the plane of its vector area, or of its
/// sharpest corner when the vector area vanishes). Near-linear for everyday polygons
/// (edges binned on a grid); two edges cross when each one's ends lie strictly on both
/// sides of the other (beyond 1e-10 of their lengths multiplied, and round-off).
SelfOverlap find_self_overlap(std::span<const Vec3> p);

}  // namespace hrad
