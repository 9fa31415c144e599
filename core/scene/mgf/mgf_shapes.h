// Tessellation of MGF's curved primitives (sph, cyl, cone, ring, torus) and of
// prisms into oriented planar polygons: triangles and quadrilaterals only, so that
// every piece is a face the element quadtree can split. All pieces are exactly
// planar (quads are isosceles trapezoids) and wound so that their right-hand normal
// is the primitive's surface normal (outward unless the spec's sign says inward).
//
// Watertight: each shape is an indexed mesh. Every point is computed once (the circle's
// directions once per shape, so the seam at 2 pi is the point at 0 and not its
// recomputation), and points that coincide (a sphere's pole, a cone's apex, a disk's
// centre, a torus touching its axis) are one point; a facet that loses a corner that
// way is a triangle. Neighbouring facets therefore share their edge's two points
// exactly: sph, torus and prism are closed (every edge in two facets, once each way);
// cyl and cone are open-ended (MGF: "truncated right cone (open-ended)", no caps), and
// ring is a flat annulus.
//
// `segments` (n) is the number of divisions of a full circle:
//   ring   n pieces (triangles when rmin = 0, else trapezoids);
//   cone   n pieces (triangles when one radius is 0); cyl is a cone with equal radii;
//   sph    n around x max(2, n/2) bands: 2n triangles at the poles, n(bands - 2) quads;
//   torus  n around the axis x n around the tube: n^2 quads;
//   prism  the two end faces (as given: SceneBuilder triangulates concave ones) plus
//          one quad per edge, independent of n.
// Preconditions (checked by the reader, which knows the file and line): n >= 3,
// radii and axes as the MGF spec requires (see each function).
#pragma once

#include "core/base/geometry.h"

#include <cstdint>
#include <span>
#include <vector>

namespace hrad {

/// Points, and polygons as indices into them (each with >= 3 distinct points).
struct ShapeMesh {
  std::vector<Vec3> points;
  std::vector<std::vector<std::uint32_t>> polygons;
};

/// Sphere about `c`; r < 0 points the normals inward. |r| > 0.
ShapeMesh tessellate_sphere(const Vec3& c, double r, int segments);

/// Open truncated cone from `a` (radius ra) to `b` (radius rb); a != b. The radii
/// share a sign (or one is 0, not both); negative radii point the normals inward.
ShapeMesh tessellate_cone(const Vec3& a, double ra, const Vec3& b, double rb, int segments);

/// Flat annulus (disk when rmin = 0) about `c`, facing `normal` (non-zero);
/// 0 <= rmin < rmax.
ShapeMesh tessellate_ring(const Vec3& c, const Vec3& normal, double rmin, double rmax,
                          int segments);

/// Torus about `c` in the plane perpendicular to `normal` (non-zero), spanning radii
/// rmin to rmax from the axis; |rmin| < |rmax|, same sign (rmin may be 0); negative
/// radii point the normals inward.
ShapeMesh tessellate_torus(const Vec3& c, const Vec3& normal, double rmin, double rmax,
                           int segments);

/// Closed right prism: `base` (>= 3 points, non-zero area) keeps its orientation; the
/// solid extends `length` against the base's normal (length < 0: along it, with every
/// face then pointing inward). length != 0.
ShapeMesh tessellate_prism(std::span<const Vec3> base, double length);

/// Unit vectors u, w with u x w = n / |n| (a right-handed frame around n).
void orthonormal_frame(const Vec3& n, Vec3& u, Vec3& w);

}  // namespace hrad
