// Element: the nodes of the hierarchical radiosity graph (its edges, the links, are
// in core/hierarchy/link_list.h).
//
// One complete hierarchy covers the scene: clusters (axis-aligned groups of input
// polygons) over surface elements (an input polygon and, below it, its lazily built
// quadtree). Children are a pure function of the parent, and every element's id is
// a hash of its path from the root, so ids, geometry and random numbers do not
// depend on the order in which refiners happened to subdivide.
//
// Concurrency: `children` is published once with a release store after the block
// is fully built (under the element lock pool); readers acquire it. `links` is
// only appended to under the link lock pool during refinement, from the storing
// refiner's arena, and read-only during propagation. Radiosities are frozen during
// refinement.
#pragma once

#include "core/base/geometry.h"
#include "core/hierarchy/link_list.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace hrad {

enum class ElementKind : std::uint8_t { Cluster, Surface };

struct ClusterLight;

struct Element {
  std::uint64_t id = 0;  ///< hash of the path from the root (stable across runs)
  Element* parent = nullptr;
  std::atomic<Element*> children{nullptr};  ///< contiguous block of child_count
  std::uint32_t child_count = 0;            ///< valid once children is non-null
  ElementKind kind = ElementKind::Surface;
  std::uint8_t depth = 0;      ///< levels below the input polygon (surfaces) or root
  std::uint16_t nverts = 0;    ///< surfaces: 3, 4, or more (then corners live in ngon)
  std::uint32_t face = 0;      ///< surfaces: input polygon; clusters: first in face order
  std::uint32_t face_end = 0;  ///< clusters: one past the last in face order
  std::uint32_t material = 0;  ///< surfaces only
  /// Leaves: factor applied to the gathered irradiance (row-sum correction, see
  /// core/solver/row_sums.h; 1 when off): gather_scale to what the leaf's surface chain
  /// gathers, cluster_scale to what it inherits from cluster receivers above its polygon
  /// (the two differ only where normalize takes a surplus out of the latter).
  float gather_scale = 1;
  float cluster_scale = 1;
  /// The element's position in the list the last propagation was given (its gather
  /// matrix's row and value slot, core/solver/propagation.cpp); scratch elsewhere. Near
  /// `kind`: the matrix's build reads both from every link's source.
  std::uint32_t index = 0;
  /// Open fraction in [0, 1]: the share of the area that is not closed in by a
  /// contact and so can exchange light (core/transport/open_fraction.h); negative until set.
  float open = -1;
  /// NUMA node (logical) of the arena memory holding this element, as the arena
  /// counts it (core/parallel/node_arena.h); set at allocation. Uses what was padding.
  std::uint16_t home_node = 0;
  /// Surface children of surface elements: the share of the parent's irradiance this
  /// element receives, relative to the parent's mean (core/solver/push_weights.h); 1 elsewhere.
  float push_weight = 1;
  /// Surface children of surface elements: the share of what the parent inherited from
  /// the clusters above its polygon that this element receives, relative to the
  /// parent's mean (core/solver/push_weights.h); 1 elsewhere. (In what was padding.)
  float cluster_weight = 1;
  double area = 0;             ///< surface area (clusters: total of member polygons)
  Vec3 corner[4];              ///< surfaces with nverts <= 4
  const Vec3* ngon = nullptr;  ///< surfaces with nverts > 4 (top-level polygon only)
  Vec3 normal = Vec3::Zero();  ///< surfaces: unit normal; clusters: zero
  Vec3 center = Vec3::Zero();  ///< surfaces: centroid; clusters: area-weighted centroid
  Aabb box;                    ///< bounds (surfaces too)
  /// Clusters: member areas split by axis direction +x,-x,+y,-y,+z,-z (add_by_axis);
  /// the directional cluster model's projected area is sum_i |d_i| dir_area[axis i, sign].
  std::array<float, 6> dir_area{};
  Rgb rho = Rgb::Zero();       ///< reflectance (clusters: area-weighted average)
  Rgb emission = Rgb::Zero();  ///< exitance E (clusters: area-weighted average)
  Rgb B = Rgb::Zero();         ///< radiosity, frozen during refinement
  Rgb gathered = Rgb::Zero();  ///< irradiance gathered over this element's own links
  Rgb next = Rgb::Zero();      ///< scratch for the Jacobi update
  LinkList links;  ///< links where this element is the receiver (core/hierarchy/link_list.h)
  /// Clusters: the propagation's directional state (below); allocated by it.
  std::unique_ptr<ClusterLight> light;
  /// Share of the hemisphere above the element's open points that meets no lit surface
  /// (nothing, a back face, or the inside of a solid), estimated by rays (row_sums =
  /// normalize, core/solver/row_sums.cpp; negative until estimated).
  float uncovered = -1;
  /// The standard error of `uncovered` (over its points; 0 when every point agrees).
  float uncovered_se = 0;

