#include "core/transport/cluster_exposure.h"

#include "core/base/geometry.h"
#include "core/base/hash.h"
#include "core/base/interrupt.h"
#include "core/hierarchy/element.h"
#include "core/hierarchy/hierarchy.h"
#include "core/raycast/ray_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace hrad {

namespace {

// Distance along the unit direction d from o (inside or on the box) to where it leaves b.
double exit_distance(const Aabb& b, const Vec3& o, const Vec3& d) {
  double t = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 0) t = std::min(t, (b.hi[a] - o[a]) / d[a]);
    if (d[a] < 0) t = std::min(t, (b.lo[a] - o[a]) / d[a]);
  }
  return std::max(t, 0.0);
}

// The unit vector of axis direction k (+x, -x, +y, -y, +z, -z).
Vec3 axis_direction(std::size_t k) {
  Vec3 d = Vec3::Zero();
  d[static_cast<int>(k / 2)] = k % 2 == 0 ? 1.0 : -1.0;
  return d;
}

// Per cluster (by its place in `clusters`), per axis direction: the sums whose ratio is
// its exposure within its parent (numerator: its members' area along k times their
// exposure within the parent; denominator: within the cluster itself).
struct ChildSums {
  std::array<double, 6> within_parent{};
  std::array<double, 6> within_own{};
};

}  // namespace

ExposureStats compute_cluster_exposure(Hierarchy& hierarchy, const RayScene& rays,
                                       std::uint64_t seed, int threads) {
  ExposureStats st;
  // Clusters, numbered through Element::index (scratch until the next propagation),
  // and the member polygons directly under them.
  std::vector<Element*> clusters, members;
  std::vector<Element*> stack{&hierarchy.root()};
  while (!stack.empty()) {
    Element* c = stack.back();
    stack.pop_back();
    if (!c->is_cluster()) continue;
    c->index = static_cast<std::uint32_t>(clusters.size());
    clusters.push_back(c);
    if (!c->light) c->light = std::make_unique<ClusterLight>();
    c->light->exposure.assign(c->child_span().size(), std::array<float, 6>{1, 1, 1, 1, 1, 1});
    for (Element& k : c->child_span()) {
      if (k.is_cluster())
        stack.push_back(&k);
      else
        members.push_back(&k);
    }
  }
  std::vector<ChildSums> sums(clusters.size());
  const double slack = 4 * RayScene::kEndpointEpsilon * rays.scale();
  const auto n = static_cast<std::ptrdiff_t>(members.size());
  std::uint64_t cast = 0;
  double exposed_area = 0, facing_area = 0;
#pragma omp parallel num_threads(threads) reduction(+ : cast, exposed_area, facing_area)
  {
    std::vector<Element*> chain;
    std::vector<double> exposure;  // per level of the chain, for one axis direction
#pragma omp for schedule(dynamic, 64)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      if (interrupted()) continue;
      Element& m = *members[static_cast<std::size_t>(i)];
      chain.clear();
      for (Element* c = m.parent; c != nullptr; c = c->parent) chain.push_back(c);
      const std::array<double, 6> share = axis_shares(m.normal);
      const std::uint64_t key = child_id(m.id, 0xE7905u) ^ seed;
      std::array<float, 6>& own = exposure_within_parent(m);
      for (std::size_t k = 0; k < 6; ++k) {
        if (!(share[k] > 0)) continue;
        const Vec3 axis = axis_direction(k);
        const Vec3 u = axis.unitOrthogonal(), v = axis.cross(u);
        exposure.assign(chain.size(), 0.0);
        int counted = 0;
        for (int r = 0; r < kExposureRays; ++r) {
          const auto j = static_cast<std::uint64_t>(8 * (6 * r + static_cast<int>(k)));
          const Vec3 at = hierarchy.sample_point(
              m, hashed_uniform(key, j), hashed_uniform(key, j + 1), hashed_uniform(key, j + 2));
          Vec3 dir = cosine_direction(axis, u, v, hashed_uniform(key, j + 3),
                                      (r + hashed_uniform(key, j + 4)) / kExposureRays);
          const double front = dir.dot(m.normal);
          if (front < 0) dir -= 2 * front * m.normal;  // folded into m's front half-space
          if (!(dir.dot(m.normal) > 0)) continue;
          ++counted;
          ++cast;
          const auto hit = rays.intersect(at, dir, std::numeric_limits<double>::infinity(), m.face);
          const double t = hit ? hit->t : std::numeric_limits<double>::infinity();
          // The boxes grow along the chain: once a ray stops inside one, it stops inside
          // every larger one. A hit on the box's face (a wall the cluster holds) is out.
          for (std::size_t l = 0;
               l < chain.size() && t >= exit_distance(chain[l]->box, at, dir) - slack; ++l)
            exposure[l] += 1;
        }
        if (counted == 0) continue;
        for (double& x : exposure) x /= counted;
        own[k] = static_cast<float>(exposure[0]);
        const double a = share[k] * m.area;
        exposed_area += a * exposure[0];
        facing_area += a;
        for (std::size_t l = 1; l < chain.size() && exposure[l - 1] > 0; ++l) {
          ChildSums& s = sums[chain[l - 1]->index];
#pragma omp atomic
          s.within_parent[k] += a * exposure[l];
#pragma omp atomic
          s.within_own[k] += a * exposure[l - 1];
        }
      }
    }
  }
  throw_if_interrupted();
  for (Element* c : clusters) {
    if (c->parent == nullptr) continue;
    const ChildSums& s = sums[c->index];
    std::array<float, 6>& x = exposure_within_parent(*c);
    for (std::size_t k = 0; k < 6; ++k)
      x[k] = s.within_own[k] > 0 ? static_cast<float>(s.within_parent[k] / s.within_own[k]) : 1.0f;
  }
  st.rays_cast = cast;
  if (facing_area > 0) st.mean_exposure = exposed_area / facing_area;
  return st;
}

}  // namespace hrad
