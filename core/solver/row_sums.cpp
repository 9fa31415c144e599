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

// Fraction of `n` cosine-distributed directions from points on `e` that hit nothing.
double estimate_escape(const Element& e, const Hierarchy& h, const RayScene& rays, int n,
                       std::uint64_t seed) {
  const Vec3 u = e.normal.unitOrthogonal();
  const Vec3 v = e.normal.cross(u);
  const std::uint64_t key = child_id(e.id, 0xE5CA7Eu) ^ seed;
  // Origins step off the surface by twice the ray end-point exclusion and keep 1%
  // of the element's size away from its edges: a ray must not slip through the
  // seam of two walls because its first hit fell within the exclusion distance.
  const double lift = 2 * RayScene::kEndpointEpsilon * rays.scale();
  int escaped = 0;
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<std::uint64_t>(5 * k);
    const Vec3 s = h.sample_point(e, hashed_uniform(key, i), hashed_uniform(key, i + 1),
                                  hashed_uniform(key, i + 2));
    const Vec3 p = e.center + 0.99 * (s - e.center) + lift * e.normal;
    const Vec3 dir =
        cosine_direction(e.normal, u, v, hashed_uniform(key, i + 3), hashed_uniform(key, i + 4));
    // The ray leaves e's own polygon, which it cannot hit again (a grazing ray could
    // be reported hitting it in single precision).
    if (!rays.intersect(p, dir, std::numeric_limits<double>::infinity(), e.face)) ++escaped;
  }
  return static_cast<double>(escaped) / n;
}

}  // namespace

RowSumStats apply_row_sums(const std::vector<Element*>& elements, RowSumMode mode,
                           ClusterReceiver receiver, const Hierarchy& hierarchy,
                           const RayScene& rays, int escape_rays, std::uint64_t seed, int threads,
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
    if (e->is_cluster() || !e->child_span().empty()) continue;
    leaves.push_back(e);
    const double s = e->next[1];
    // The open-area gain must not lift a leaf far above a whole hemisphere (or above
    // what its links give without it, if that is more already): where an estimated
    // open fraction is lower than its links' visibility says (two contacts that
    // coincide with both ends of a segment let it pass through a solid), it would.
    const double cap = kOpenGainCap * std::max(1.0, e->next[0]);
    if (s > cap) {
      e->gather_scale = static_cast<float>(cap / s);
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
    double target = 1;
    if (mode == RowSumMode::Normalize) {
      if (e.escape < 0) {
        e.escape = static_cast<float>(estimate_escape(e, hierarchy, rays, escape_rays, seed));
        rays_cast += static_cast<std::uint64_t>(escape_rays);
      }
      target = 1.0 - e.escape;
      if (s > 0) e.gather_scale *= static_cast<float>(target / s);
    } else if (s > target) {
      e.gather_scale *= static_cast<float>(target / s);
    }
  }
  throw_if_interrupted();
  st.corrected = 0;
  for (const Element* e : leaves) st.corrected += e->gather_scale != 1.0f ? 1 : 0;
  st.rays_cast = rays_cast;
  return st;
}

}  // namespace hrad
