#include "core/scene/mgf/mgf_segments.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hrad {

int automatic_segments(double radius, double diagonal) {
  if (!(diagonal > 0) || !std::isfinite(diagonal) || !std::isfinite(radius)) return kMinSegments;
  const double n = std::ceil(2 * std::numbers::pi * std::abs(radius) / (kSegmentEdge * diagonal));
  return static_cast<int>(std::clamp(n, double{kMinSegments}, double{kMaxSegments}));
}

Aabb circle_bounds(const Vec3& centre, const Vec3& axis, double radius) {
  const Vec3 a = axis.normalized();
  Vec3 half;
  for (int i = 0; i < 3; ++i)
    half[i] = std::abs(radius) * std::sqrt(std::max(0.0, 1 - a[i] * a[i]));
  Aabb b;
  b.extend(centre - half);
  b.extend(centre + half);
  return b;
}

}  // namespace hrad
