// Form-factor estimators for diffuse surface-to-surface transport (no visibility).
//
// A form factor is unitless: the fraction of the energy leaving a diffuse (Lambertian)
// receiver element that arrives at the source polygon, equivalently (by reciprocity) the
// weight of the source's radiosity in the receiver's gathered irradiance. Every function
// here returns a value in [0, 1], never NaN, for any finite input, including degenerate
// polygons and points on or arbitrarily close to the source.
//
// Conventions:
//  * Polygons are planar (or nearly planar) and convex, given as vertex loops; their
//    front side is the side the right-hand-rule normal (Newell's, see vector_area) points
//    to. A source emits only from its front side: a point behind it gets 0.
//  * Normals passed explicitly (nx, ny) must be unit vectors.
//  * Nothing allocates: the polygons are only read, in order, once or twice.
#pragma once

#include <span>

#include "core/base/geometry.h"

namespace hrad {

/// Largest quadrature order (points per direction) polygon_to_polygon_ff uses; a
/// larger n is clamped to it.
inline constexpr int kMaxFormFactorOrder = 512;

/// Exact form factor from a differential area at `x` with unit normal `nx` to the
/// polygon `poly` (any number of vertices >= 3; convex), by Lambert's contour integral
///   F = (1/2pi) sum_edges gamma_i  nx . (R_{i+1} x R_i) / |R_{i+1} x R_i|,
/// R_i = v_i - x, gamma_i the angle between R_i and R_{i+1}: the projected solid angle
/// of the polygon seen from x, divided by pi.
/// * The part of the polygon behind x's tangent plane (nx . (p - x) <= 0) is clipped
///   away first, so a source crossing the receiver's horizon gets the value of its
///   visible part.
/// * x behind the source's plane, or on it (within 1e-12 of the distance scale: the
///   source is seen edge-on, including x on its edges or vertices), gives 0. Just in
///   front of the plane the value is the one-sided limit (1 over the interior, 1/2 over
///   an edge, ... for nx facing the source).
/// * A zero-area polygon gives 0.
/// Result clamped to [0, 1].
[[nodiscard]] double point_to_polygon_ff(const Vec3& x, const Vec3& nx, std::span<const Vec3> poly);

/// Bounded "disk" approximation of the point-to-area form factor from a point x (unit
/// normal nx) to a source of area `area_s` centred at y (unit normal ny), seen as a
/// coaxial-like disk:  A_s cos_x cos_y / (pi d^2 + A_s),  cosines clamped at 0.
/// Exact for a point on the axis of a facing disk; never exceeds 1 (unlike
/// A_s cos cos / (pi d^2)); 0 when x == y.
[[nodiscard]] double disk_ff(const Vec3& x, const Vec3& nx, const Vec3& y, const Vec3& ny,
                             double area_s);

/// Area-averaged form factor F_{recv->src} = (1/A_r) int_{A_r} F_{dA->src} dA, without
/// visibility, by an n x n Gauss-Legendre product rule on the receiver (a bilinear map
/// for a quad, a collapsed bilinear map for a triangle, a fan of such triangles from
/// vertex 0 for a convex polygon with more vertices), each term point_to_polygon_ff at
/// the quadrature point with the receiver's local normal. n is clamped to
/// [1, kMaxFormFactorOrder]. The error falls quickly with n for separated polygons and
/// like a low power of 1/n when they touch (shared edge) or nearly do; the solver uses
/// n = 1..3. A zero-area receiver gives 0. Result in [0, 1].
[[nodiscard]] double polygon_to_polygon_ff(std::span<const Vec3> recv, std::span<const Vec3> src,
                                           int n);

/// Gauss-Legendre rule on [0, 1] with n = nodes.size() points (weights.size() must be
/// the same): nodes ascending, weights summing to 1, exact for polynomials of degree
/// <= 2n - 1. n <= 4 uses closed forms; larger n Newton's iteration on P_n.
void gauss_legendre_01(std::span<double> nodes, std::span<double> weights);

}  // namespace hrad
