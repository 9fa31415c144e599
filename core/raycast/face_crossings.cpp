#include "core/raycast/face_crossings.h"

#include "core/base/box_tree.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hrad {

namespace {

// A convex polygon in its plane: corners, unit normal, and each edge's unit inward normal.
struct Flat {
  std::vector<Vec3> corner;
  Vec3 n = Vec3::Zero();
  std::vector<Vec3> inward;  // inward[i]: of the edge corner[i] -> corner[i + 1]
};

// Whether the polygon is convex: every turn goes the way of its normal (collinear
// corners allowed). The open fractions' shortcut needs convex pieces: a polygon that
// a reflex corner folds into its own hull is tested as crossed instead.
bool convex(const Flat& f) {
  const std::size_t k = f.corner.size();
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3 a = f.corner[(i + 1) % k] - f.corner[i];
    const Vec3 b = f.corner[(i + 2) % k] - f.corner[(i + 1) % k];
    if (a.cross(b).dot(f.n) < -1e-9 * a.norm() * b.norm()) return false;
  }
  return true;
}

// Whether the segment p + t (q - p), t in [0, 1], has a point farther than `tol` inside
// every edge of `f` (Liang-Barsky clipping against the shrunk polygon).
bool segment_reaches_inside(const Flat& f, const Vec3& p, const Vec3& q, double tol) {
  double t0 = 0, t1 = 1;
  const Vec3 d = q - p;
  for (std::size_t i = 0; i < f.corner.size(); ++i) {
    const Vec3& m = f.inward[i];
    if (m.squaredNorm() == 0) continue;  // a repeated corner: no edge
    const double a = m.dot(p - f.corner[i]) - tol;
    const double b = m.dot(d);
    if (b == 0) {
      if (a < 0) return false;
    } else if (b > 0) {
      t0 = std::max(t0, -a / b);
    } else {
      t1 = std::min(t1, -a / b);
    }
    if (t0 > t1) return false;
  }
  return true;
}

// Whether polygon g (its corners) reaches into f's inside: see crossed_inside.
bool reaches_into(const Flat& f, std::span<const Vec3> g, double tol) {
  const Vec3& c0 = f.corner[0];
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec3& x : g) {
    const double s = f.n.dot(x - c0);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  if (lo > tol || hi < -tol) return false;  // wholly on one side
  if (lo >= -tol && hi <= tol) {
    // In f's plane. Facing f, it closes in what it covers: the state changes along its
    // edges (a piece wholly under it is wholly closed in: not crossed). Facing the same
    // way, it is the next piece of one surface.
    if (polygon_normal(g).dot(f.n) >= 0) return false;
    for (std::size_t k = 0; k < g.size(); ++k)
      if (segment_reaches_inside(f, g[k], g[(k + 1) % g.size()], tol)) return true;
    return false;
  }
  // g meets f's plane along a segment (g is convex): its ends are where g's edges cross
  // the plane, or g's corners within `tol` of it.
  std::vector<Vec3> at;
  for (std::size_t k = 0; k < g.size(); ++k) {
    const Vec3& a = g[k];
    const Vec3& b = g[(k + 1) % g.size()];
    const double sa = f.n.dot(a - c0), sb = f.n.dot(b - c0);
    if (std::abs(sa) <= tol) at.push_back(a);
    if ((sa < -tol && sb > tol) || (sa > tol && sb < -tol))
      at.push_back(a + sa / (sa - sb) * (b - a));
  }
  if (at.empty()) return false;
  // The segment's ends: the two points farthest apart (all lie on one line, up to tol).
  const auto farthest = [&](const Vec3& from) {
    return *std::max_element(at.begin(), at.end(), [&](const Vec3& x, const Vec3& y) {
      return (x - from).squaredNorm() < (y - from).squaredNorm();
    });
  };
  const Vec3 q = farthest(at.front());
  return segment_reaches_inside(f, farthest(q), q, tol);
}

}  // namespace

bool crossed_inside(const RayScene& rays, const Scene& scene, std::span<const Vec3> corners,
                    const Vec3& normal, std::uint32_t own, double tolerance) {
  thread_local Flat f;
  thread_local std::vector<Vec3> g;
  f.corner.assign(corners.begin(), corners.end());
  f.n = normal;
  const std::size_t k = f.corner.size();
  f.inward.resize(k);
  for (std::size_t e = 0; e < k; ++e) {
    const Vec3 edge = f.corner[(e + 1) % k] - f.corner[e];
    const double len = edge.norm();
    f.inward[e] = len > 0 ? Vec3(f.n.cross(edge) / len) : Vec3::Zero();
  }
  if (k < 3 || !convex(f)) return true;
  // A polygon that reaches in comes within `tolerance` of a point inside the piece.
  Aabb near;
  for (const Vec3& c : f.corner) near.extend(c);
  near.lo.array() -= 2 * tolerance;
  near.hi.array() += 2 * tolerance;
  const std::uint32_t twin = rays.twin(own);
  int tested = 0;
  bool crossed = false;
  const BoxTree& boxes = rays.polygon_boxes();
  boxes.for_each_overlapping(near, [&](std::uint32_t other) {
    if (other == own || other == twin) return true;
    if (++tested > kCrossingCandidates) {
      crossed = true;
      return false;
    }
    // A polygon whose box lies wholly on one side of the piece's plane cannot reach it.
    const Aabb& b = boxes.box(other);
    const double mid = f.n.dot(b.center() - f.corner[0]);
    const double half = f.n.cwiseAbs().dot(0.5 * (b.hi - b.lo));
    if (mid - half > tolerance || mid + half < -tolerance) return true;
    const Face& face = scene.faces[other];
    g.clear();
    for (std::uint32_t c = 0; c < face.count; ++c)
      g.push_back(scene.vertices[scene.indices[face.first + c]]);
    crossed = reaches_into(f, g, tolerance);
    return !crossed;
  });
  return crossed;
}

}  // namespace hrad
