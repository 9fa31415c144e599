// Form-factor estimators against closed forms (Howell's catalogue of configuration
// factors, re-derived here as reference functions), reciprocity, closure, and the hard
// cases: points on or near the source, horizon clipping, slivers, degenerate polygons.
#include "core/transport/form_factor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace hrad {
namespace {

constexpr double kPi = std::numbers::pi;
using Poly = std::vector<Vec3>;

// ---------------------------------------------------------------------------------
// Reference closed forms (textbook formulas, written out independently of the code
// under test).

// Two parallel, directly opposed (coaxial) a x b rectangles a distance c apart.
double ref_parallel_rectangles(double a, double b, double c) {
  const double x = a / c;
  const double y = b / c;
  const double x2 = x * x;
  const double y2 = y * y;
  const double sx = std::sqrt(1 + x2);
  const double sy = std::sqrt(1 + y2);
  return 2 / (kPi * x * y) *
         (0.5 * std::log((1 + x2) * (1 + y2) / (1 + x2 + y2)) + x * sy * std::atan(x / sy) +
          y * sx * std::atan(y / sx) - x * std::atan(x) - y * std::atan(y));
}

// From an l x w rectangle to an l x h rectangle perpendicular to it, sharing the edge
// of length l.
double ref_perpendicular_rectangles(double l, double w, double h) {
  const double W = w / l;
  const double H = h / l;
  const double W2 = W * W;
  const double H2 = H * H;
  const double s = std::sqrt(W2 + H2);
  const double ln_a = std::log((1 + W2) * (1 + H2) / (1 + W2 + H2));
  const double ln_b = std::log(W2 * (1 + W2 + H2) / ((1 + W2) * (W2 + H2)));
  const double ln_c = std::log(H2 * (1 + W2 + H2) / ((1 + H2) * (W2 + H2)));
  return (W * std::atan(1 / W) + H * std::atan(1 / H) - s * std::atan(1 / s) +
          0.25 * (ln_a + W2 * ln_b + H2 * ln_c)) /
         (kPi * W);
}

// Differential area facing an a x b rectangle, on the rectangle's normal through one
// corner, at distance c.
double ref_point_over_corner(double a, double b, double c) {
  const double x = a / c;
  const double y = b / c;
  const double sx = std::sqrt(1 + x * x);
  const double sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * kPi);
}

// Differential area at the origin with normal +z; a rectangle in the plane y = d
// covering x in [0, a], z in [0, b], facing the origin (one of its edges lies in the
// point's tangent plane).
double ref_point_to_perpendicular_rectangle(double a, double b, double d) {
  const double s = std::sqrt(b * b + d * d);
  return (std::atan(a / d) - d / s * std::atan(a / s)) / (2 * kPi);
}

// Differential area on the axis of a regular N-gon of circumradius r at distance h,
// facing it: every edge contributes gamma * r^2 sin(2pi/N) / |R_i x R_{i+1}|.
double ref_point_on_axis_of_ngon(int sides, double r, double h) {
  const double t = 2 * kPi / sides;
  const double cross = std::sqrt(4 * h * h * r * r * std::pow(std::sin(t / 2), 2) +
                                 std::pow(r * r * std::sin(t), 2));
  const double gamma = std::atan2(cross, r * r * std::cos(t) + h * h);
  return sides * gamma * r * r * std::sin(t) / (cross * 2 * kPi);
}

// ---------------------------------------------------------------------------------
// Geometry helpers.

// Axis-aligned rectangle [x0,x1] x [y0,y1] at height z, normal +z (up) or -z.
Poly rect_z(double x0, double x1, double y0, double y1, double z, bool up) {
  Poly p = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  if (!up) std::reverse(p.begin(), p.end());
  return p;
}

// Regular N-gon of circumradius r centred on the z axis at height z.
Poly ngon_z(int sides, double r, double z, bool up) {
  Poly p;
  for (int i = 0; i < sides; ++i) {
    const double phi = 2 * kPi * i / sides * (up ? 1 : -1);
    p.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  return p;
}

double area(const Poly& p) { return polygon_area(p); }

// Unclipped contour integral (no tangent-plane clipping), to show what clipping fixes.
double naive_contour(const Vec3& x, const Vec3& n, const Poly& poly) {
  double sum = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec3 a = poly[i] - x;
    const Vec3 b = poly[(i + 1) % poly.size()] - x;
    const Vec3 c = b.cross(a);
    sum += std::atan2(c.norm(), a.dot(b)) * n.dot(c) / c.norm();
  }
  return sum / (2 * kPi);
}

// (1/pi) int cos_x cos_y / r^2 dA over a triangle or quad by a product Gauss rule on
// the bilinear map: an independent check of the contour integral, valid when the whole
// source is in front of x's tangent plane and x in front of the source.
double kernel_integral(const Vec3& x, const Vec3& nx, const Poly& src, int n) {
  std::vector<double> u(n), w(n);
  gauss_legendre_01(u, w);
  const Vec3 p0 = src[0], p1 = src[1], p2 = src[2], p3 = src.size() == 4 ? src[3] : src[2];
  const Vec3 ns = polygon_normal(src);
  double sum = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double s = u[i], t = u[j];
      const Vec3 y = (1 - s) * (1 - t) * p0 + s * (1 - t) * p1 + s * t * p2 + (1 - s) * t * p3;
      const Vec3 du = (1 - t) * (p1 - p0) + t * (p2 - p3);
      const Vec3 dv = (1 - s) * (p3 - p0) + s * (p2 - p1);
      const Vec3 r = y - x;
      const double d2 = r.squaredNorm();
      sum += w[i] * w[j] * du.cross(dv).norm() * nx.dot(r) * (-ns.dot(r)) / (d2 * d2);
    }
  }
  return sum / kPi;
}

