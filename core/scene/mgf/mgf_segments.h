// How finely MGF's curved primitives are tessellated when `segments` is 0 (automatic):
// a circle of radius r (in world units, after its transform) gets
//   n = clamp(ceil(2 pi r / (kSegmentEdge * D)), kMinSegments, kMaxSegments)
// divisions, so that its facets' chords are at most kSegmentEdge of the scene's
// bounding-box diagonal D (faces and every primitive's exact extent) wherever the clamp
// allows. Shapes small against the scene keep kMinSegments, the count every shape had
// before the rule (an inscribed 16-gon has 2.6 % less area than its circle); large ones
// are capped at kMaxSegments (a torus makes n^2 facets). A sphere is n around and
// n / 2 bands; a cylinder or cone uses its larger radius, a ring its outer one and a
// torus its outer radius, for the tube too.
#pragma once

#include "core/base/geometry.h"

namespace hrad {

inline constexpr double kSegmentEdge = 0.02;
inline constexpr int kMinSegments = 16;
inline constexpr int kMaxSegments = 128;

/// The rule above; a non-positive or non-finite diagonal gives kMinSegments.
int automatic_segments(double radius, double diagonal);

/// The bounding box of a circle of `radius` about `centre` in the plane perpendicular to
/// `axis` (non-zero): exact, radius * sqrt(1 - a_i^2) along each unit axis a.
Aabb circle_bounds(const Vec3& centre, const Vec3& axis, double radius);

}  // namespace hrad
