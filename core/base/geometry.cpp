#include "core/base/geometry.h"

#include <algorithm>

namespace hrad {

double relative_nonplanarity(std::span<const Vec3> p) {
  if (p.size() <= 3) return 0.0;
  const Vec3 a = vector_area(p);
  const double area = a.norm();
  if (area <= 0) return std::numeric_limits<double>::infinity();
  const Vec3 n = a / area;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& v : p) mean += v;
  mean /= static_cast<double>(p.size());
  double worst = 0;
  for (const Vec3& v : p) worst = std::max(worst, std::abs(n.dot(v - mean)));
  return worst / std::sqrt(area);
}

bool is_convex(std::span<const Vec3> p) {
  const std::size_t k = p.size();
  if (k < 3) return false;
  if (k == 3) return polygon_area(p) > 0;
  const Vec3 n = polygon_normal(p);
  if (n.isZero()) return false;
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3 e0 = p[(i + 1) % k] - p[i];
    const Vec3 e1 = p[(i + 2) % k] - p[(i + 1) % k];
    // Every turn must go the same way as the polygon's orientation (strictly:
    // collinear vertices make a degenerate "corner" that the quadtree cannot use).
    if (e0.cross(e1).dot(n) <= 1e-12 * e0.norm() * e1.norm()) return false;
  }
  return true;
}

}  // namespace hrad
