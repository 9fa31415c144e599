#include "core/transport/transport.h"

#include "core/base/hash.h"
#include "core/hierarchy/hierarchy.h"
#include "core/raycast/ray_scene.h"
#include "core/transport/form_factor.h"

#include <algorithm>
#include <array>
#include <numbers>
#include <stdexcept>
#include <tuple>
#include <vector>

namespace hrad {

namespace {

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

Transport::Transport(const Hierarchy& hierarchy, const RayScene& rays, int visibility_rays,
                     std::uint64_t seed, ClusterModel model)
    : hierarchy_(hierarchy),
      rays_(rays),
      visibility_rays_(visibility_rays),
      seed_(seed),
      model_(model),
      scale_(hierarchy.scene().bounds().diagonal()),
      plane_tol_(kPlaneTolerance * hierarchy.scene().bounds().diagonal()),
      shafts_(hierarchy) {}

PairClass Transport::classify(const Element& r, const Element& s) const {
  if (&r == &s) return r.is_cluster() ? PairClass::SourceInside : PairClass::Cull;
  if (contains(&s, &r)) return PairClass::ReceiverInside;
  if (contains(&r, &s)) return PairClass::SourceInside;
  // One end wholly behind (or on) the plane the other lies in and faces from: a
  // surface's, or that of a cluster whose polygons share one plane and face one way (a
  // polygon triangulated into slivers). Without the clusters' planes, such clusters near
  // each other (long slivers are near everything) were opened down to every pair of
  // their polygons (a comb of 25,000 sliver teeth: 589 M culled tasks).
  const auto behind = [&](const Element& a, const Element& b) {  // b behind a's plane
    const Vec3* n = a.is_cluster() ? hierarchy_.common_normal(a) : &a.normal;
    if (n == nullptr) return false;
    const double front =
        b.is_cluster() ? box_front(b.box, *n, a.center) : polygon_front(b.corners(), *n, a.center);
    return front <= plane_tol_;
  };
  if (behind(r, s) || behind(s, r)) return PairClass::Cull;
  if (r.is_cluster() || s.is_cluster()) {
    const double d = (s.center - r.center).norm();
    if (d < r.radius() + s.radius()) return PairClass::NearField;
  }
  return PairClass::Regular;
}

namespace {

/// The cluster model's form factor from centre to centre: cos_r * proj_s / (pi d^2),
/// where the receiver's mean cosine and the source's projected area are taken along
/// the centre-to-centre direction. (A disk-like "+ proj_s" in the denominator, which
/// bounds the value for near pairs, made cluster links 5-22 % low at the separations
/// where they are accepted; near pairs are now opened instead, see cluster_ff.)
double centre_ff(const Element& r, const Element& s, bool iso) {
  const Vec3 d = s.center - r.center;
  const double dist2 = d.squaredNorm();
  if (dist2 <= 0) return 0;
  const Vec3 dir = d / std::sqrt(dist2);
  const double proj_s = s.is_cluster() && iso ? 0.25 * s.area : s.projected_area(-dir);
  const double cos_r = !r.is_cluster() ? std::max(0.0, r.normal.dot(dir))
                       : iso           ? 0.25
                       : r.area > 0    ? r.projected_area(dir) / r.area
                                       : 0.0;
  return cos_r * proj_s / (std::numbers::pi * dist2);
}

}  // namespace

// A single centre-to-centre evaluation underestimates the transport between spread-out
// or near-perpendicular members (max(0, cos) and 1/d^2 are convex), by 5-22 % at the
// separations where cluster links are accepted (docs/energy-budget.md). So a pair
// closer than kClusterOpenDistance x (r_r + r_s) is opened, larger end first, and
// its parts are evaluated in turn, up to kClusterOpenBudget evaluations per link; a
// pair of two input polygons is evaluated with one exact point-to-polygon value. The
// result is a pure function of the two elements.
double Transport::cluster_ff(const Element& r, const Element& s, int& budget) const {
  const bool iso = model_ == ClusterModel::Isotropic;
  const double d = (s.center - r.center).norm();
  const bool open_r = r.is_cluster() && r.child_count > 0;
  const bool open_s = s.is_cluster() && s.child_count > 0;
  if (budget <= 0 || d >= kClusterOpenDistance * (r.radius() + s.radius()) ||
      (!open_r && !open_s)) {
    --budget;
    if (!r.is_cluster() && !s.is_cluster())
      return polygon_to_polygon_ff(r.corners(), s.corners(), 1);
    return centre_ff(r, s, iso);
  }
  // Open the larger end: F adds over the parts of the source, and is the
  // area-weighted mean over the parts of the receiver.
  const bool expand_r = open_r && (!open_s || r.radius() > s.radius());
  double f = 0;
  if (expand_r) {
    if (r.area <= 0) return 0;
    for (const Element& c : r.child_span()) f += c.area * cluster_ff(c, s, budget);
    return f / r.area;
  }
  for (const Element& c : s.child_span()) f += cluster_ff(r, c, budget);
  return f;
}

namespace {

/// A convex polygon clipped to the front of a plane: at most one vertex more than it
/// had, held in place for up to kInPlace vertices.
class FrontPart {
 public:
  static constexpr std::size_t kInPlace = 8;
  /// The part of `poly` where n . (p - p0) > 0 (Sutherland-Hodgman).
  FrontPart(std::span<const Vec3> poly, const Vec3& n, const Vec3& p0) {
    if (poly.size() + 1 > kInPlace) heap_.reserve(poly.size() + 1);
    Vec3 a = poly.back();
    double da = n.dot(a - p0);
    for (const Vec3& b : poly) {
      const double db = n.dot(b - p0);
      if ((da > 0) != (db > 0)) add(a + (da / (da - db)) * (b - a));
      if (db > 0) add(b);
      a = b;
      da = db;
    }
  }
  [[nodiscard]] std::span<const Vec3> vertices() const {
    return heap_.empty() ? std::span<const Vec3>(local_.data(), count_)
                         : std::span<const Vec3>(heap_);
  }

