// Transport: what a candidate link r <- s carries, estimated from geometry and
// visibility. Surface pairs use the exact point-to-polygon form factor averaged
// over Gauss points on the receiver (bounded for touching or very close pairs);
// links with a cluster use the cluster model (Sillion 1995) from centre to centre:
// the source's projected area along the direction (A/4 for the isotropic model,
// from its members' axis-aligned areas for the directional one) and the receiver's
// mean cosine (1/4, or its own projected area over its area). A cluster pair closer
// than twice the sum of its radii is opened and summed over its parts, because a
// single evaluation is low there.
//
// Visibility is estimated from k segments between stratified points on r and s,
// each weighted by the form-factor kernel cos cos / r^2, so it is the occluded
// share of the transport and not of the point pairs (the plain fraction of open
// segments was 3-12 % low). The sample points come from a hash of the two element
// ids and the run seed (no shared random stream), so the estimate is the same in
// whatever order or thread the link is examined.
#pragma once

#include "core/hierarchy/element.h"
#include "core/transport/cluster_model.h"
#include "core/transport/shaft.h"

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

class Transport {
 public:
  /// Gauss points per direction on a surface receiver (n x n point evaluations).
  static constexpr int kQuadratureOrder = 2;
  /// A link with a cluster end closer than this many times the sum of the two radii
  /// has its form factor summed over the ends' parts (see cluster_ff in the .cpp) ...
  static constexpr double kClusterOpenDistance = 2.0;
  /// ... with at most this many centre-to-centre evaluations per link.
  static constexpr int kClusterOpenBudget = 32;

  Transport(const Hierarchy& hierarchy, const RayScene& rays, int visibility_rays,
            std::uint64_t seed, ClusterModel model = ClusterModel::Directional);

  [[nodiscard]] PairClass classify(const Element& r, const Element& s) const;
  /// Unoccluded F_rs in [0,1], receiver-area normalised.
  [[nodiscard]] double form_factor(const Element& r, const Element& s) const;
  /// Form factor from the point p (unit normal n) to s: exact for a surface s, the
  /// cluster model's point form for a cluster (core/solver/push_weights.h).
  [[nodiscard]] double form_factor_from_point(const Vec3& p, const Vec3& n, const Element& s) const;
  /// Spread of the point-to-source form factor over the receiver's corners and
  /// centre (surface pairs; 0 for clusters).
  [[nodiscard]] double form_factor_spread(const Element& r, const Element& s) const;
  /// Kernel-weighted fraction of unblocked segments (see above); adds the rays cast to
  /// `rays` and the rays not needed (visibility off for the scene, or an empty shaft:
  /// V = 1) to `skipped`. `draw` picks one of independent sets of random numbers for
  /// the pair (draw 0 is the one the oracle decides on; the refiner re-draws with 1
  /// where that decision depended on the value, core/solver/refiner.cpp); `count` rays
  /// (0: visibility_rays; none at all when visibility_rays is 0).
  [[nodiscard]] double visibility(const Element& r, const Element& s, std::uint64_t& rays,
                                  std::uint64_t& skipped, unsigned draw = 0, int count = 0) const;
  /// The same, without counting skipped rays.
  [[nodiscard]] double visibility(const Element& r, const Element& s, std::uint64_t& rays) const {
    std::uint64_t skipped = 0;
    return visibility(r, s, rays, skipped);
  }
  /// Visibility from the point p (unit normal n) to s, estimated in the same way with
  /// `rays` segments whose random numbers come from `key` and the run seed (the
  /// final gather at probes, core/solver/solver.cpp). 1 without rays or when visibility is
  /// off for the scene.
  [[nodiscard]] double visibility_from_point(const Vec3& p, const Vec3& n, const Element& s,
                                             std::uint64_t key, int rays) const;
  /// Scene-wide visibility effect (core/config/effects.h): off means V = 1 without rays,
  /// which is exact when nothing in the scene can block (a convex enclosure).
  void set_visibility_effect(bool on) { visibility_on_ = on; }
  /// Per-pair shaft culling (core/transport/shaft.h): V = 1 without rays when the shaft
  /// between the two elements holds no polygon.
  void set_shaft_culling(bool on) { shaft_culling_ = on; }
  [[nodiscard]] int rays_per_link() const { return visibility_rays_; }
  [[nodiscard]] double scale() const { return scale_; }

 private:
  template <class SampleA>
  double kernel_visibility(SampleA&& sample_a, const Vec3& toward_a, double radius,
                           const Element& s, std::uint64_t key, int rays) const;
  double cluster_ff(const Element& r, const Element& s, int& budget) const;

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

}  // namespace hrad
