#include "core/scene/coplanar_overlap.h"

#include "core/base/interrupt.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <vector>

namespace hrad {

namespace {

using Point = Eigen::Vector2d;

double area(const std::vector<Point>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Point& x = p[i];
    const Point& y = p[(i + 1) % p.size()];
    a += x.x() * y.y() - x.y() * y.x();
  }
  return 0.5 * a;
}

// The part of convex polygon `a` inside convex polygon `b`, both counter-clockwise
// (Sutherland-Hodgman).
std::vector<Point> clip(std::vector<Point> a, const std::vector<Point>& b) {
  for (std::size_t e = 0; e < b.size() && !a.empty(); ++e) {
    const Point& p = b[e];
    const Point& q = b[(e + 1) % b.size()];
    std::vector<Point> out;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const Point& s = a[i];
      const Point& t = a[(i + 1) % a.size()];
      const double ds = orient2d(p, q, s), dt = orient2d(p, q, t);
      if (ds >= 0) out.push_back(s);
      if ((ds >= 0) != (dt >= 0)) out.push_back(s + (ds / (ds - dt)) * (t - s));
    }
    a = std::move(out);
  }
  return a;
}

struct Flat {
  std::size_t face;
  std::vector<Point> p;  // counter-clockwise in the plane's frame
  Point lo, hi;
  double area;
};

}  // namespace

CoplanarOverlaps find_coplanar_overlaps(const Scene& scene, std::span<const std::uint32_t> source) {
  CoplanarOverlaps r;
  const double diag = scene.bounds().diagonal();
  if (!(diag > 0)) return r;
  // Faces by plane: the normal to 1e-6 and the offset to 1e-7 of the diagonal.
  std::map<std::tuple<long long, long long, long long, long long>, std::vector<std::size_t>> planes;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Vec3 n = scene.face_normal(f);
    const double d = n.dot(scene.vertices[scene.indices[scene.faces[f].first]]);
    const auto q = [](double x, double step) {  // clamped: llround of 1e30 has no value
      return std::llround(std::clamp(x / step, -9e18, 9e18));
    };
    planes[{q(n.x(), 1e-6), q(n.y(), 1e-6), q(n.z(), 1e-6), q(d, 1e-7 * diag)}].push_back(f);
  }
  for (const auto& [key, group] : planes) {
    if (group.size() < 2) continue;
    const Vec3 n = scene.face_normal(group.front());
    const Vec3 u = n.unitOrthogonal();
    const Vec3 v = n.cross(u);  // (u, v, n) right-handed: faces are counter-clockwise
    std::vector<Flat> flats;
    flats.reserve(group.size());
    for (const std::size_t f : group) {
      Flat fl{f, {}, Point::Constant(INFINITY), Point::Constant(-INFINITY), 0};
      for (const Vec3& x : scene.face_vertices(f)) {
        fl.p.emplace_back(x.dot(u), x.dot(v));
        fl.lo = fl.lo.cwiseMin(fl.p.back());
        fl.hi = fl.hi.cwiseMax(fl.p.back());
      }
      fl.area = area(fl.p);
      if (fl.area > 0) flats.push_back(std::move(fl));
    }
    std::sort(flats.begin(), flats.end(), [](const Flat& a, const Flat& b) {
      return a.lo.x() != b.lo.x() ? a.lo.x() < b.lo.x() : a.face < b.face;
    });
    std::size_t checks = 0;
    for (std::size_t i = 0; i < flats.size() && checks < kMaxOverlapChecks; ++i) {
      poll_interrupt(i);
      for (std::size_t j = i + 1; j < flats.size() && flats[j].lo.x() < flats[i].hi.x(); ++j) {
        if (++checks >= kMaxOverlapChecks) break;
        poll_interrupt(checks);
        const Flat &a = flats[i], &b = flats[j];
        if (b.lo.y() >= a.hi.y() || a.lo.y() >= b.hi.y()) continue;
        if (!source.empty() && source[a.face] == source[b.face]) continue;
        const double shared = area(clip(a.p, b.p));
        if (!(shared > 1e-6 * std::min(a.area, b.area))) continue;
        if (r.pairs++ == 0)
          r.first = polygon_centroid(scene.face_vertices(std::min(a.face, b.face)));
        r.area += shared;
      }
    }
  }
  return r;
}

}  // namespace hrad
