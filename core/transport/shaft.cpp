#include "core/transport/shaft.h"

#include "core/hierarchy/hierarchy.h"

#include <algorithm>
#include <array>
#include <limits>

namespace hrad {

namespace {

/// The points whose convex hull holds every sample point of an element: a surface's
/// corners (up to 8), else the 8 corners of its bounding box.
struct Hull {
  std::array<Vec3, 8> p;
  int n = 0;
};

Hull hull_of(const Element& e) {
  Hull h;
  const auto c = e.corners();
  if (!e.is_cluster() && c.size() <= h.p.size()) {
    for (const Vec3& v : c) h.p[static_cast<std::size_t>(h.n++)] = v;
    return h;
  }
  for (int i = 0; i < 8; ++i)
    h.p[static_cast<std::size_t>(h.n++)] =
        Vec3((i & 1) ? e.box.hi.x() : e.box.lo.x(), (i & 2) ? e.box.hi.y() : e.box.lo.y(),
             (i & 4) ? e.box.hi.z() : e.box.lo.z());
  return h;
}

/// Smallest and largest signed distance of the points from the plane (n, p0).
std::pair<double, double> range(const Hull& h, const Vec3& n, const Vec3& p0) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i = 0; i < h.n; ++i) {
    const double d = n.dot(h.p[static_cast<std::size_t>(i)] - p0);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return {lo, hi};
}

double box_front(const Aabb& b, const Vec3& n, const Vec3& p0) {
  // The corner farthest along n.
  const Vec3 c((n.x() > 0 ? b.hi : b.lo).x(), (n.y() > 0 ? b.hi : b.lo).y(),
               (n.z() > 0 ? b.hi : b.lo).z());
  return n.dot(c - p0);
}

double polygon_front(std::span<const Vec3> poly, const Vec3& n, const Vec3& p0) {
  double best = -std::numeric_limits<double>::infinity();
  for (const Vec3& v : poly) best = std::max(best, n.dot(v - p0));
  return best;
}

bool boxes_overlap(const Aabb& a, const Aabb& b, double tol) {
  return (a.lo.array() <= b.hi.array() + tol).all() && (b.lo.array() <= a.hi.array() + tol).all();
}

}  // namespace

ShaftCuller::ShaftCuller(const Hierarchy& hierarchy)
    : hierarchy_(hierarchy), tol_(1e-9 * hierarchy.scene().bounds().diagonal()) {}

bool ShaftCuller::clear(const Element& r, const Element& s) const {
  const Hull hr = hull_of(r), hs = hull_of(s);
  Aabb shaft = r.box;
  shaft.extend(s.box);
  // A surface's plane bounds the shaft when the other element lies wholly on or in
  // front of it: rays leave the surface forwards and never come back behind it.
  const bool r_plane = !r.is_cluster() && range(hs, r.normal, r.center).first >= -tol_;
  const bool s_plane = !s.is_cluster() && range(hr, s.normal, s.center).first >= -tol_;

  std::array<const Element*, 256> stack;
  std::size_t top = 0;
  stack[top++] = &hierarchy_.root();
  while (top > 0) {
    const Element& e = *stack[--top];
    if (!boxes_overlap(e.box, shaft, tol_)) continue;
    if (r_plane && box_front(e.box, r.normal, r.center) <= tol_) continue;
    if (s_plane && box_front(e.box, s.normal, s.center) <= tol_) continue;
    if (e.is_cluster()) {
      const auto kids = e.child_span();
      if (top + kids.size() > stack.size()) return false;  // too deep: cast the rays
      for (const Element& k : kids) stack[top++] = &k;
      continue;
    }
    // An input polygon (clusters' children are clusters or input polygons).
    const auto poly = e.corners();
    if (r_plane && polygon_front(poly, r.normal, r.center) <= tol_) continue;
    if (s_plane && polygon_front(poly, s.normal, s.center) <= tol_) continue;
    // Both elements on one side of P's plane, touching allowed. A face that is not
    // quite planar (faces are planar only to 1e-3 of their size) is a slab: then
    // both must lie clear of the slab.
    double flat = 0;
    for (const Vec3& v : poly) flat = std::max(flat, std::abs(e.normal.dot(v - e.center)));
    const auto [rlo, rhi] = range(hr, e.normal, e.center);
    const auto [slo, shi] = range(hs, e.normal, e.center);
    const double lo = std::min(rlo, slo), hi = std::max(rhi, shi);
    if (flat <= tol_) {
      const bool one_side = lo >= -tol_ || hi <= tol_;
      const bool in_plane = lo >= -tol_ && hi <= tol_;
      if (one_side && !in_plane) continue;
    } else if (lo > flat + tol_ || hi < -(flat + tol_)) {
      continue;
    }
    return false;
  }
  return true;
}

}  // namespace hrad
