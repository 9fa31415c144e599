#include "core/scene/self_overlap.h"

#include "core/base/interrupt.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace hrad {

namespace {

using Point = Eigen::Vector2d;

// The plane's normal: the vector area's, else (the lobes of a bow-tie cancel) that of
// the corner with the largest cross product.
Vec3 plane_normal(std::span<const Vec3> p) {
  const Vec3 a = vector_area(p);
  double best = 0;
  Vec3 n = Vec3::Zero();
  const std::size_t k = p.size();
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3 c = (p[(i + 1) % k] - p[i]).cross(p[(i + 2) % k] - p[(i + 1) % k]);
    if (c.norm() > best) {
      best = c.norm();
      n = c;
    }
  }
  // A vector area much smaller than the corners says the lobes cancelled.
  if (a.norm() > 1e-3 * best) n = a;
  const double len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

}  // namespace

SelfOverlap find_self_overlap(std::span<const Vec3> p) {
  SelfOverlap r;
  const std::size_t k = p.size();
  if (k < 4) return r;  // a triangle cannot overlap itself
  // An edge run twice in the same direction (by positions: a face may repeat indices or
  // give the same corner twice under two indices).
  std::map<std::array<double, 6>, std::size_t> directed;
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3& a = p[i];
    const Vec3& b = p[(i + 1) % k];
    if (a == b) continue;
    const auto [it, fresh] =
        directed.emplace(std::array<double, 6>{a.x(), a.y(), a.z(), b.x(), b.y(), b.z()}, i);
    if (!fresh) {
      r.found = true;
      r.what = fmt::format("edge {} runs along edge {} again", i + 1, it->second + 1);
      return r;
    }
  }
  const Vec3 n = plane_normal(p);
  if (n.isZero()) return r;  // every corner degenerate: no area to cover twice
  const Vec3 u = n.unitOrthogonal();
  const Vec3 v = n.cross(u);
  std::vector<Point> q(k);
  Point lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  Point hi = -lo;
  for (std::size_t i = 0; i < k; ++i) {
    q[i] = Point(p[i].dot(u), p[i].dot(v));
    lo = lo.cwiseMin(q[i]);
    hi = hi.cwiseMax(q[i]);
  }
  const double size = (hi - lo).norm();
  if (!(size > 0)) return r;
  for (Point& x : q) x -= lo;  // round-off in orient2d() then scales with the size
  std::vector<double> length(k);
  for (std::size_t i = 0; i < k; ++i) length[i] = (q[(i + 1) % k] - q[i]).norm();
  const auto crossing = [&](std::size_t i, std::size_t j) {
    // Edges sharing a corner of the cycle only touch.
    if (i == j || (i + 1) % k == j || (j + 1) % k == i) return false;
    const Point &a = q[i], &b = q[(i + 1) % k], &c = q[j], &d = q[(j + 1) % k];
    // Orientations this small count as zero (touching, or collinear like a seam):
    // 1e-10 of the two edges' lengths multiplied, plus round-off at the polygon's size.
    const double ab = length[i], cd = length[j];
    const double tiny = 1e-10 * ab * cd + 1e-14 * size * (ab + cd);
    const auto sign = [&](double o) { return o > tiny ? 1 : (o < -tiny ? -1 : 0); };
    return sign(orient2d(a, b, c)) * sign(orient2d(a, b, d)) < 0 &&
           sign(orient2d(c, d, a)) * sign(orient2d(c, d, b)) < 0;
  };
  const auto found = [&](std::size_t i, std::size_t j) {
    r.found = true;
    r.what = fmt::format("edges {} and {} cross", std::min(i, j) + 1, std::max(i, j) + 1);
    return r;
  };
  constexpr std::size_t kBrute = 64;
  if (k <= kBrute) {
    for (std::size_t i = 0; i < k; ++i)
      for (std::size_t j = i + 2; j < k; ++j)
        if (crossing(i, j)) return found(i, j);
    return r;
  }
  // Edges binned by their boxes on a grid of about k cells; pairs meet in a cell.
  const Point extent = hi - lo;
  const std::array<std::size_t, 2> shape = grid_shape(extent.x(), extent.y(), k);
  const std::size_t gx = shape[0], gy = shape[1];
  const Point cell(extent.x() / static_cast<double>(gx), extent.y() / static_cast<double>(gy));
  std::vector<std::vector<std::size_t>> bins(gx * gy);
  for (std::size_t i = 0; i < k; ++i) {
    const Point a = q[i], b = q[(i + 1) % k];
    const std::size_t x0 = grid_cell(std::min(a.x(), b.x()), 0, cell.x(), gx),
                      x1 = grid_cell(std::max(a.x(), b.x()), 0, cell.x(), gx),
                      y0 = grid_cell(std::min(a.y(), b.y()), 0, cell.y(), gy),
                      y1 = grid_cell(std::max(a.y(), b.y()), 0, cell.y(), gy);
    for (std::size_t y = y0; y <= y1; ++y)
      for (std::size_t x = x0; x <= x1; ++x) bins[y * gx + x].push_back(i);
  }
  for (std::size_t b = 0; b < bins.size(); ++b) {
    const std::vector<std::size_t>& bin = bins[b];
    poll_interrupt(b, 1024);
    for (std::size_t s = 0; s < bin.size(); ++s)
      for (std::size_t t = s + 1; t < bin.size(); ++t)
        if (crossing(bin[s], bin[t])) return found(bin[s], bin[t]);
  }
  return r;
}

}  // namespace hrad
