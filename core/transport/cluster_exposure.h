// Cluster exposure: how much of each member of a cluster the light that reaches the
// cluster can reach, and the cluster's members' light can leave by.
//
// A link with a cluster end treats the cluster's members alike along each axis
// direction (core/hierarchy/element.h, ClusterLight): the members facing +y share what
// arrives along +y by their open area, and show along +y the mean radiosity of those
// members. Where one member hides another (a monitor's tube over the top of its foot
// 2-8 cm below it, a desk's top over the chair seat under it), the hidden one took an
// equal share of the light that only the exposed one can catch, and the link showed
// its receiver the hidden one's radiosity as well as the exposed one's. On builtin:lab
// the top of a monitor's foot came out 3.4 times too bright, and links from clusters
// showed their receivers 5-10 % too little radiosity (docs/energy-budget.md: the
// members in view are the lit ones).
//
// So each child c of a cluster P carries, per axis direction k, its exposure X_ck in
// [0, 1] within P: for a member polygon, the share of kExposureRays rays from points
// on it, cosine-distributed about k (folded into its front half-space), that leave
// P's bounding box before they hit anything (a hit on the box's face, a wall that P
// holds, counts as leaving); for a child cluster, the same share
// over its members' rays, taken among those that left the child's own box (weighted
// by the members' area along k), so that a member's exposure within an ancestor is
// the product of the factors along its chain. The propagation
// (core/solver/propagation.cpp) weighs both ways by it: light arriving at P along k is
// shared by open area times X (the total kept), and P shows along k the mean of its
// members' radiosity weighted by open area times X (along a direction in which no
// member is exposed, by open area alone). Reciprocity is kept: member m and a receiver
// exchange in proportion to m's area along k times its exposure, both ways.
//
// A study option (cluster_members = exposed), not the default: the factors multiply
// along the chain, so a member exposed within its own small cluster but hidden by a
// surface of the next one up (a luggage bin's side 2 cm from the fuselage) still
// counts as exposed there, and in the cabin the propagation then needs 20 times the
// sweeps (docs/energy-budget.md).
//
// The rays depend only on the geometry, the hierarchy's ids and the seed: computed
// once per run, before the first propagation.
#pragma once

#include "core/hierarchy/element.h"

#include <array>
#include <cstdint>

namespace hrad {

class Hierarchy;
class RayScene;

/// Rays per member polygon and axis direction it faces.
inline constexpr int kExposureRays = 8;

struct ExposureStats {
  std::uint64_t rays_cast = 0;
  /// Area-weighted mean over member polygons and the axis directions they face of the
  /// exposure within their own cluster.
  double mean_exposure = 1;
};

/// A child's exposure within its parent cluster per axis direction: the entry of the
/// parent's ClusterLight::exposure that belongs to it (the parent must have them).
inline const std::array<float, 6>& exposure_within_parent(const Element& child) {
  const Element& p = *child.parent;
  return p.light->exposure[static_cast<std::size_t>(&child - p.child_span().data())];
}
inline std::array<float, 6>& exposure_within_parent(Element& child) {
  Element& p = *child.parent;
  return p.light->exposure[static_cast<std::size_t>(&child - p.child_span().data())];
}

/// Fills ClusterLight::exposure of every cluster (creating its ClusterLight). On
/// `threads` threads; polls for interrupts (throws Interrupted).
ExposureStats compute_cluster_exposure(Hierarchy& hierarchy, const RayScene& rays,
                                       std::uint64_t seed, int threads);

}  // namespace hrad
