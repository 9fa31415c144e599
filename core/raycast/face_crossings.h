// Face crossings: whether another polygon reaches into a piece of a polygon, as the
// sides of a box that stands on a floor meet the floor along the box's footprint, or a
// shelf pushed into a wall meets the wall. Only where such a crossing runs through a
// piece can some of its points be closed in (inside a solid) and others open: moving
// along a surface without meeting another never enters or leaves a solid, so all the
// points of an uncrossed piece share one state. The open fractions
// (core/transport/open_fraction.cpp) decide such a piece from a few points.
#pragma once

#include "core/base/geometry.h"

#include <cstdint>
#include <span>

namespace hrad {

class RayScene;
struct Scene;

/// Whether a polygon of `scene` other than `own` and its twin reaches into the convex
/// piece `corners` of polygon `own` (unit normal `normal`, corners in its order) shrunk
/// by `tolerance`: it meets the piece's plane, within `tolerance`, along a segment with
/// a point farther than `tolerance` inside every edge. A polygon in the plane facing the
/// same way (the next piece of one surface) does not count; one facing the other way (a
/// contact) does when one of its edges does (the piece wholly under it is wholly closed
/// in). Answers true without more tests
/// (which only costs the caller rays) for a non-convex piece and beyond
/// kCrossingCandidates candidates. `rays` must be built from `scene`'s faces
/// (RayScene::from_scene): it finds the candidates. Thread-safe.
bool crossed_inside(const RayScene& rays, const Scene& scene, std::span<const Vec3> corners,
                    const Vec3& normal, std::uint32_t own, double tolerance);

/// The most candidates tested for one piece before it counts as crossed.
inline constexpr int kCrossingCandidates = 256;

}  // namespace hrad