 private:
  void add(const Vec3& v) {
    if (heap_.capacity() > 0) {
      heap_.push_back(v);
    } else {
      local_[count_++] = v;
    }
  }
  std::array<Vec3, kInPlace> local_;
  std::size_t count_ = 0;
  std::vector<Vec3> heap_;
};

}  // namespace

// A receiver that crosses the source's plane receives nothing on the part behind it,
// and the product rule over its whole area puts its few points without regard to the
// crossing: the front part can hold none of them, and a pair of elements that cross
// each other's planes (a chair leg through a floor, tilted panels meeting at an
// angle) then gets F = 0 although light passes. Such a receiver is integrated over
// its front part only, with the same rule, and the result scaled by that part's share
// of the area.
double Transport::form_factor(const Element& r, const Element& s) const {
  if (!r.is_cluster() && !s.is_cluster()) {
    const std::span<const Vec3> rc = r.corners();
    // r has corners both in front of s's plane and behind it (as classify() measures).
    const bool crosses = polygon_front(rc, s.normal, s.center) > plane_tol_ &&
                         polygon_front(rc, -s.normal, s.center) > plane_tol_;
    if (!crosses || !(r.area > 0)) return polygon_to_polygon_ff(rc, s.corners(), kQuadratureOrder);
    const FrontPart part(rc, s.normal, s.center);
    const double share = polygon_area(part.vertices()) / r.area;
    if (!(share > 0)) return 0;
    return std::clamp(std::min(share, 1.0) *
                          polygon_to_polygon_ff(part.vertices(), s.corners(), kQuadratureOrder),
                      0.0, 1.0);
  }
  int budget = kClusterOpenBudget;
  return std::clamp(cluster_ff(r, s, budget), 0.0, 1.0);
}

double Transport::form_factor_from_point(const Vec3& p, const Vec3& n, const Element& s) const {
  if (!s.is_cluster()) return point_to_polygon_ff(p, n, s.corners());
  const Vec3 d = s.center - p;
  const double dist2 = d.squaredNorm();
  if (!(dist2 > 0)) return 0;
  const Vec3 dir = d / std::sqrt(dist2);
  const double proj_s = model_ == ClusterModel::Isotropic ? 0.25 * s.area : s.projected_area(-dir);
  return std::max(0.0, n.dot(dir)) * proj_s / (std::numbers::pi * dist2);
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

// Kernel-weighted, stratified visibility between the points `sample_a` draws (it
// takes three uniforms and returns the point, its unit normal and the polygon it lies
// on) and points of s.
//
// Each segment a-b is weighted by the form-factor kernel cos_a cos_b / |b - a|^2
// (member-polygon normals at cluster ends), so the estimate is the visibility the
// transport sees: near pairs carry most of the light and are blocked less often than
// far ones, and the plain fraction of open segments was biased low by 3-12 %
// (docs/energy-budget.md). The distance is floored at a tenth of `radius`, which
// bounds the weights of pairs near a shared edge. The k segments are stratified: each
// takes its own k-th of every coordinate range (a Latin hypercube whose strata are
// paired by per-pair random offsets), which lowers the variance and with it the bias
// of the ratio.
template <class SampleA>
double Transport::kernel_visibility(SampleA&& sample_a, const Vec3& toward_a, double radius,
                                    const Element& s, std::uint64_t key, int k_rays) const {
  const double floor_d = 0.1 * radius;
  const double floor_d2 = std::max(floor_d * floor_d, 1e-300);
  double w_open = 0, w_all = 0;
  int open = 0;
  std::uint64_t offsets[6];
  for (int dim = 0; dim < 6; ++dim)
    offsets[dim] = splitmix64_mix(key + 0x51ED27ull * static_cast<std::uint64_t>(dim + 1));
  for (int k = 0; k < k_rays; ++k) {
    const auto i = static_cast<std::uint64_t>(6 * k);
    const auto strat = [&](int dim) {
      const std::uint64_t p = dim % 2 ? static_cast<std::uint64_t>(k_rays - 1) : 1;
      const auto stratum =
          (static_cast<std::uint64_t>(k) * p + offsets[dim]) % static_cast<std::uint64_t>(k_rays);
      return (static_cast<double>(stratum) +
              hashed_uniform(key, i + static_cast<std::uint64_t>(dim))) /
             k_rays;
    };
    const auto [a, na, fa] = sample_a(strat(0), strat(1), strat(2));
    // The polygons the end points lie on cannot block the segment (it meets each
    // one's plane only at its end); in single precision a grazing segment would
    // still be reported blocked by them, so the query ignores both.
    std::uint32_t fb = RayScene::kNoPolygon;
    const Vec3 b = hierarchy_.sample_point(s, strat(3), strat(4), strat(5), &toward_a, &fb);
    const bool is_open = !rays_.occluded(a, b, fa, fb);
    open += is_open ? 1 : 0;
    const Vec3 d = b - a;
    const double d2 = d.squaredNorm();
    const Vec3& nb = fb == RayScene::kNoPolygon ? s.normal : hierarchy_.face_normal(fb);
    const double w = std::max(0.0, na.dot(d)) * std::max(0.0, -nb.dot(d)) /
                     (std::max(d2, floor_d2) * std::max(d2, 1e-300));
    w_all += w;
    if (is_open) w_open += w;
  }
  // No sampled pair faces each other (possible only at grazing or cluster ends):
  // the plain fraction.
  return w_all > 0 ? w_open / w_all : static_cast<double>(open) / k_rays;
}

double Transport::visibility(const Element& r, const Element& s, std::uint64_t& rays,
                             std::uint64_t& skipped, unsigned draw, int count) const {
  if (visibility_rays_ <= 0) return 1.0;
  const int k = count > 0 ? count : visibility_rays_;
  // The rays would all be unblocked: their fraction is exactly 1.
  if (!visibility_on_ || (shaft_culling_ && shafts_.clear(r, s))) {
    skipped += static_cast<std::uint64_t>(k);
    return 1.0;
  }
  std::uint64_t key = splitmix64_mix(splitmix64_mix(r.id ^ seed_) + s.id);
  if (draw != 0) key = splitmix64_mix(key + 0xD1B54A32D192ED03ull * draw);
  const auto sample_r = [&](double u1, double u2, double u3) {
    std::uint32_t fa = RayScene::kNoPolygon;
    const Vec3 a = hierarchy_.sample_point(r, u1, u2, u3, &s.center, &fa);
    const Vec3 na = fa == RayScene::kNoPolygon ? r.normal : hierarchy_.face_normal(fa);
    return std::tuple<Vec3, Vec3, std::uint32_t>(a, na, fa);
  };
  rays += static_cast<std::uint64_t>(k);
  return kernel_visibility(sample_r, r.center, std::min(r.radius(), s.radius()), s, key, k);
}

double Transport::visibility_from_point(const Vec3& p, const Vec3& n, const Element& s,
                                        std::uint64_t key, int k_rays) const {
  if (k_rays <= 0 || !visibility_on_) return 1.0;
  const auto sample_p = [&](double, double, double) {
    return std::tuple<Vec3, Vec3, std::uint32_t>(p, n, RayScene::kNoPolygon);
  };
  return kernel_visibility(sample_p, p, s.radius(), s, splitmix64_mix(key ^ seed_), k_rays);
}

}  // namespace hrad
