#include "core/solver/row_sums.h"

#include "core/base/hash.h"
#include "core/base/interrupt.h"
#include "core/hierarchy/hierarchy.h"
#include "core/raycast/ray_scene.h"
#include "core/solver/propagation.h"
#include "core/transport/open_fraction.h"
#include "core/transport/transport.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hrad {

namespace {

// How far above max(1, plain row sum) the open-area gain may lift a leaf. A cap at
// exactly 1 also cut the leaves whose row sum the estimates' noise put a little above
// 1, a one-sided clamp: with push weights (core/solver/push_weights.h) the cluttered furnace
// at rho 0.9 was 2.5 % low with a cap of 1, 0.7 % low with 1.1, 0.15 % low with 1.2
// and 0.1 % high with 1.3 (signed mean at 32 probes); the office moved from -1.2 % to
// +0.4 %. Without push weights the spread of the row sums made any looser cap
// overshoot (+3.8 % with no cap).
constexpr double kOpenGainCap = 1.2;

// A normalized leaf's gain (its target over its row sum) is at most this. A leaf whose
// links carry less than half of what its rays find covered is missing links (a pair
// dropped as it straddled a plane), not mis-estimating them, and its few links are no
// sample of what it should gather. With normalize and independent decision rays at the
// default eps, about 1 % of the office's open leaf area and 0.3 % of the lab's have a
// gain above 1.5.
constexpr double kNormalizeGainCap = 2;

// Rays from one point of the uncovered-share estimate: the point is closed in (the
// inside of a solid, see core/transport/open_fraction.h) when more than half of them
// first meet a back face, and then it does not count.
constexpr int kRaysPerPoint = 4;

// Share of cosine-distributed directions from the open points of `e` that meet no lit
// surface: they escape, meet a back face (black, as in `hrad reference`), or meet a
// front face where the back of another face coincides with it (the inside of a solid).
// max(1, n / kRaysPerPoint) points, kRaysPerPoint rays each. Without an open point
// (a leaf closed in nearly everywhere) the share of its rays that escape.
struct Uncovered {
  double share = 0;
  double se = 0;  ///< standard error of `share`, from the spread over its points
};
Uncovered estimate_uncovered(const Element& e, const Hierarchy& h, const RayScene& rays, int n,
                             std::uint64_t seed) {
  const Vec3 u = e.normal.unitOrthogonal();
  const Vec3 v = e.normal.cross(u);
  const std::uint64_t key = child_id(e.id, 0xE5CA7Eu) ^ seed;
  // Origins step off the surface by twice the ray end-point exclusion and keep 1%
  // of the element's size away from its edges: a ray must not slip through the
  // seam of two walls because its first hit fell within the exclusion distance.
  const double lift = 2 * RayScene::kEndpointEpsilon * rays.scale();
  const int points = std::max(1, n / kRaysPerPoint);
  int counted = 0, uncovered = 0, all = 0, escaped = 0;
  double square_sum = 0;  // of the counted points' shares
  for (int k = 0; k < points; ++k) {
    const auto i = static_cast<std::uint64_t>(3 * k);
    const Vec3 s = h.sample_point(e, hashed_uniform(key, i), hashed_uniform(key, i + 1),
                                  hashed_uniform(key, i + 2));
    const Vec3 p = e.center + 0.99 * (s - e.center) + lift * e.normal;
    int back = 0, lost = 0;
    for (int j = 0; j < kRaysPerPoint; ++j) {
      const auto d = static_cast<std::uint64_t>(3 * points + 2 * (k * kRaysPerPoint + j));
      const Vec3 dir =
          cosine_direction(e.normal, u, v, hashed_uniform(key, d), hashed_uniform(key, d + 1));
      // The ray leaves e's own polygon, which it cannot hit again (a grazing ray could
      // be reported hitting it in single precision).
      const auto hit = rays.intersect(p, dir, std::numeric_limits<double>::infinity(), e.face);
      if (!hit) {
        ++lost;
        ++escaped;
      } else if (dir.dot(rays.normal(hit->prim)) >= 0 ||
                 rays.back_coincides(p, dir, hit->t, hit->prim)) {
        ++lost;
        ++back;
      }
    }
    all += kRaysPerPoint;
    if (2 * back > kRaysPerPoint) continue;  // closed in
    counted += kRaysPerPoint;
    uncovered += lost;
    const double f = static_cast<double>(lost) / kRaysPerPoint;
    square_sum += f * f;
  }
  if (counted == 0) {
    const double share = static_cast<double>(escaped) / all;
    return {share, std::sqrt(share * (1 - share) / all)};
  }
  const double share = static_cast<double>(uncovered) / counted;
  const int m = counted / kRaysPerPoint;
  // Rays from one point are not independent (the point may sit in a corner): the
  // spread is taken over points. One point: the rays' binomial spread.
  const double var = m > 1 ? std::max(0.0, square_sum / m - share * share) / (m - 1)
                           : share * (1 - share) / counted;
  return {share, std::sqrt(var)};
}

// row_sums = normalize on one open leaf: its gathered light scaled to the share of its
// hemisphere that rays find lit (estimated once, kept in the element). Returns the rays
// cast.
std::uint64_t normalize_leaf(Element& e, const Hierarchy& hierarchy, const RayScene& rays,
                             int rays_per_leaf, std::uint64_t seed) {
  // A closed-in leaf gathers nothing (core/solver/propagation.cpp, open_gain): a gain
  // would only lift the row sum its parents' links leave it.
  if (open_weight(e) <= 0) return 0;
  std::uint64_t cast = 0;
  if (e.uncovered < 0) {
    const Uncovered u = estimate_uncovered(e, hierarchy, rays, rays_per_leaf, seed);
    e.uncovered = static_cast<float>(u.share);
    e.uncovered_se = static_cast<float>(u.se);
    cast = static_cast<std::uint64_t>(std::max(1, rays_per_leaf / kRaysPerPoint) * kRaysPerPoint);
  }
  const double s = static_cast<double>(e.gather_scale) * e.next[1];
  double target = 1.0 - e.uncovered;
  // The rays' target is noisy where part of the hemisphere is open (a leaf facing the
  // Cornell box's open front: about 0.06 at 64 rays where the target is 0.5). A
  // correction no larger than that noise is mostly noise: it is shrunk by
  // d^2 / (d^2 + se^2) (Wiener), whole where the rays agree (a closed room, se 0).
  const double d = target - s, se2 = static_cast<double>(e.uncovered_se) * e.uncovered_se;
  if (se2 > 0 && d != 0) target = s + d * (d * d / (d * d + se2));
  // A surplus comes out of what the leaf inherits from cluster receivers first: a
  // cluster hands its members light that arrives along their direction whether or not
  // they see its source (a room's inner walls, whose clusters also hold the outside,
  // get the outside's light), so the surface chain is the better estimate.
  const double clusters = s - static_cast<double>(e.gather_scale) * e.gathered[1];
  if (s > target && clusters > 0) {
    const double surplus = s - target;
    if (surplus <= clusters) {
      e.cluster_scale *= static_cast<float>((clusters - surplus) / clusters);
    } else {
      e.cluster_scale = 0;
      e.gather_scale *= static_cast<float>(target / (s - clusters));
    }
  } else if (s > 0) {
    const auto g = static_cast<float>(std::min(kNormalizeGainCap, target / s));
    e.gather_scale *= g;
    e.cluster_scale *= g;
  }
  return cast;
}

}  // namespace

