// Tessellation of MGF primitives into oriented planar triangles and quads, as indexed
// meshes; see mgf_shapes.h for the piece counts, orientation and watertightness.
#include "core/scene/mgf/mgf_shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>

namespace hrad {

namespace {

// Collects a shape's points (one index per distinct position) and its polygons.
class MeshBuilder {
 public:
  std::uint32_t point(const Vec3& p) {
    // -0 and +0 are one position.
    const std::array<double, 3> key{p.x() + 0.0, p.y() + 0.0, p.z() + 0.0};
    const auto [it, added] = index_.emplace(key, static_cast<std::uint32_t>(mesh_.points.size()));
    if (added) mesh_.points.push_back(p);
    return it->second;
  }
  /// A polygon over point indices; corners that repeat their predecessor (a collapsed
  /// edge) are dropped, and what has fewer than 3 corners left is no polygon.
  void polygon(std::initializer_list<std::uint32_t> corners) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t i : corners)
      if (out.empty() || out.back() != i) out.push_back(i);
    if (out.size() > 1 && out.front() == out.back()) out.pop_back();
    if (out.size() >= 3) mesh_.polygons.push_back(std::move(out));
  }
  ShapeMesh finish(bool inward) {
    if (inward)
      for (auto& p : mesh_.polygons) std::reverse(p.begin(), p.end());
    return std::move(mesh_);
  }

 private:
  ShapeMesh mesh_;
  std::map<std::array<double, 3>, std::uint32_t> index_;
};

// The n unit directions cos(2 pi j / n) u + sin(2 pi j / n) w, each computed once; the
// direction of j = n is that of j = 0 (indices are taken mod n).
std::vector<Vec3> circle(const Vec3& u, const Vec3& w, int n) {
  std::vector<Vec3> d(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    const double a = 2.0 * std::numbers::pi * j / n;
    d[static_cast<std::size_t>(j)] = std::cos(a) * u + std::sin(a) * w;
  }
  return d;
}

// Indices of the points centre + radius * d over the circle's directions (one point
// when the radius is 0).
std::vector<std::uint32_t> ring_points(MeshBuilder& m, const Vec3& centre, double radius,
                                       const std::vector<Vec3>& dirs) {
  std::vector<std::uint32_t> out;
  out.reserve(dirs.size());
  for (const Vec3& d : dirs) out.push_back(m.point(radius == 0 ? centre : centre + radius * d));
  return out;
}

}  // namespace

void orthonormal_frame(const Vec3& n, Vec3& u, Vec3& w) {
  const Vec3 a = n.normalized();
  u = a.unitOrthogonal();
  w = a.cross(u);
}

ShapeMesh tessellate_sphere(const Vec3& c, double r, int segments) {
  const int n = segments, bands = std::max(2, segments / 2);
  const double R = std::abs(r);
  const std::vector<Vec3> dirs = circle(Vec3::UnitX(), Vec3::UnitY(), n);
  MeshBuilder m;
  // rows[i][j]: latitude i from the +z pole (0) to the -z pole (bands), longitude j.
  std::vector<std::vector<std::uint32_t>> rows(static_cast<std::size_t>(bands) + 1);
  rows.front().assign(dirs.size(), m.point(c + Vec3(0, 0, R)));
  for (int i = 1; i < bands; ++i) {
    const double phi = std::numbers::pi * i / bands;
    for (const Vec3& d : dirs)
      rows[static_cast<std::size_t>(i)].push_back(
          m.point(c + R * (std::sin(phi) * d + Vec3(0, 0, std::cos(phi)))));
  }
  rows.back().assign(dirs.size(), m.point(c - Vec3(0, 0, R)));
  const auto un = static_cast<std::size_t>(n);
  for (std::size_t i = 0; i + 1 < rows.size(); ++i)
    for (std::size_t j = 0; j < un; ++j)
      m.polygon({rows[i][j], rows[i + 1][j], rows[i + 1][(j + 1) % un], rows[i][(j + 1) % un]});
  return m.finish(r < 0);
}

ShapeMesh tessellate_cone(const Vec3& a, double ra, const Vec3& b, double rb, int segments) {
  Vec3 u, w;
  orthonormal_frame(b - a, u, w);
  const std::vector<Vec3> dirs = circle(u, w, segments);
  MeshBuilder m;
  const auto p = ring_points(m, a, std::abs(ra), dirs);
  const auto q = ring_points(m, b, std::abs(rb), dirs);
  const std::size_t n = dirs.size();
  for (std::size_t j = 0; j < n; ++j) m.polygon({p[j], p[(j + 1) % n], q[(j + 1) % n], q[j]});
  return m.finish(ra < 0 || rb < 0);
}

ShapeMesh tessellate_ring(const Vec3& c, const Vec3& normal, double rmin, double rmax,
                          int segments) {
  Vec3 u, w;
  orthonormal_frame(normal, u, w);
  const std::vector<Vec3> dirs = circle(u, w, segments);
  MeshBuilder m;
  const auto in = ring_points(m, c, rmin, dirs);
  const auto out = ring_points(m, c, rmax, dirs);
  const std::size_t n = dirs.size();
  for (std::size_t j = 0; j < n; ++j) m.polygon({in[j], out[j], out[(j + 1) % n], in[(j + 1) % n]});
  return m.finish(false);
}

ShapeMesh tessellate_torus(const Vec3& c, const Vec3& normal, double rmin, double rmax,
                           int segments) {
  Vec3 u, w;
  orthonormal_frame(normal, u, w);
  const Vec3 a = normal.normalized();
  const double big = 0.5 * (std::abs(rmax) + std::abs(rmin));
  const double tube = 0.5 * (std::abs(rmax) - std::abs(rmin));
  const std::vector<Vec3> around = circle(u, w, segments);
  // The tube's circle in its own (radial, axial) plane: (cos, sin) pairs, once.
  const std::vector<Vec3> section = circle(Vec3::UnitX(), Vec3::UnitY(), segments);
  MeshBuilder m;
  const auto n = static_cast<std::size_t>(segments);
  std::vector<std::uint32_t> grid(n * n);
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t k = 0; k < n; ++k)
      grid[j * n + k] =
          m.point(c + (big + tube * section[k].x()) * around[j] + tube * section[k].y() * a);
  auto at = [&](std::size_t j, std::size_t k) { return grid[(j % n) * n + k % n]; };
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t k = 0; k < n; ++k)
      m.polygon({at(j, k), at(j + 1, k), at(j + 1, k + 1), at(j, k + 1)});
  return m.finish(rmax < 0);
}

ShapeMesh tessellate_prism(std::span<const Vec3> base, double length) {
  const Vec3 off = -length * polygon_normal(base);
  const std::size_t k = base.size();
  ShapeMesh out;
  for (const Vec3& p : base) out.points.push_back(p);
  for (const Vec3& p : base) out.points.push_back(p + off);
  auto bottom = [](std::size_t i) { return static_cast<std::uint32_t>(i); };
  auto top = [k](std::size_t i) { return static_cast<std::uint32_t>(k + i); };
  std::vector<std::uint32_t> b, t;
  for (std::size_t i = 0; i < k; ++i) b.push_back(bottom(i));
  for (std::size_t i = k; i-- > 0;) t.push_back(top(i));
  out.polygons.push_back(std::move(b));
  out.polygons.push_back(std::move(t));
  for (std::size_t i = 0; i < k; ++i) {
    const std::size_t j = (i + 1) % k;
    out.polygons.push_back({bottom(j), bottom(i), top(i), top(j)});
  }
  return out;
}

}  // namespace hrad
