#include "core/transport.h"

#include "core/form_factor.h"
#include "core/hierarchy.h"
#include "core/ray_scene.h"

#include <algorithm>
#include <numbers>
#include <stdexcept>

namespace hrad {

namespace {

std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// Largest signed distance of the box's corners from the plane (n, p0).
double box_front(const Aabb& b, const Vec3& n, const Vec3& p0) {
  double best = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < 8; ++i) {
    const Vec3 c((i & 1) ? b.hi.x() : b.lo.x(), (i & 2) ? b.hi.y() : b.lo.y(),
                 (i & 4) ? b.hi.z() : b.lo.z());
    best = std::max(best, n.dot(c - p0));
  }
  return best;
}

double polygon_front(std::span<const Vec3> poly, const Vec3& n, const Vec3& p0) {
  double best = -std::numeric_limits<double>::infinity();
  for (const Vec3& v : poly) best = std::max(best, n.dot(v - p0));
  return best;
}

}  // namespace

double hashed_uniform(std::uint64_t key, std::uint64_t i) {
  return static_cast<double>(mix64(key + 0x9E3779B97F4A7C15ull * (i + 1)) >> 11) * 0x1.0p-53;
}

ClusterModel parse_cluster_model(const std::string& name) {
  if (name == "isotropic") return ClusterModel::Isotropic;
  if (name == "directional") return ClusterModel::Directional;
  throw std::invalid_argument("cluster_model must be isotropic or directional, not '" + name + "'");
}

Transport::Transport(const Hierarchy& hierarchy, const RayScene& rays, int visibility_rays,
                     std::uint64_t seed, ClusterModel model)
    : hierarchy_(hierarchy),
      rays_(rays),
      visibility_rays_(visibility_rays),
      seed_(seed),
      model_(model),
      scale_(hierarchy.scene().bounds().diagonal()),
      plane_tol_(1e-9 * hierarchy.scene().bounds().diagonal()),
      shafts_(hierarchy) {}

PairClass Transport::classify(const Element& r, const Element& s) const {
  if (&r == &s) return r.is_cluster() ? PairClass::SourceInside : PairClass::Cull;
  if (contains(&s, &r)) return PairClass::ReceiverInside;
  if (contains(&r, &s)) return PairClass::SourceInside;
  if (!r.is_cluster()) {
    const double front =
        s.is_cluster() ? box_front(s.box, r.normal, r.center) : polygon_front(s.corners(), r.normal, r.center);
    if (front <= plane_tol_) return PairClass::Cull;  // s wholly behind (or on) r's plane
  }
  if (!s.is_cluster()) {
    const double front =
        r.is_cluster() ? box_front(r.box, s.normal, s.center) : polygon_front(r.corners(), s.normal, s.center);
    if (front <= plane_tol_) return PairClass::Cull;
  }
  if (r.is_cluster() || s.is_cluster()) {
    const double d = (s.center - r.center).norm();
    if (d < r.radius() + s.radius()) return PairClass::NearField;
  }
  return PairClass::Regular;
}

double Transport::form_factor(const Element& r, const Element& s) const {
  if (!r.is_cluster() && !s.is_cluster())
    return polygon_to_polygon_ff(r.corners(), s.corners(), kQuadratureOrder);
  const Vec3 d = s.center - r.center;
  const double dist2 = d.squaredNorm();
  if (dist2 <= 0) return 0;
  const Vec3 dir = d / std::sqrt(dist2);
  const bool iso = model_ == ClusterModel::Isotropic;
  const double proj_s = s.is_cluster() && iso ? 0.25 * s.area : s.projected_area(-dir);
  const double cos_r = !r.is_cluster() ? std::max(0.0, r.normal.dot(dir))
                       : iso          ? 0.25
                       : r.area > 0   ? r.projected_area(dir) / r.area
                                      : 0.0;
  return std::clamp(cos_r * proj_s / (std::numbers::pi * dist2 + proj_s), 0.0, 1.0);
}

double Transport::form_factor_spread(const Element& r, const Element& s) const {
  if (r.is_cluster() || s.is_cluster()) return 0;
  // Points slightly inside the corners (the corners themselves may touch s).
  double lo = point_to_polygon_ff(r.center, r.normal, s.corners()), hi = lo;
  for (const Vec3& c : r.corners()) {
    const double f = point_to_polygon_ff(r.center + 0.9 * (c - r.center), r.normal, s.corners());
    lo = std::min(lo, f);
    hi = std::max(hi, f);
  }
  return hi - lo;
}

double Transport::visibility(const Element& r, const Element& s, std::uint64_t& rays,
                             std::uint64_t& skipped) const {
  if (visibility_rays_ <= 0) return 1.0;
  // The rays would all be unblocked: their fraction is exactly 1.
  if (!visibility_on_ || (shaft_culling_ && shafts_.clear(r, s))) {
    skipped += static_cast<std::uint64_t>(visibility_rays_);
    return 1.0;
  }
  const std::uint64_t key = mix64(mix64(r.id ^ seed_) + s.id);
  int open = 0;
  for (int k = 0; k < visibility_rays_; ++k) {
    const auto i = static_cast<std::uint64_t>(6 * k);
    // The polygons the end points lie on cannot block the segment (it meets each
    // one's plane only at its end); in single precision a grazing segment would
    // still be reported blocked by them, so the query ignores both.
    std::uint32_t fa = RayScene::kNoPolygon, fb = RayScene::kNoPolygon;
    const Vec3 a = hierarchy_.sample_point(r, hashed_uniform(key, i), hashed_uniform(key, i + 1),
                                           hashed_uniform(key, i + 2), &s.center, &fa);
    const Vec3 b = hierarchy_.sample_point(s, hashed_uniform(key, i + 3), hashed_uniform(key, i + 4),
                                           hashed_uniform(key, i + 5), &r.center, &fb);
    if (!rays_.occluded(a, b, fa, fb)) ++open;
  }
  rays += static_cast<std::uint64_t>(visibility_rays_);
  return static_cast<double>(open) / visibility_rays_;
}

}  // namespace hrad