RowSumStats apply_row_sums(const std::vector<Element*>& elements, RowSumMode mode,
                           ClusterReceiver receiver, const Hierarchy& hierarchy,
                           const RayScene& rays, int rays_per_leaf, std::uint64_t seed, int threads,
                           PropagationCache* cache) {
  RowSumStats st;
  // Push the transport totals down like irradiance from a unit radiosity, per unit of
  // area as the links give it (channel 0) and per unit of open area as the propagation
  // gathers (channel 1; the same when nothing is closed in). `next` is scratch here
  // (propagation overwrites it).
  st.rows_kept = push_transport(elements, receiver, threads, cache);
  std::vector<Element*> leaves;
  double area = 0;
  st.min = std::numeric_limits<double>::infinity();
  for (Element* e : elements) {
    e->gather_scale = 1;
    e->cluster_scale = 1;
    if (e->is_cluster() || !e->child_span().empty()) continue;
    leaves.push_back(e);
    const double s = e->next[1];
    // The open-area gain must not lift a leaf far above a whole hemisphere (or above
    // what its links give without it, if that is more already): where an estimated
    // open fraction is lower than its links' visibility says (two contacts that
    // coincide with both ends of a segment let it pass through a solid), it would.
    const double cap = kOpenGainCap * std::max(1.0, e->next[0]);
    if (s > cap) {
      e->gather_scale = e->cluster_scale = static_cast<float>(cap / s);
      ++st.open_capped;
    }
    // The statistics are over the open area, where the row sum means something.
    const double open = open_weight(*e);
    if (open <= 0) continue;
    const double used = static_cast<double>(e->gather_scale) * s;
    st.min = std::min(st.min, used);
    st.max = std::max(st.max, used);
    st.area_mean += e->area * open * used;
    if (std::abs(used - 1) <= kRowSumBand) st.within_band += e->area * open;
    area += e->area * open;
  }
  if (area > 0) {
    st.area_mean /= area;
    st.within_band /= area;
  }
  if (area <= 0) st.min = 0;
  st.corrected = st.open_capped;
  if (mode == RowSumMode::Keep) return st;

  std::uint64_t rays_cast = 0;
  const auto n = static_cast<std::ptrdiff_t>(leaves.size());
#pragma omp parallel for num_threads(threads) schedule(dynamic, 64) reduction(+ : rays_cast)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (interrupted()) continue;
    Element& e = *leaves[static_cast<std::size_t>(i)];
    const double s = static_cast<double>(e.gather_scale) * e.next[1];
    if (mode == RowSumMode::Normalize) {
      rays_cast += normalize_leaf(e, hierarchy, rays, rays_per_leaf, seed);
    } else if (s > 1) {
      e.gather_scale *= static_cast<float>(1 / s);
      e.cluster_scale *= static_cast<float>(1 / s);
    }
  }
  throw_if_interrupted();
  st.corrected = 0;
  for (const Element* e : leaves)
    st.corrected += e->gather_scale != 1.0f || e->cluster_scale != 1.0f ? 1 : 0;
  st.rays_cast = rays_cast;
  return st;
}

}  // namespace hrad