  [[nodiscard]] bool is_cluster() const { return kind == ElementKind::Cluster; }
  [[nodiscard]] std::span<const Vec3> corners() const {
    return nverts > 4 ? std::span<const Vec3>(ngon, nverts) : std::span<const Vec3>(corner, nverts);
  }
  [[nodiscard]] std::span<Element> child_span() const {
    Element* c = children.load(std::memory_order_acquire);
    return c ? std::span<Element>(c, child_count) : std::span<Element>();
  }
  /// Projected area seen from direction `d` (unit): exact for surfaces; for clusters
  /// the directional model (exact when every member is axis-aligned).
  [[nodiscard]] double projected_area(const Vec3& d) const {
    if (!is_cluster()) return area * std::max(0.0, normal.dot(d));
    double p = 0;
    for (int i = 0; i < 3; ++i)
      p += std::abs(d[i]) *
           static_cast<double>(dir_area[static_cast<std::size_t>(2 * i + (d[i] < 0))]);
    return p;
  }
  /// Radius of the bounding sphere around `center` (a cheap size for near-field tests):
  /// the distance to the box's farthest corner, which for an off-centre `center` (a
  /// cluster's area-weighted centre) need not be box.lo or box.hi.
  [[nodiscard]] double radius() const {
    return (box.hi - center).cwiseAbs().cwiseMax((center - box.lo).cwiseAbs()).norm();
  }
};

/// What the propagation keeps per cluster, by axis direction +x, -x, +y, -y, +z, -z.
struct ClusterLight {
  /// cluster_receiver = cosine only: irradiance arriving along each direction (on a
  /// unit surface facing that way), gathered here plus all that the cluster's
  /// ancestors gathered.
  std::array<Rgb, 6> arriving{};
  /// Radiosity leaving towards each direction: sum over the member polygons of open
  /// area x B split by axis direction (add_by_axis), and the same sum without B. A
  /// link from the cluster carries, along its direction d, sum_i |d_i| leaving /
  /// sum_i |d_i| open_area: the radiosity of the members that face d, not the mean of
  /// all of them (a desk shows the ceiling its lit top, not the mean of its top and
  /// its dark underside).
  std::array<Rgb, 6> leaving{};
  std::array<Rgb, 6> leaving_next{};
  std::array<double, 6> open_area{};
  /// Each child's exposure within this cluster per axis direction
  /// (core/transport/cluster_exposure.h), by its place among the children; empty: 1.
  std::vector<std::array<float, 6>> exposure;
  /// The members' open area weighted by their exposure (the product along the chain of
  /// children), per axis direction: `leaving` is summed with the same weights, and
  /// `leaving / exposed_area` is the radiosity the cluster shows. open_area without
  /// exposures.
  std::array<double, 6> exposed_area{};
  bool leaving_made = false;  ///< `leaving` holds the sums of a finished sweep
  /// The members' open area projected along d: sum_i |d_i| open_area (times |d|).
  [[nodiscard]] double projected_open_area(const Vec3& d) const {
    double a = 0;
    for (int i = 0; i < 3; ++i)
      a += std::abs(d[i]) * open_area[static_cast<std::size_t>(2 * i + (d[i] < 0))];
    return a;
  }
  /// The radiosity this cluster shows along the direction d (of any non-zero length:
  /// the ratio does not depend on it); its mean B when no member faces d or the sums
  /// are not yet made.
  [[nodiscard]] Rgb radiosity_towards(const Vec3& d, const Rgb& mean) const {
    if (!leaving_made) return mean;
    Rgb p = Rgb::Zero();
    for (int i = 0; i < 3; ++i)
      p += std::abs(d[i]) * leaving[static_cast<std::size_t>(2 * i + (d[i] < 0))];
    double a = 0;
    for (int i = 0; i < 3; ++i)
      a += std::abs(d[i]) * exposed_area[static_cast<std::size_t>(2 * i + (d[i] < 0))];
    return a > 0 ? Rgb(p / a) : mean;
  }
};

/// A unit normal n's shares of the axis directions +x, -x, +y, -y, +z, -z, in
/// proportion to |n_i| (weights |n_i| / (|n_x| + |n_y| + |n_z|) on the side n faces,
/// which sum to 1); add_by_axis adds x split by them to a per-axis-direction array.
/// This is how the directional cluster model's sums (Element::dir_area, ClusterLight)
/// are made, and how a cosine cluster receiver hands its light on. An axis-aligned
/// member puts all of x on one entry, and the model is exact for it. A tilted one is
/// spread so that the model's projected area, averaged over all directions, is A/4 as
/// it must be; with weights |n_i| it was up to 73 % too large (a member facing
/// (1,1,1)/sqrt 3 seen along that diagonal), and clusters of tilted polygons (the
/// cabin's fuselage and seats) carried too much.
inline std::array<double, 6> axis_shares(const Vec3& n) {
  std::array<double, 6> w{};
  const double l1 = std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]);
  if (!(l1 > 0)) return w;
  for (int a = 0; a < 3; ++a) {
    w[static_cast<std::size_t>(2 * a)] = std::max(0.0, n[a] / l1);
    w[static_cast<std::size_t>(2 * a + 1)] = std::max(0.0, -n[a] / l1);
  }
  return w;
}
template <class T>
void add_by_axis(std::array<T, 6>& sums, const Vec3& n, const T& x) {
  const std::array<double, 6> w = axis_shares(n);
  for (std::size_t k = 0; k < 6; ++k) sums[k] += w[k] * x;
}

/// True when a is b or an ancestor of b.
inline bool contains(const Element* a, const Element* b) {
  for (const Element* e = b; e != nullptr; e = e->parent)
    if (e == a) return true;
  return false;
}

}  // namespace hrad