bool in_unit_interval(double f) { return std::isfinite(f) && f >= 0 && f <= 1; }

// ---------------------------------------------------------------------------------
// The reference functions themselves reproduce the published numbers (tolerance 1e-9,
// the precision those numbers are given to).

TEST(FormFactorReference, ClosedFormsMatchPublishedValues) {
  EXPECT_NEAR(ref_parallel_rectangles(1, 1, 1), 0.1998248957, 1e-9);
  EXPECT_NEAR(ref_parallel_rectangles(1, 1, 0.5), 0.4152532836, 1e-9);
  EXPECT_NEAR(ref_parallel_rectangles(1, 1, 0.1), 0.8269945224, 1e-9);
  EXPECT_NEAR(ref_parallel_rectangles(1, 1, 0.01), 0.98042, 1e-5);
  EXPECT_NEAR(ref_perpendicular_rectangles(1, 1, 1), 0.2000437761, 1e-9);
  EXPECT_NEAR(ref_perpendicular_rectangles(1, 0.1, 0.1), 0.2818878068, 1e-9);
  // Closure of the unit cube's floor: 0.1998249 + 4 * 0.2000438 = 1.
  EXPECT_NEAR(ref_parallel_rectangles(1, 1, 1) + 4 * ref_perpendicular_rectangles(1, 1, 1), 1,
              1e-12);
  // Corner formula: four corner rectangles of a square at vanishing height fill the
  // hemisphere; at height h = r the N-gon value tends to the disk's r^2/(r^2+h^2).
  EXPECT_NEAR(4 * ref_point_over_corner(0.5, 0.5, 1e-9), 1, 1e-8);
  EXPECT_NEAR(ref_point_on_axis_of_ngon(100000, 1, 1), 0.5, 1e-9);
}

// ---------------------------------------------------------------------------------
// Gauss-Legendre rule.

TEST(FormFactorGauss, ExactForPolynomialsUpToDegree2nMinus1) {
  // Tolerance 1e-13 relative: the rule is exact up to round-off for degree <= 2n-1.
  for (int n : {1, 2, 3, 4, 5, 7, 12, 33, 64, 200}) {
    std::vector<double> x(n), w(n);
    gauss_legendre_01(x, w);
    double wsum = 0;
    for (int i = 0; i < n; ++i) {
      EXPECT_GT(w[i], 0) << "n=" << n;
      EXPECT_GT(x[i], 0) << "n=" << n;
      EXPECT_LT(x[i], 1) << "n=" << n;
      if (i > 0) {
        EXPECT_LT(x[i - 1], x[i]) << "n=" << n;
      }
      wsum += w[i];
    }
    EXPECT_NEAR(wsum, 1, 1e-13) << "n=" << n;
    for (int d = 1; d <= std::min(2 * n - 1, 60); ++d) {
      double q = 0;
      for (int i = 0; i < n; ++i) q += w[i] * std::pow(x[i], d);
      EXPECT_NEAR(q * (d + 1), 1, 1e-13) << "n=" << n << " degree " << d;
    }
    // Not exact one degree higher (proves the check above can fail): x^(2n) is
    // under-integrated by a clearly visible amount for small n.
    if (n <= 4) {
      double q = 0;
      for (int i = 0; i < n; ++i) q += w[i] * std::pow(x[i], 2 * n);
      EXPECT_GT(std::abs(q * (2 * n + 1) - 1), 1e-4) << "n=" << n;
    }
  }
}

// ---------------------------------------------------------------------------------
// Point to polygon.

TEST(FormFactorPoint, OnAxisOfSquareMatchesCornerFormula) {
  // Unit square emitter at z = 0 facing up; receiver above its centre facing down.
  // Tolerance 1e-13 absolute (both sides are closed forms evaluated in double).
  const Poly sq = rect_z(0, 1, 0, 1, 0, true);
  for (double h : {10.0, 1.0, 0.1, 0.01, 0.001, 1e-6, 1e-9}) {
    const double f = point_to_polygon_ff(Vec3(0.5, 0.5, h), Vec3(0, 0, -1), sq);
    EXPECT_NEAR(f, 4 * ref_point_over_corner(0.5, 0.5, h), 1e-13) << "h=" << h;
    EXPECT_TRUE(in_unit_interval(f));
  }
}

TEST(FormFactorPoint, OffAxisMatchesSumOfCornerRectangles) {
  // Point above (px, py) inside a 2 x 1 rectangle: the four corner rectangles around the
  // foot of the normal. Tolerance 1e-13 absolute.
  const Poly r = rect_z(0, 2, 0, 1, 0, true);
  const double px = 0.3, py = 0.8;
  for (double h : {2.0, 0.5, 0.05}) {
    const double ref = ref_point_over_corner(px, py, h) + ref_point_over_corner(2 - px, py, h) +
                       ref_point_over_corner(px, 1 - py, h) +
                       ref_point_over_corner(2 - px, 1 - py, h);
    EXPECT_NEAR(point_to_polygon_ff(Vec3(px, py, h), Vec3(0, 0, -1), r), ref, 1e-13);
  }
  // Foot of the normal outside the rectangle: differences of corner rectangles.
  // Point above (3, 0.5): rectangles [0,3] minus [2,3] (each split at y = 0.5).
  const double h = 0.7;
  const double ref = 2 * (ref_point_over_corner(3, 0.5, h) - ref_point_over_corner(1, 0.5, h));
  EXPECT_NEAR(point_to_polygon_ff(Vec3(3, 0.5, h), Vec3(0, 0, -1), r), ref, 1e-13);
}

