// Tessellation of MGF primitives into oriented planar triangles and quads; see
// mgf_shapes.h for the piece counts and orientation rules.
#include "core/mgf_shapes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hrad {

namespace {

void reverse_all(PolygonList& polys) {
  for (auto& p : polys) std::reverse(p.begin(), p.end());
}

// A quad with possibly coincident corners (a pole, a cone apex) as a triangle.
std::vector<Vec3> quad_or_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  std::vector<Vec3> q{a, b, c, d};
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < q.size(); ++i)
    if (out.empty() || q[i] != out.back()) out.push_back(q[i]);
  if (out.size() > 1 && out.front() == out.back()) out.pop_back();
  return out;
}

double angle(int j, int n) { return 2.0 * std::numbers::pi * j / n; }

}  // namespace

void orthonormal_frame(const Vec3& n, Vec3& u, Vec3& w) {
  const Vec3 a = n.normalized();
  u = a.unitOrthogonal();
  w = a.cross(u);
}

PolygonList tessellate_sphere(const Vec3& c, double r, int segments) {
  const int n = segments, bands = std::max(2, segments / 2);
  const double R = std::abs(r);
  auto point = [&](int i, int j) -> Vec3 {
    // i: latitude index from the +z pole (0) to the -z pole (bands); j: longitude.
    if (i == 0) return c + Vec3(0, 0, R);
    if (i == bands) return c - Vec3(0, 0, R);
    const double phi = std::numbers::pi * i / bands, th = angle(j % n, n);
    return c + R * Vec3(std::sin(phi) * std::cos(th), std::sin(phi) * std::sin(th), std::cos(phi));
  };
  PolygonList out;
  out.reserve(static_cast<std::size_t>(n) * bands);
  for (int i = 0; i < bands; ++i)
    for (int j = 0; j < n; ++j)
      out.push_back(quad_or_triangle(point(i, j), point(i + 1, j), point(i + 1, j + 1),
                                     point(i, j + 1)));
  if (r < 0) reverse_all(out);
  return out;
}

PolygonList tessellate_cone(const Vec3& a, double ra, const Vec3& b, double rb, int segments) {
  Vec3 u, w;
  orthonormal_frame(b - a, u, w);
  const double r0 = std::abs(ra), r1 = std::abs(rb);
  PolygonList out;
  out.reserve(static_cast<std::size_t>(segments));
  for (int j = 0; j < segments; ++j) {
    const Vec3 e0 = std::cos(angle(j, segments)) * u + std::sin(angle(j, segments)) * w;
    const Vec3 e1 = std::cos(angle(j + 1, segments)) * u + std::sin(angle(j + 1, segments)) * w;
    out.push_back(quad_or_triangle(a + r0 * e0, a + r0 * e1, b + r1 * e1, b + r1 * e0));
  }
  if (ra < 0 || rb < 0) reverse_all(out);
  return out;
}

PolygonList tessellate_ring(const Vec3& c, const Vec3& normal, double rmin, double rmax,
                            int segments) {
  Vec3 u, w;
  orthonormal_frame(normal, u, w);
  PolygonList out;
  out.reserve(static_cast<std::size_t>(segments));
  for (int j = 0; j < segments; ++j) {
    const Vec3 e0 = std::cos(angle(j, segments)) * u + std::sin(angle(j, segments)) * w;
    const Vec3 e1 = std::cos(angle(j + 1, segments)) * u + std::sin(angle(j + 1, segments)) * w;
    out.push_back(quad_or_triangle(c + rmin * e0, c + rmax * e0, c + rmax * e1, c + rmin * e1));
  }
  return out;
}

PolygonList tessellate_torus(const Vec3& c, const Vec3& normal, double rmin, double rmax,
                             int segments) {
  Vec3 u, w;
  orthonormal_frame(normal, u, w);
  const Vec3 a = normal.normalized();
  const double big = 0.5 * (std::abs(rmax) + std::abs(rmin));
  const double tube = 0.5 * (std::abs(rmax) - std::abs(rmin));
  const int n = segments;
  auto point = [&](int j, int k) -> Vec3 {
    const Vec3 e = std::cos(angle(j % n, n)) * u + std::sin(angle(j % n, n)) * w;
    const double ph = angle(k % n, n);
    return c + (big + tube * std::cos(ph)) * e + tube * std::sin(ph) * a;
  };
  PolygonList out;
  out.reserve(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k)
      out.push_back(
          quad_or_triangle(point(j, k), point(j + 1, k), point(j + 1, k + 1), point(j, k + 1)));
  if (rmax < 0) reverse_all(out);
  return out;
}

PolygonList tessellate_prism(std::span<const Vec3> base, double length) {
  const Vec3 off = -length * polygon_normal(base);
  const std::size_t k = base.size();
  PolygonList out;
  out.reserve(k + 2);
  out.emplace_back(base.begin(), base.end());
  std::vector<Vec3> top;
  for (std::size_t i = k; i-- > 0;) top.push_back(base[i] + off);
  out.push_back(std::move(top));
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3& p = base[i];
    const Vec3& q = base[(i + 1) % k];
    out.push_back({q, p, p + off, q + off});
  }
  return out;
}

}  // namespace hrad
