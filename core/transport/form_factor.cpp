#include "core/transport/form_factor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace hrad {
namespace {

constexpr double kPi = std::numbers::pi;

// Relative tolerance (of the distance scale) below which a point counts as lying in the
// source's plane. The tangent-plane clipping compares nx . R_i with 0, whose rounding
// error is a few ulps of |R_i|; well above that, the contour integral is accurate.
constexpr double kCoplanarTol = 1e-12;

// Contribution of the contour edge a -> b (both relative to the receiver point) to the
// sum whose value / 2pi is the form factor: gamma * n . c / |c| with c = b x a, gamma the
// angle between a and b. (b - a) x a == b x a, but the edge vector b - a keeps the
// cross product accurate when a and b are nearly opposite (point close to the edge).
// A zero cross product means either a zero-length edge or a point on the edge line;
// both contribute nothing.
inline double edge_term(const Vec3& a, const Vec3& b, const Vec3& n) {
  const Vec3 c = (b - a).cross(a);
  const double s = c.norm();
  if (!(s > 0)) return 0.0;
  return std::atan2(s, a.dot(b)) * n.dot(c) / s;
}

// Clamp to [0, 1], mapping NaN to 0.
inline double unit_clamp(double f) {
  if (!(f > 0)) return 0.0;
  return f < 1 ? f : 1.0;
}

// Integrates F_{dA->src} over the bilinear patch P(u,v) = (1-u)(1-v) p0 + u(1-v) p1
// + uv p2 + (1-u)v p3 with the product rule (u_i, w_i); a triangle is the patch with
// p3 == p2. Adds sum w |J| F to *wf and sum w |J| (the patch's area, exactly for a
// planar patch since |J| is then affine in u and v) to *wa.
void integrate_patch(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3,
                     std::span<const Vec3> src, std::span<const double> u,
                     std::span<const double> w, double* wf, double* wa) {
  const std::size_t n = u.size();
  const Vec3 e01 = p1 - p0;
  const Vec3 e03 = p3 - p0;
  const Vec3 twist = (p2 - p3) - e01;  // zero for a parallelogram
  for (std::size_t j = 0; j < n; ++j) {
    const double v = u[j];
    // Points on the iso-v line: a + u * b, with b = dP/du; dP/dv = e03 + u * twist.
    const Vec3 a = p0 + v * e03;
    const Vec3 b = e01 + v * twist;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 x = a + u[i] * b;
      const Vec3 jn = b.cross(e03 + u[i] * twist);  // normal scaled by the Jacobian
      const double jac = jn.norm();
      if (!(jac > 0)) continue;
      const double wij = w[i] * w[j] * jac;
      *wf += wij * point_to_polygon_ff(x, jn / jac, src);
      *wa += wij;
    }
  }
}

}  // namespace

double point_to_polygon_ff(const Vec3& x, const Vec3& nx, std::span<const Vec3> poly) {
  const std::size_t k = poly.size();
  if (k < 3) return 0.0;

  // Pass 1: the source's vector area (twice it, as a fan from v0 so that x's distance
  // does not cost precision) and vertex mean, to place x relative to the source plane.
  const Vec3& v0 = poly[0];
  Vec3 area2 = Vec3::Zero();
  Vec3 mean = Vec3::Zero();
  for (std::size_t i = 1; i < k; ++i) {
    mean += poly[i] - v0;
    if (i + 1 < k) area2 += (poly[i] - v0).cross(poly[i + 1] - v0);
  }
  const double a2 = area2.norm();
  if (!(a2 > 0)) return 0.0;                               // zero-area (or non-finite) source
  const Vec3 rc = x - v0 - mean / static_cast<double>(k);  // source centre -> x
  const double h = area2.dot(rc) / a2;  // height of x in front of the source's plane
  // Behind the source, or in its plane (edge-on): nothing is received.
  if (!(h > kCoplanarTol * (rc.norm() + std::sqrt(a2)))) return 0.0;

  // Pass 2: Sutherland-Hodgman clipping against the tangent half-space nx . R > 0,
  // streamed edge by edge straight into the contour sum (no vertex storage, so any
  // polygon length works). A clipped edge leaves through an "exit" point and the
  // contour re-enters at the next "entry" point; the segment exit -> entry lies on
  // x's horizon and contributes like any other edge. For a convex polygon there is at
  // most one exit and one entry.
  double sum = 0.0;
  Vec3 exit_pt = Vec3::Zero();
  Vec3 first_entry = Vec3::Zero();
  bool pending_exit = false;
  bool stashed_entry = false;
  Vec3 ra = poly[k - 1] - x;
  double da = nx.dot(ra);
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3 rb = poly[i] - x;
    const double db = nx.dot(rb);
    if (da > 0) {
      if (db > 0) {
        sum += edge_term(ra, rb, nx);
      } else {
        // da > 0 >= db, so t lies in (0, 1].
        const Vec3 p = ra + (da / (da - db)) * (rb - ra);
        sum += edge_term(ra, p, nx);
        exit_pt = p;
        pending_exit = true;
      }
    } else if (db > 0) {
      // da <= 0 < db, so t lies in [0, 1).
      const Vec3 p = ra + (da / (da - db)) * (rb - ra);
      if (pending_exit) {
        sum += edge_term(exit_pt, p, nx);
        pending_exit = false;
      } else {
        first_entry = p;  // closes the loop with the last exit, after the loop
        stashed_entry = true;
      }
      sum += edge_term(p, rb, nx);
    }
    ra = rb;
    da = db;
  }
  if (pending_exit && stashed_entry) sum += edge_term(exit_pt, first_entry, nx);
  return unit_clamp(sum / (2 * kPi));
}