TEST(FormFactorPoint, RegularPolygonAndDisk) {
  // Exact N-gon value (tolerance 1e-13); as N grows the inscribed N-gon tends to the
  // disk, F = r^2 / (r^2 + h^2) = 0.5 at r = h, with an error ~ (2pi/N)^2/12 that the
  // tolerance states for N = 4096 (1e-6).
  for (int sides : {3, 4, 8, 64, 4096}) {
    const Poly p = ngon_z(sides, 1, 0, true);
    const double f = point_to_polygon_ff(Vec3(0, 0, 1), Vec3(0, 0, -1), p);
    EXPECT_NEAR(f, ref_point_on_axis_of_ngon(sides, 1, 1), 1e-13) << sides;
  }
  const Poly disk = ngon_z(4096, 1, 0, true);
  EXPECT_NEAR(point_to_polygon_ff(Vec3(0, 0, 1), Vec3(0, 0, -1), disk), 0.5, 1e-6);
}

TEST(FormFactorPoint, MatchesDirectKernelIntegration) {
  // Random triangles and quads wholly in front of a random receiver point (and facing
  // it), compared with a 60 x 60 Gauss product rule of the kernel cos cos / (pi r^2),
  // which converges exponentially for these separated configurations (measured
  // differences <= 3e-16). Tolerance 1e-13 absolute.
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> U(-1, 1);
  int checked = 0;
  while (checked < 40) {
    const Vec3 x(U(rng), U(rng), U(rng));
    const Vec3 nx = Vec3(U(rng), U(rng), U(rng)).normalized();
    // Source: a parallelogram or triangle about 1 wide, centred ~2.5 away along a
    // direction in x's front hemisphere.
    Vec3 dir = Vec3(U(rng), U(rng), U(rng)).normalized();
    if (dir.dot(nx) < 0) dir = -dir;
    const Vec3 c = x + 2.5 * dir;
    const Vec3 e1(U(rng), U(rng), U(rng));
    const Vec3 e2(U(rng), U(rng), U(rng));
    Poly src = checked % 2 ? Poly{c - e1 - e2, c + e1 - e2, c + e1 + e2, c - e1 + e2}
                           : Poly{c - e1, c + e1, c + e2};
    if (polygon_area(src) < 0.2) continue;
    if (polygon_normal(src).dot(x - c) < 0) std::reverse(src.begin(), src.end());
    bool in_front = true;
    for (const Vec3& v : src) in_front = in_front && nx.dot(v - x) > 0.05;
    if (!in_front || polygon_normal(src).dot(x - src[0]) < 0.05) continue;
    const double f = point_to_polygon_ff(x, nx, src);
    EXPECT_NEAR(f, kernel_integral(x, nx, src, 60), 1e-13) << "case " << checked;
    // Independent of the start vertex.
    Poly rot = src;
    std::rotate(rot.begin(), rot.begin() + 1, rot.end());
    EXPECT_NEAR(point_to_polygon_ff(x, nx, rot), f, 1e-15);
    ++checked;
  }
}

TEST(FormFactorPoint, BackFacingSourceGivesZero) {
  const Poly up = rect_z(0, 1, 0, 1, 0, true);
  const Poly down = rect_z(0, 1, 0, 1, 0, false);
  const Vec3 x(0.5, 0.5, 1);
  EXPECT_GT(point_to_polygon_ff(x, Vec3(0, 0, -1), up), 0.1);
  EXPECT_EQ(point_to_polygon_ff(x, Vec3(0, 0, -1), down), 0.0);
  // Receiver facing away from the source.
  EXPECT_EQ(point_to_polygon_ff(x, Vec3(0, 0, 1), up), 0.0);
}

TEST(FormFactorPoint, PolygonBehindTangentPlaneIsClipped) {
  // Receiver at the origin facing +z; a 2 x 2 wall in the plane y = 1 facing it, half
  // below the horizon z = 0. Only the upper half counts: two corner rectangles of the
  // perpendicular-rectangle closed form. Tolerance 1e-14 absolute.
  const Vec3 x(0, 0, 0), n(0, 0, 1);
  const Poly wall = {{-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}};
  const Poly upper = {{-1, 1, 0}, {1, 1, 0}, {1, 1, 1}, {-1, 1, 1}};
  const double ref = 2 * ref_point_to_perpendicular_rectangle(1, 1, 1);
  EXPECT_NEAR(point_to_polygon_ff(x, n, wall), ref, 1e-14);
  EXPECT_NEAR(point_to_polygon_ff(x, n, upper), ref, 1e-14);
  // Without clipping, the contour integral of the symmetric wall cancels to 0 instead.
  EXPECT_NEAR(naive_contour(x, n, wall), 0, 1e-14);
  EXPECT_GT(ref, 0.1);

  // Tilted receiver cutting a triangle diagonally: compare with the hand-clipped part.
  // Receiver normal (0, 0.6, 0.8): the horizon plane 0.6 y + 0.8 z = 0.
  const Vec3 n2(0, 0.6, 0.8);
  const Poly tri = {{-1, 2, -2}, {1, 2, -2}, {0, 2, 1}};  // in the plane y = 2, facing -y
  ASSERT_LT(polygon_normal(tri).y(), 0);
  // Edges cross z = -1.5 (where 0.6 * 2 + 0.8 z = 0): on the two slanted edges.
  const double t = (-1.5 - (-2)) / 3.0;  // fraction from the bottom vertices to the apex
  const Poly clipped = {{-1 + t, 2, -1.5}, {1 - t, 2, -1.5}, {0, 2, 1}};
  const double f = point_to_polygon_ff(x, n2, tri);
  EXPECT_NEAR(f, point_to_polygon_ff(x, n2, clipped), 1e-14);
  EXPECT_NEAR(f, naive_contour(x, n2, clipped), 1e-14);
  EXPECT_GT(std::abs(naive_contour(x, n2, tri) - f), 1e-3);

  // A polygon wholly behind the tangent plane gives 0.
  EXPECT_EQ(point_to_polygon_ff(x, Vec3(0, 0, -1), upper), 0.0);
}

