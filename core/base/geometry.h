// Small geometric vocabulary shared by every part of hrad.
//
// Units: whatever the scene uses. Nothing in hrad assumes metres or an up axis;
// tolerances are always relative to the scene's bounding-box diagonal.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

namespace hrad {

using Vec3 = Eigen::Vector3d;
/// Linear RGB triple: reflectance (unitless, in [0,1]) or radiometric quantities
/// (radiosity / exitance / irradiance, in W per unit area of the scene's units).
using Rgb = Eigen::Array3d;

/// Axis-aligned bounding box. An empty box has lo > hi.
struct Aabb {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());

  void extend(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void extend(const Aabb& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  [[nodiscard]] bool empty() const { return (lo.array() > hi.array()).any(); }
  [[nodiscard]] Vec3 center() const { return 0.5 * (lo + hi); }
  [[nodiscard]] Vec3 extent() const { return empty() ? Vec3::Zero() : Vec3(hi - lo); }
  [[nodiscard]] double diagonal() const { return extent().norm(); }
};

/// Vector area of a polygon (Newell's method): its direction is the normal, its
/// length the area. Exact for planar polygons; for slightly non-planar ones it is
/// the area of the projection on the best-fit plane.
inline Vec3 vector_area(std::span<const Vec3> p) {
  Vec3 n = Vec3::Zero();
  const std::size_t k = p.size();
  for (std::size_t i = 0; i < k; ++i) n += p[i].cross(p[(i + 1) % k]);
  return 0.5 * n;
}

inline double polygon_area(std::span<const Vec3> p) { return vector_area(p).norm(); }

/// Twice the signed area of the 2D triangle (a, b, c): positive when it turns
/// counter-clockwise.
inline double orient2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                       const Eigen::Vector2d& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

/// The cell of coordinate x on a grid of `cells` cells of `width` from `lo` (clamped;
/// cell 0 when the grid has no width): for binning points and boxes.
inline std::size_t grid_cell(double x, double lo, double width, std::size_t cells) {
  if (!(width > 0)) return 0;
  return std::min(cells - 1, static_cast<std::size_t>(std::max(0.0, (x - lo) / width)));
}

/// Cells along x and y of a grid of about `cells` cells over a w x h box, shaped like
/// the box so that its cells are near square. (A square grid over a comb 100,000 times
/// wider than tall put each tooth's side into hundreds of rows: 1.2 GB of bins.)
inline std::array<std::size_t, 2> grid_shape(double w, double h, std::size_t cells) {
  const double n = static_cast<double>(std::max<std::size_t>(cells, 1));
  const auto fit = [n](double c) {
    return static_cast<std::size_t>(std::clamp(std::ceil(c), 1.0, n));
  };
  if (!(w > 0) && !(h > 0)) return {1, 1};
  if (!(h > 0)) return {fit(n), 1};
  if (!(w > 0)) return {1, fit(n)};
  const std::size_t gx = fit(std::sqrt(n * w / h));
  return {gx, fit(n / static_cast<double>(gx))};
}

/// Unit normal, or zero for a degenerate polygon.
inline Vec3 polygon_normal(std::span<const Vec3> p) {
  const Vec3 a = vector_area(p);
  const double n = a.norm();
  return n > 0 ? Vec3(a / n) : Vec3::Zero();
}

/// A cosine-distributed direction about the unit normal n, in the orthonormal frame
/// (u, v, n), from two numbers in [0, 1): sin^2 of the angle from n is r1, the
/// azimuth 2 pi r2.
inline Vec3 cosine_direction(const Vec3& n, const Vec3& u, const Vec3& v, double r1, double r2) {
  const double r = std::sqrt(r1), phi = 2 * 3.14159265358979323846 * r2;
  return r * std::cos(phi) * u + r * std::sin(phi) * v + std::sqrt(1 - r1) * n;
}

inline Vec3 polygon_centroid(std::span<const Vec3> p) {
  // Area-weighted centroid via a fan from the first vertex (exact for planar convex).
  if (p.size() == 3) return (p[0] + p[1] + p[2]) / 3.0;
  Vec3 c = Vec3::Zero();
  double total = 0;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const double a = (p[i] - p[0]).cross(p[i + 1] - p[0]).norm();
    c += a * (p[0] + p[i] + p[i + 1]) / 3.0;
    total += a;
  }
  if (total <= 0) {
    for (const Vec3& v : p) c += v;
    return c / static_cast<double>(p.size());
  }
  return c / total;
}

/// Largest distance of a vertex from the polygon's mean plane, relative to the
/// polygon's size (sqrt of area). 0 for triangles.
double relative_nonplanarity(std::span<const Vec3> p);

/// True when the (near-planar) polygon is strictly convex in its own plane.
bool is_convex(std::span<const Vec3> p);

}  // namespace hrad