double disk_ff(const Vec3& x, const Vec3& nx, const Vec3& y, const Vec3& ny, double area_s) {
  const Vec3 r = y - x;
  const double d2 = r.squaredNorm();
  if (!(d2 > 0) || !(area_s > 0)) return 0.0;
  // cos_x cos_y = (nx . r)(-ny . r) / d^2, each factor clamped at 0.
  const double cx = std::max(0.0, nx.dot(r));
  const double cy = std::max(0.0, -ny.dot(r));
  return unit_clamp(area_s * (cx * cy / d2) / (kPi * d2 + area_s));
}

double polygon_to_polygon_ff(std::span<const Vec3> recv, std::span<const Vec3> src, int n) {
  const std::size_t k = recv.size();
  if (k < 3 || src.size() < 3) return 0.0;
  n = std::clamp(n, 1, kMaxFormFactorOrder);
  std::array<double, kMaxFormFactorOrder> nodes;
  std::array<double, kMaxFormFactorOrder> weights;
  const std::span<double> u(nodes.data(), static_cast<std::size_t>(n));
  const std::span<double> w(weights.data(), static_cast<std::size_t>(n));
  gauss_legendre_01(u, w);

  double wf = 0.0;
  double wa = 0.0;
  if (k == 4) {
    integrate_patch(recv[0], recv[1], recv[2], recv[3], src, u, w, &wf, &wa);
  } else {
    // Triangle, or a fan of triangles for a larger convex polygon; each triangle is the
    // bilinear patch collapsed at its last vertex.
    for (std::size_t i = 1; i + 1 < k; ++i)
      integrate_patch(recv[0], recv[i], recv[i + 1], recv[i + 1], src, u, w, &wf, &wa);
  }
  if (!(wa > 0)) return 0.0;
  return unit_clamp(wf / wa);
}

void gauss_legendre_01(std::span<double> nodes, std::span<double> weights) {
  const std::size_t n = std::min(nodes.size(), weights.size());
  switch (n) {
    case 0: return;
    case 1:
      nodes[0] = 0.5;
      weights[0] = 1.0;
      return;
    case 2: {
      const double d = 0.5 / std::sqrt(3.0);
      nodes[0] = 0.5 - d;
      nodes[1] = 0.5 + d;
      weights[0] = weights[1] = 0.5;
      return;
    }
    case 3: {
      const double d = 0.5 * std::sqrt(0.6);
      nodes[0] = 0.5 - d;
      nodes[1] = 0.5;
      nodes[2] = 0.5 + d;
      weights[0] = weights[2] = 5.0 / 18.0;
      weights[1] = 8.0 / 18.0;
      return;
    }
    case 4: {
      const double s = 2.0 / 7.0 * std::sqrt(6.0 / 5.0);
      const double d_in = 0.5 * std::sqrt(3.0 / 7.0 - s);
      const double d_out = 0.5 * std::sqrt(3.0 / 7.0 + s);
      const double w_in = (18.0 + std::sqrt(30.0)) / 72.0;
      const double w_out = (18.0 - std::sqrt(30.0)) / 72.0;
      nodes[0] = 0.5 - d_out;
      nodes[1] = 0.5 - d_in;
      nodes[2] = 0.5 + d_in;
      nodes[3] = 0.5 + d_out;
      weights[0] = weights[3] = w_out;
      weights[1] = weights[2] = w_in;
      return;
    }
    default: break;
  }
  // Roots z of the Legendre polynomial P_n on [-1, 1] by Newton's iteration from the
  // usual asymptotic guess, largest root first; weight 2 / ((1 - z^2) P_n'(z)^2).
  const double nd = static_cast<double>(n);
  // P_n'(z) from the three-term recurrence; `pn` receives P_n(z).
  auto legendre_derivative = [&](double z, double& pn) {
    double p0 = 1.0;
    double p1 = z;
    for (std::size_t j = 2; j <= n; ++j) {
      const double jd = static_cast<double>(j);
      const double p2 = ((2 * jd - 1) * z * p1 - (jd - 1) * p0) / jd;
      p0 = p1;
      p1 = p2;
    }
    pn = p1;
    return nd * (z * p1 - p0) / (z * z - 1);
  };
  for (std::size_t i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(kPi * (static_cast<double>(i) + 0.75) / (nd + 0.5));
    double pn = 0;
    for (int iter = 0; iter < 100; ++iter) {
      const double dp = legendre_derivative(z, pn);  // sets pn first
      const double dz = pn / dp;
      z -= dz;
      if (std::abs(dz) <= 1e-16) break;
    }
    // P_n' at the converged root, for the weight.
    const double dp = legendre_derivative(z, pn);
    const double wt = 1.0 / ((1 - z * z) * dp * dp);  // half of the [-1, 1] weight
    nodes[i] = 0.5 * (1 - z);
    nodes[n - 1 - i] = 0.5 * (1 + z);
    weights[i] = weights[n - 1 - i] = wt;
  }
}

}  // namespace hrad