TEST(FormFactorPoint, NearSourcePlaneApproachesOneSidedLimits) {
  // Just in front of the unit square (height eps), facing it: 1 over the interior, 1/2
  // over an edge, 1/4 over a corner. With the receiver tilted by theta the source fills
  // the whole lower hemisphere, and the horizon clip leaves (1 + cos theta) / 2.
  // The limits are reached to O(eps) (measured <= 1.2e-9): tolerance 1e-8.
  const Poly sq = rect_z(0, 1, 0, 1, 0, true);
  const double eps = 1e-9;
  const Vec3 down(0, 0, -1);
  EXPECT_NEAR(point_to_polygon_ff(Vec3(0.5, 0.5, eps), down, sq), 1, 1e-8);
  EXPECT_NEAR(point_to_polygon_ff(Vec3(0.5, 0, eps), down, sq), 0.5, 1e-8);
  EXPECT_NEAR(point_to_polygon_ff(Vec3(1, 0.3, eps), down, sq), 0.5, 1e-8);
  EXPECT_NEAR(point_to_polygon_ff(Vec3(0, 0, eps), down, sq), 0.25, 1e-8);
  EXPECT_NEAR(point_to_polygon_ff(Vec3(1, 1, eps), down, sq), 0.25, 1e-8);
  for (double theta : {0.3, 1.0, kPi / 2, 2.0}) {
    const Vec3 n(std::sin(theta), 0, -std::cos(theta));
    EXPECT_NEAR(point_to_polygon_ff(Vec3(0.5, 0.5, eps), n, sq), (1 + std::cos(theta)) / 2, 1e-8)
        << theta;
  }
}

TEST(FormFactorPoint, OnSourcePlaneIsZero) {
  // A point in the source's plane sees it edge-on: exactly 0, whether it is inside,
  // on an edge, at a vertex or outside, and whatever its normal.
  const Poly sq = rect_z(0, 1, 0, 1, 0, true);
  for (const Vec3& x : {Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0), Vec3(0, 0, 0), Vec3(1, 1, 0),
                        Vec3(2, 0.5, 0), Vec3(0.25, 0, 0)}) {
    for (const Vec3& n : {Vec3(0, 0, -1), Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0.6, 0, -0.8)}) {
      EXPECT_EQ(point_to_polygon_ff(x, n, sq), 0.0) << x.transpose() << " / " << n.transpose();
    }
  }
}

TEST(FormFactorPoint, SliversAndDegeneratePolygons) {
  const Vec3 x(0.5, 0.3, 1);
  const Vec3 down(0, 0, -1);
  // Zero-area sources: collinear, repeated vertices, fewer than 3 vertices.
  EXPECT_EQ(point_to_polygon_ff(x, down, Poly{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}), 0.0);
  EXPECT_EQ(point_to_polygon_ff(x, down, Poly{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}), 0.0);
  EXPECT_EQ(point_to_polygon_ff(x, down, Poly{{0, 0, 0}, {1, 0, 0}}), 0.0);
  // A sliver triangle of height eta: its form factor scales linearly with eta (the
  // sliver is a line of sources); compare eta = 1e-10 against eta = 1e-6 scaled
  // (measured 1.2e-8 apart): relative tolerance 1e-6.
  auto sliver = [](double eta) { return Poly{{0, 0, 0}, {1, 0, 0}, {0.5, eta, 0}}; };
  const double f_small = point_to_polygon_ff(x, down, sliver(1e-10));
  const double f_ref = point_to_polygon_ff(x, down, sliver(1e-6));
  EXPECT_TRUE(in_unit_interval(f_small));
  EXPECT_GT(f_ref, 0);
  EXPECT_NEAR(f_small / f_ref * 1e4, 1, 1e-6);
  // Points very close to a sliver: over its long edge or just outside it, at most the
  // edge limit 1/2; 1e-14 above its interior (1e-10 wide) it fills the hemisphere
  // (measured 1 - 2e-8; tolerance 1e-6).
  for (double h : {1e-3, 1e-8, 1e-11, 1e-14}) {
    for (const Vec3& p : {Vec3(0.5, 0, h), Vec3(0.5, -1e-11, h), Vec3(0, 0, h)}) {
      const double f = point_to_polygon_ff(p, down, sliver(1e-10));
      EXPECT_TRUE(in_unit_interval(f)) << f;
      EXPECT_LE(f, 0.5 + 1e-9);
    }
  }
  EXPECT_NEAR(point_to_polygon_ff(Vec3(0.5, 5e-11, 1e-14), down, sliver(1e-10)), 1, 1e-6);
}

