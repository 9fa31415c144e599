// Open fraction: the share of an element's area that can exchange light at all.
//
// Faces in contact with other faces have closed-in parts: the floor under a box that
// stands on it, the side of a cube pushed against another, a wall behind a cabinet.
// Every direction above such a point leads into the inside of a solid (its first hit
// is a back face), so it neither receives nor sends light. Left in the energy books,
// a coarse element that straddles a contact shares what it gathers evenly with its
// closed-in part, which wastes it, and as a source it shows the dark closed-in part's
// radiosity averaged into its own: in a cluttered furnace (every face E, one rho)
// visible leaves gathered 1.8 % less than their whole hemisphere and the closed-in
// area (5 % of it) 0.1-0.5 of it, where it should gather nothing; at rho 0.9 that
// made the answer 13 % low.
//
// So every surface element carries w, its open fraction, and the propagation works
// per unit of *open* area (core/solver/propagation.h): an element's gathered irradiance is
// divided by w (its links' visibility already counts the closed-in part as blocked),
// a closed-in element (w = 0) gathers nothing, and a parent's radiosity is the mean
// of its children's weighted by open area. Energy is conserved exactly: an interior
// element's w is the area-weighted mean of its children's.
//
// A leaf's w is estimated once, by rays: kOpenPoints stratified points on the leaf,
// kOpenRays cosine-distributed rays from each, and a point counts as closed in when
// most of its rays first hit a back face. A leaf that no other polygon crosses or
// touches inside (core/raycast/face_crossings.h) cannot be partly closed in: moving
// along it never enters or leaves a solid. Its w is 1 (or 0) when kQuickPoints points,
// one per quarter, two rays each, all find it open (or all closed in); only when they
// disagree (geometry that is not watertight) does it get the full estimate. That
// decides about 80 % of the lab's leaves with 8 rays instead of about 50: 0.75 M rays
// instead of 1.89 M, about 0.3 s instead of 0.52 s on one thread. A ray that escapes, or hits a front face,
// finds the point open; so open-ended geometry seen from outside (the inside of a
// tube) does not close a point in. A surface coincident with the point's own face
// (the two faces of a contact) is skipped by the ray's end-point exclusion, which is
// what lets the ray reach the solid's inside; but a face in the point's own plane that
// faces it (a box's bottom and the floor it stands on) closes the point in at once,
// found by one short ray along the normal (the bottom would otherwise see the void
// under the floor and count as open).
#pragma once

#include "core/hierarchy/element.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace hrad {

class Hierarchy;
class RayScene;

/// The element's open fraction as a weight: 1 until it is estimated.
inline double open_weight(const Element& e) {
  return e.open < 0 ? 1.0 : static_cast<double>(e.open);
}

/// The smallest open fraction a few rays' estimate per unit of open area is divided
/// by: a mostly closed-in element's few open samples are not blown up (the
/// propagation's gather at leaves, core/solver/propagation.cpp, and the children's own
/// visibilities of push_visibility = child, core/solver/push_weights.cpp).
inline constexpr double kMinOpenFraction = 0.25;

/// Points per leaf and rays per point of the estimate.
inline constexpr int kOpenPoints = 16;
inline constexpr int kOpenRays = 3;
/// Points of the estimate on a polygon that nothing crosses (estimate_open_fraction).
inline constexpr int kQuickPoints = 4;

struct OpenStats {
  std::uint64_t rays_cast = 0;
  double area_fraction = 1;  ///< open share of the leaves' total area
};
/// Sets `open` for every element in `elements` (parents before children): leaves
/// whose estimate is missing get one from rays, every other element the
/// area-weighted mean of its children. With `possible` false (nothing in the scene
/// can close a point in: visibility is off for it, see core/config/effects.h) every element
/// is open (w = 1) and no ray is cast. `on_progress`, when given, is called on the
/// calling thread now and then with the share of `elements` done (the last call: 1).
OpenStats update_open_fractions(const std::vector<Element*>& elements, const Hierarchy& hierarchy,
                                const RayScene& rays, std::uint64_t seed, int threads,
                                bool possible,
                                const std::function<void(double share)>& on_progress = {});

/// The estimate for one surface element, in [0, 1]; adds the rays it cast to
/// `rays_cast` when given (a contact ray per point, then up to kOpenRays per point and
/// one more for every front hit, which is checked for a coincident back face). With
/// `shortcut` (the default), an element that no other polygon crosses
/// (core/raycast/face_crossings.h) is decided from kQuickPoints points when they agree
/// (see the file's comment); without, every element gets the full estimate (tests
/// compare the two).
double estimate_open_fraction(const Element& e, const Hierarchy& hierarchy, const RayScene& rays,
                              std::uint64_t seed, std::uint64_t* rays_cast = nullptr,
                              bool shortcut = true);

/// Rays a probe point is tested with (point_closed_in).
inline constexpr int kProbeOpenRays = 8;
/// Whether the point p with unit normal n sees nothing: each of kProbeOpenRays
/// cosine-distributed rays (stratified in azimuth, from stream `key`) first meets a
/// back face or a front at a point that is itself closed in by the leaves' rule (most
/// of kOpenRays rays from it meet back faces: the floor inside a cabinet without a
/// bottom). So a point on the floor under a box, on a wall behind or inside a cabinet
/// pushed against it, or on the top of a fitting flush with the ceiling. Such a point
/// sees only the inside of a solid, which is black: its irradiance is 0 (the reference
/// path tracer's too). A ray that leaves the scene makes the point open: a point that
/// looks mostly out of the Cornell box's open side still sees some of its light. Every ray, not most
/// as for the leaves' points: a point above a one-sided sheet (a lamp strip hanging
/// under a ceiling) sees the sheet's back in most directions but light past its edges
/// (in the cabin, 0.65 of the irradiance the lit ceiling gets). Adds the rays cast to
/// `rays_cast` when given.
bool point_closed_in(const Vec3& p, const Vec3& n, const Hierarchy& hierarchy, const RayScene& rays,
                     std::uint64_t key, std::uint64_t* rays_cast = nullptr);

}  // namespace hrad
