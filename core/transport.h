// Transport: what a candidate link r <- s carries, estimated from geometry and
// visibility. Surface pairs use the exact point-to-polygon form factor averaged
// over Gauss points on the receiver (bounded for touching or very close pairs);
// links with a cluster use the isotropic cluster model (Sillion 1995): a cluster
// of total area A shows a projected area of A/4 in every direction, and a cluster
// receiver's members see on average 1/4 of the normal-incidence irradiance.
//
// Visibility is the fraction of k segments between points sampled on r and s
// that nothing blocks; the sample points come from a hash of the two element ids
// and the run seed (no shared random stream), so the estimate is the same in
// whatever order or thread the link is examined.
#pragma once

#include "core/element.h"
#include "core/shaft.h"

#include <cstdint>
#include <string>

namespace hrad {

class Hierarchy;
class RayScene;

enum class PairClass : std::uint8_t {
  Cull,            ///< cannot exchange light (self, back-facing, coplanar): no link, no ray
  ReceiverInside,  ///< r lies inside s (s contains r): s must be refined
  SourceInside,    ///< s lies inside r: r must be refined
  NearField,       ///< a cluster is too close for the cluster model: refine if possible
  Regular,
};

/// How a cluster's projected area and its members' mean cosine are estimated:
///  isotropic    A/4 in every direction, members see 1/4 (Sillion 1995);
///  directional  from the members' areas along +-x, +-y, +-z (exact when every
///               member is axis-aligned, as in most architecture).
enum class ClusterModel : std::uint8_t { Isotropic, Directional };
ClusterModel parse_cluster_model(const std::string& name);

class Transport {
 public:
  /// Gauss points per direction on a surface receiver (n x n point evaluations).
  static constexpr int kQuadratureOrder = 2;

  Transport(const Hierarchy& hierarchy, const RayScene& rays, int visibility_rays,
            std::uint64_t seed, ClusterModel model = ClusterModel::Directional);

  [[nodiscard]] PairClass classify(const Element& r, const Element& s) const;
  /// Unoccluded F_rs in [0,1], receiver-area normalised.
  [[nodiscard]] double form_factor(const Element& r, const Element& s) const;
  /// Spread of the point-to-source form factor over the receiver's corners and
  /// centre (surface pairs; 0 for clusters).
  [[nodiscard]] double form_factor_spread(const Element& r, const Element& s) const;
  /// Fraction of unblocked segments; adds the rays cast to `rays` and the rays not
  /// needed (visibility off for the scene, or an empty shaft: V = 1) to `skipped`.
  [[nodiscard]] double visibility(const Element& r, const Element& s, std::uint64_t& rays,
                                  std::uint64_t& skipped) const;
  /// The same, without counting skipped rays.
  [[nodiscard]] double visibility(const Element& r, const Element& s, std::uint64_t& rays) const {
    std::uint64_t skipped = 0;
    return visibility(r, s, rays, skipped);
  }
  /// Scene-wide visibility effect (core/effects.h): off means V = 1 without rays,
  /// which is exact when nothing in the scene can block (a convex enclosure).
  void set_visibility_effect(bool on) { visibility_on_ = on; }
  /// Per-pair shaft culling (core/shaft.h): V = 1 without rays when the shaft
  /// between the two elements holds no polygon.
  void set_shaft_culling(bool on) { shaft_culling_ = on; }
  [[nodiscard]] int rays_per_link() const { return visibility_rays_; }
  [[nodiscard]] double scale() const { return scale_; }

 private:
  const Hierarchy& hierarchy_;
  const RayScene& rays_;
  int visibility_rays_;
  std::uint64_t seed_;
  ClusterModel model_;
  double scale_;      ///< scene bounding-box diagonal
  double plane_tol_;  ///< distance below which a point counts as on a plane
  bool visibility_on_ = true;
  bool shaft_culling_ = false;
  ShaftCuller shafts_;
};

/// Counter-based random numbers: the i-th uniform double in [0,1) of stream `key`.
double hashed_uniform(std::uint64_t key, std::uint64_t i);

}  // namespace hrad