TEST(FormFactorPoint, RandomNearContactStressStaysInUnitInterval) {
  // Points on, near and far from a unit square (near edges and vertices especially),
  // with arbitrary normals including tangent ones; no NaN, never outside [0, 1].
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  const Poly sq = rect_z(0, 1, 0, 1, 0, true);
  const Poly tri = {{0, 0, 0}, {1, 0, 0}, {0.3, 1e-7, 0}};
  const double coords[] = {0, 1, 0.5, 1e-15, 1 - 1e-15, -1e-12};
  const double heights[] = {0, 1e-300, 1e-16, 1e-12, 1e-9, 1e-5, 1e-2, -1e-12};
  int count = 0;
  for (double cx : coords) {
    for (double cy : coords) {
      for (double h : heights) {
        for (int k = 0; k < 6; ++k) {
          Vec3 n = Vec3(U(rng), U(rng), U(rng)).normalized();
          if (k == 0) n = Vec3(0, 0, -1);
          if (k == 1) n = Vec3(1, 0, 0);
          const Vec3 x(cx, cy, h);
          for (const Poly* p : {&sq, &tri}) {
            const double f = point_to_polygon_ff(x, n, *p);
            ASSERT_TRUE(in_unit_interval(f)) << x.transpose() << " n " << n.transpose();
            ++count;
          }
        }
      }
    }
  }
  EXPECT_EQ(count, 6 * 6 * 8 * 6 * 2);
}

// ---------------------------------------------------------------------------------
// Polygon to polygon.

TEST(FormFactorPolygon, ParallelUnitSquares) {
  // Receiver z = 0 facing up, source at z = c facing down. The integrand is analytic on
  // the receiver, so Gauss converges exponentially: measured error at distance 1 is
  // 4e-2 (n=1), 1.4e-3 (2), 1.9e-5 (3), 8e-12 (8); at distance 0.5, 2e-12 at n = 12.
  // Tolerance 1e-9 against the published 10-digit values, 1e-10 against the closed form.
  const Poly recv = rect_z(0, 1, 0, 1, 0, true);
  const double f1 = polygon_to_polygon_ff(recv, rect_z(0, 1, 0, 1, 1, false), 8);
  const double f05 = polygon_to_polygon_ff(recv, rect_z(0, 1, 0, 1, 0.5, false), 12);
  EXPECT_NEAR(f1, 0.1998248957, 1e-9);
  EXPECT_NEAR(f1, ref_parallel_rectangles(1, 1, 1), 1e-10);
  EXPECT_NEAR(f05, 0.4152532836, 1e-9);
  EXPECT_NEAR(f05, ref_parallel_rectangles(1, 1, 0.5), 1e-10);
  // Cross-check on 2 x 0.5 rectangles at other distances (n = 24, tolerance 1e-10).
  for (double c : {0.3, 2.0, 7.0}) {
    const Poly r = rect_z(0, 2, 0, 0.5, 0, true);
    const Poly s = rect_z(0, 2, 0, 0.5, c, false);
    EXPECT_NEAR(polygon_to_polygon_ff(r, s, 24), ref_parallel_rectangles(2, 0.5, c), 1e-10) << c;
  }
}

TEST(FormFactorPolygon, ParallelSquaresAtDistanceTenthConverges) {
  // Distance 0.1: F varies over a boundary layer ~0.1 wide near the receiver's edges.
  // The error must fall as n grows: measured 8.2e-2 (n=2), 3.5e-3 (4), 3.0e-6 (8),
  // 6.5e-8 (16), 2.7e-14 (32); each step at least 10x here. Tolerance at n = 32: 1e-9
  // against the published value, 1e-12 against the closed form.
  const Poly recv = rect_z(0, 1, 0, 1, 0, true);
  const Poly src = rect_z(0, 1, 0, 1, 0.1, false);
  const double exact = ref_parallel_rectangles(1, 1, 0.1);
  double prev = 1;
  for (int n : {2, 4, 8, 16, 32}) {
    const double err = std::abs(polygon_to_polygon_ff(recv, src, n) - exact);
    EXPECT_LT(err, prev / 10) << "n=" << n;
    prev = err;
  }
  EXPECT_NEAR(polygon_to_polygon_ff(recv, src, 32), 0.8269945224, 1e-9);
  EXPECT_NEAR(polygon_to_polygon_ff(recv, src, 32), exact, 1e-12);
}

TEST(FormFactorPolygon, ParallelSquaresAtDistanceHundredth) {
  // Near contact (0.01): boundary layer 0.01 wide; closed form 0.9804166029. Small n
  // overestimates (no point falls in the layer): measured error 1.9e-2 (n=1),
  // 7.5e-3 (8), 2.2e-4 (16), 4.0e-6 (32), 3.2e-10 (64), 8e-15 (128).
  // Tolerances: 1e-3 at n = 16, 1e-5 at n = 32, 1e-9 at n = 64; all values in [0, 1].
  const Poly recv = rect_z(0, 1, 0, 1, 0, true);
  const Poly src = rect_z(0, 1, 0, 1, 0.01, false);
  const double exact = ref_parallel_rectangles(1, 1, 0.01);
  for (int n : {1, 2, 3, 8, 16, 32, 64, 128}) {
    const double f = polygon_to_polygon_ff(recv, src, n);
    EXPECT_TRUE(in_unit_interval(f)) << n;
  }
  EXPECT_NEAR(polygon_to_polygon_ff(recv, src, 16), exact, 1e-3);
  EXPECT_NEAR(polygon_to_polygon_ff(recv, src, 32), exact, 1e-5);
  EXPECT_NEAR(polygon_to_polygon_ff(recv, src, 64), exact, 1e-9);
}

TEST(FormFactorPolygon, PerpendicularRectanglesSharingAnEdge) {
  // Floor [0,w] x [0,l] at z = 0 facing up (receiver); wall x = 0, y in [0,l],
  // z in [0,h] facing +x (source). The point value is not smooth at the shared edge,
  // and the error falls algebraically once the rule resolves the aspect ratio:
  // measured for the unit squares 3.6e-4 (n=2), 3.8e-7 (4), <3e-11 (8, the published
  // value's rounding); for the 1 x 0.1 strips 2.7e-3 (4), 1.5e-4 (8), 1.1e-5 (16),
  // 7.2e-7 (32), 4.6e-8 (64) (~n^-4); for the other two ~1.2e-8 at n = 64.
  // Tolerance at n = 64: 1e-9 for the unit squares, 1e-7 for the others.
  auto floor = [](double w, double l) { return rect_z(0, w, 0, l, 0, true); };
  auto wall = [](double l, double h) { return Poly{{0, 0, 0}, {0, l, 0}, {0, l, h}, {0, 0, h}}; };
  ASSERT_GT(polygon_normal(wall(1, 1)).x(), 0);
  EXPECT_NEAR(polygon_to_polygon_ff(floor(1, 1), wall(1, 1), 64), 0.2000437761, 1e-9);
  // l = 1, w = h = 0.1: F from one 1 x 0.1 strip to the adjacent perpendicular strip.
  EXPECT_NEAR(polygon_to_polygon_ff(floor(0.1, 1), wall(1, 0.1), 64), 0.2818878068, 1e-7);
  double prev = 1;
  for (int n : {4, 8, 16, 32, 64}) {
    const double err =
        std::abs(polygon_to_polygon_ff(floor(0.1, 1), wall(1, 0.1), n) - 0.2818878068);
    EXPECT_LT(err, prev / 8) << "n=" << n;
    prev = err;
  }
  // Unequal widths against the reference function.
  EXPECT_NEAR(polygon_to_polygon_ff(floor(0.5, 1), wall(1, 2), 64),
              ref_perpendicular_rectangles(1, 0.5, 2), 1e-7);
  EXPECT_NEAR(polygon_to_polygon_ff(floor(2, 1), wall(1, 0.3), 64),
              ref_perpendicular_rectangles(1, 2, 0.3), 1e-7);
}

TEST(FormFactorPolygon, UnitCubeFloorRowSumsToOne) {
  // Floor of the unit cube to the ceiling and the four walls (all facing inwards):
  // closure sum = 1. Closure holds point by point (the five faces' projected solid
  // angles tile the hemisphere), so any n gives 1 up to round-off: tolerance 1e-12
  // (the brief asks 1e-4) at n = 2 and n = 16. The individual terms must match the
  // closed forms: measured 1.4e-3 / 3.6e-4 at n = 2, < 1e-11 at n = 16; tolerance 2e-3
  // at n = 2, 1e-10 at n = 16.
  const Poly floor = rect_z(0, 1, 0, 1, 0, true);
  const std::vector<Poly> others = {
      rect_z(0, 1, 0, 1, 1, false),
      {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}},  // x = 0, facing +x
      {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}},  // x = 1, facing -x
      {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}},  // y = 0, facing +y
      {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},  // y = 1, facing -y
  };
  const Vec3 centre(0.5, 0.5, 0.5);
  for (int n : {2, 16}) {
    double sum = 0;
    for (std::size_t k = 0; k < others.size(); ++k) {
      const Poly& p = others[k];
      ASSERT_GT(polygon_normal(p).dot(centre - p[0]), 0) << "face must point inwards";
      const double f = polygon_to_polygon_ff(floor, p, n);
      const double ref =
          k == 0 ? ref_parallel_rectangles(1, 1, 1) : ref_perpendicular_rectangles(1, 1, 1);
      EXPECT_NEAR(f, ref, n == 2 ? 2e-3 : 1e-10) << "face " << k << " n=" << n;
      sum += f;
    }
    EXPECT_NEAR(sum, 1, 1e-12) << "n=" << n;
  }
  // The floor sees nothing of itself.
  EXPECT_EQ(polygon_to_polygon_ff(floor, floor, 4), 0.0);
}

TEST(FormFactorPolygon, CoaxialDisks) {
  // Disks r1 = r2 = h: F = (3 - sqrt 5) / 2. Disks are equal-area regular 256-gons (an
  // inscribed 256-gon's O(1/N^2) area deficit would leave an error of 1.2e-5); the
  // receiver is a fan of 254 triangles with an n x n rule each. Measured error 6.9e-4
  // (n=2), 5.5e-5 (3), 5.5e-6 (4), 4.3e-8 (6). Tolerance 1e-6 at n = 6.
  const int sides = 256;
  const double t = 2 * kPi / sides;
  const double r = std::sqrt(2 * kPi / (sides * std::sin(t)));  // area pi
  const Poly recv = ngon_z(sides, r, 0, true);
  const Poly src = ngon_z(sides, r, 1, false);
  ASSERT_NEAR(area(recv), kPi, 1e-12);
  EXPECT_NEAR(polygon_to_polygon_ff(recv, src, 6), (3 - std::sqrt(5.0)) / 2, 1e-6);
}

TEST(FormFactorPolygon, TriangleAndPolygonReceiversAgreeWithQuads) {
  // Splitting a receiver must not change A * F (additivity). Separated configuration,
  // n = 12 (measured 1e-15 and 2e-13 relative); tolerance 1e-11 relative.
  const Poly src = rect_z(-0.3, 1.2, 0.1, 0.9, 1.3, false);
  const Poly sq = rect_z(0, 1, 0, 1, 0, true);
  const Poly t1 = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  const Poly t2 = {{0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const double whole = polygon_to_polygon_ff(sq, src, 12);
  const double halves =
      0.5 * polygon_to_polygon_ff(t1, src, 12) + 0.5 * polygon_to_polygon_ff(t2, src, 12);
  EXPECT_NEAR(halves / whole, 1, 1e-11);
  // A regular hexagon (fan of 4 triangles) against the same hexagon as two quads.
  const Poly hex = ngon_z(6, 1, 0, true);
  const Poly q1 = {hex[0], hex[1], hex[2], hex[3]};
  const Poly q2 = {hex[3], hex[4], hex[5], hex[0]};
  const double f_hex = polygon_to_polygon_ff(hex, src, 12);
  const double f_quads = (area(q1) * polygon_to_polygon_ff(q1, src, 12) +
                          area(q2) * polygon_to_polygon_ff(q2, src, 12)) /
                         area(hex);
  EXPECT_NEAR(f_quads / f_hex, 1, 1e-11);
}

TEST(FormFactorPolygon, Reciprocity) {
  // A_i F_ij = A_j F_ji for a triangle and a quad at an angle (non-symmetric pairs).
  struct Pair {
    Poly a, b;
    int n;
    double rel_tol;
  };
  const Poly tri = {{0, 0, 0}, {1.5, 0.2, 0}, {0.4, 1.1, 0}};  // facing +z
  // Planar parallelogram o, o + e1, o + e1 + e2, o + e2, turned to face the triangle.
  auto quad = [&](const Vec3& o, const Vec3& e1, const Vec3& e2) {
    Poly q = {o, o + e1, o + e1 + e2, o + e2};
    if (polygon_normal(q).dot(polygon_centroid(tri) - polygon_centroid(q)) < 0)
      std::reverse(q.begin(), q.end());
    return q;
  };
  const std::vector<Pair> pairs = {
      // Tilted quad above the triangle, wholly in front of it: separated, exponential
      // convergence (measured 1.8e-6 at n = 4, 2e-11 at 8, 1e-15 at 12). n = 12,
      // relative 1e-12.
      {tri, quad({0.2, 0.1, 1.2}, {1.6, 0.1, 0.4}, {-0.3, 1.3, 0.9}), 12, 1e-12},
      // Quad standing on the triangle's plane beside it (touching its plane, not the
      // triangle): measured 1.6e-6 at n = 12, 7e-10 at 24, 2e-12 at 32. n = 32,
      // relative 1e-10.
      {tri, quad({2.0, -0.5, 0}, {-0.5, 2.0, 0}, {0.1, 0.1, 1.0}), 32, 1e-10},
      // Quad crossing the triangle's plane (without meeting the triangle): the receiver's
      // horizon clips it, so the integrand has kinks and convergence is slow and
      // irregular (measured 2.5e-3 at n = 12, 1.6e-5 at 32, 3.8e-6 at 64, 2.8e-8 at
      // 128). n = 64, relative 1e-5.
      {tri, quad({1.8, -0.5, -0.7}, {-0.6, 2.1, 0.3}, {0.1, 0, 1.7}), 64, 1e-5},
  };
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Pair& p = pairs[k];
    const double ab = area(p.a) * polygon_to_polygon_ff(p.a, p.b, p.n);
    const double ba = area(p.b) * polygon_to_polygon_ff(p.b, p.a, p.n);
    EXPECT_GT(ab, 1e-3) << "pair " << k << " must exchange energy";
    EXPECT_NEAR(ab / ba, 1, p.rel_tol) << "pair " << k;
  }
}

TEST(FormFactorPolygon, DegenerateAndNearContactInputsStayBounded) {
  const Poly sq = rect_z(0, 1, 0, 1, 0, true);
  const Poly zero = {{0, 0, 1}, {1, 0, 1}, {2, 0, 1}};
  EXPECT_EQ(polygon_to_polygon_ff(zero, sq, 3), 0.0);
  EXPECT_EQ(polygon_to_polygon_ff(sq, zero, 3), 0.0);
  // Sliver receiver and source close to the square.
  const Poly sliver_up = {{0.1, 0.5, 1e-6}, {0.9, 0.5, 1e-6}, {0.5, 0.5 + 1e-12, 1e-6}};
  const Poly sliver_dn = {{0.1, 0.5, 1e-6}, {0.5, 0.5 + 1e-12, 1e-6}, {0.9, 0.5, 1e-6}};
  for (int n : {1, 2, 3, 16}) {
    EXPECT_TRUE(in_unit_interval(polygon_to_polygon_ff(sliver_dn, sq, n)));
    EXPECT_TRUE(in_unit_interval(polygon_to_polygon_ff(sq, sliver_up, n)));
  }
  // The sliver 1e-6 above the square's interior, facing it, receives nearly everything.
  EXPECT_NEAR(polygon_to_polygon_ff(sliver_dn, sq, 3), 1, 1e-5);
  // Coplanar neighbours exchange nothing.
  EXPECT_EQ(polygon_to_polygon_ff(sq, rect_z(1, 2, 0, 1, 0, true), 3), 0.0);
  // n outside [1, kMax] is clamped, not rejected.
  const Poly top = rect_z(0, 1, 0, 1, 1, false);
  EXPECT_EQ(polygon_to_polygon_ff(sq, top, 0), polygon_to_polygon_ff(sq, top, 1));
  EXPECT_EQ(polygon_to_polygon_ff(sq, top, -5), polygon_to_polygon_ff(sq, top, 1));
}

// ---------------------------------------------------------------------------------
// Disk approximation.

TEST(FormFactorDisk, ExactOnAxisOfFacingDisk) {
  // A_s / (pi h^2 + A_s) = r^2 / (r^2 + h^2): 0.5 at r = h. Tolerance 1e-15.
  EXPECT_NEAR(disk_ff(Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, -1), kPi), 0.5,
              1e-15);
}

TEST(FormFactorDisk, NeverExceedsOneAndCullsBackFaces) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 x(U(rng), U(rng), U(rng));
    const double scale = std::pow(10.0, -12 + 12 * (U(rng) + 1) / 2);
    const Vec3 y = x + scale * Vec3(U(rng), U(rng), U(rng));
    const Vec3 nx = Vec3(U(rng), U(rng), U(rng)).normalized();
    const Vec3 ny = Vec3(U(rng), U(rng), U(rng)).normalized();
    const double a = std::pow(10.0, 6 * U(rng));
    const double f = disk_ff(x, nx, y, ny, a);
    ASSERT_TRUE(in_unit_interval(f)) << f;
    if (nx.dot(y - x) <= 0 || ny.dot(x - y) <= 0) {
      ASSERT_EQ(f, 0.0);
    }
  }
  EXPECT_EQ(disk_ff(Vec3(1, 2, 3), Vec3(0, 0, 1), Vec3(1, 2, 3), Vec3(0, 0, -1), 1), 0.0);
  // Facing, extremely close, huge source: approaches but does not exceed 1.
  const double f = disk_ff(Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, 1e-9), Vec3(0, 0, -1), 1e6);
  EXPECT_LE(f, 1.0);
  EXPECT_GT(f, 1 - 1e-12);
}

TEST(FormFactorDisk, MatchesExactForDistantSmallPatches) {
  // Patches ~0.1 across, 1.5 to 4 apart, in random orientations that face each other
  // with both cosines >= 0.3: the disk value (centre to centre) is within 5% of the
  // exact area-averaged form factor (polygon_to_polygon_ff, n = 6). Measured worst
  // 0.5%.
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> U(-1, 1);
  int checked = 0;
  double worst = 0;
  while (checked < 200) {
    auto patch = [&](const Vec3& c, bool tri) {
      const Vec3 e1 = 0.05 * Vec3(U(rng), U(rng), U(rng));
      const Vec3 e2 = 0.05 * Vec3(U(rng), U(rng), U(rng));
      return tri ? Poly{c - e1, c + e1, c + e2}
                 : Poly{c - e1 - e2, c + e1 - e2, c + e1 + e2, c - e1 + e2};
    };
    const Vec3 c1(U(rng), U(rng), U(rng));
    const Vec3 c2 = c1 + (1.5 + 1.25 * (U(rng) + 1)) * Vec3(U(rng), U(rng), U(rng)).normalized();
    Poly r = patch(c1, checked % 3 == 0);
    Poly s = patch(c2, checked % 2 == 0);
    if (polygon_area(r) < 1e-3 || polygon_area(s) < 1e-3) continue;
    if (polygon_normal(r).dot(c2 - c1) < 0) std::reverse(r.begin(), r.end());
    if (polygon_normal(s).dot(c1 - c2) < 0) std::reverse(s.begin(), s.end());
    const Vec3 nr = polygon_normal(r), ns = polygon_normal(s);
    const Vec3 d = (c2 - c1).normalized();
    if (nr.dot(d) < 0.3 || -ns.dot(d) < 0.3) continue;
    const double exact = polygon_to_polygon_ff(r, s, 6);
    const double approx =
        disk_ff(polygon_centroid(r), nr, polygon_centroid(s), ns, polygon_area(s));
    worst = std::max(worst, std::abs(approx / exact - 1));
    ++checked;
  }
  EXPECT_LT(worst, 0.05);
  // Coaxial 0.1 x 0.1 squares one apart: within 0.5% (measured 0.35%).
  const Poly r = rect_z(0, 0.1, 0, 0.1, 0, true);
  const Poly s = rect_z(0, 0.1, 0, 0.1, 1, false);
  EXPECT_NEAR(
      disk_ff(Vec3(0.05, 0.05, 0), Vec3(0, 0, 1), Vec3(0.05, 0.05, 1), Vec3(0, 0, -1), 0.01) /
          ref_parallel_rectangles(0.1, 0.1, 1),
      1, 5e-3);
}

}  // namespace
}  // namespace hrad
