#include "core/scene/self_overlap.h"

#include "core/base/interrupt.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>
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

// Lexicographic order of points: the sweep's, as if its line were turned a little.
bool before(const Point& a, const Point& b) {
  return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
}

// Shamos and Hoey's sweep: a pair of edges for which `crossing` holds, found by testing
// only edges that become neighbours along the sweep line, in O(k log k); {k, k} when
// none is. Whenever two edges cross, some crossing pair is neighbours at some event,
// so a crossing is found (its pair may not be the leftmost), up to round-off in the
// order of edges that meet within the crossing test's tolerance.
template <class Crossing>
std::pair<std::size_t, std::size_t> sweep_crossing(const std::vector<Point>& q,
                                                   const Crossing& crossing) {
  const std::size_t k = q.size();
  const std::pair<std::size_t, std::size_t> none{k, k};
  std::vector<std::array<std::size_t, 2>> ends(k);  // each edge's left and right corner
  struct Event {
    std::size_t corner, edge;
    bool leaves;  // at its right end
  };
  std::vector<Event> events;
  events.reserve(2 * k);
  for (std::size_t i = 0; i < k; ++i) {
    const std::size_t a = i, b = (i + 1) % k;
    if (q[a] == q[b]) continue;  // no length: crosses nothing
    ends[i] = before(q[a], q[b]) ? std::array{a, b} : std::array{b, a};
    events.push_back({ends[i][0], i, false});
    events.push_back({ends[i][1], i, true});
  }
  // At one point, edges arrive before others leave (each is tested against the other).
  std::sort(events.begin(), events.end(), [&](const Event& u, const Event& v) {
    if (q[u.corner] != q[v.corner]) return before(q[u.corner], q[v.corner]);
    if (u.leaves != v.leaves) return !u.leaves;
    return u.edge < v.edge;
  });
  // Edge i below edge j where both are on the sweep line: judged at the one that
  // arrived later, against the other's line (their order cannot change before a
  // crossing); edges along one line by index.
  const auto below = [&](std::size_t i, std::size_t j) {
    if (i == j) return false;
    const Point &li = q[ends[i][0]], &ri = q[ends[i][1]], &lj = q[ends[j][0]], &rj = q[ends[j][1]];
    if (li != lj) {
      const bool i_first = before(li, lj);
      const Point &l = i_first ? li : lj, &r = i_first ? ri : rj;
      const Point &nl = i_first ? lj : li, &nr = i_first ? rj : ri;
      double o = orient2d(l, r, nl);  // > 0: the newer edge's left end is above
      if (o == 0) o = orient2d(l, r, nr);
      if (o != 0) return i_first ? o > 0 : o < 0;
    } else if (const double o = orient2d(li, ri, rj); o != 0) {
      return o > 0;
    }
    return i < j;
  };
  std::set<std::size_t, decltype(below)> line(below);
  std::vector<typename std::set<std::size_t, decltype(below)>::iterator> at(k, line.end());
  for (std::size_t e = 0; e < events.size(); ++e) {
    poll_interrupt(e);
    const Event& ev = events[e];
    if (!ev.leaves) {
      const auto it = line.insert(ev.edge).first;
      at[ev.edge] = it;
      if (it != line.begin() && crossing(*std::prev(it), ev.edge)) return {*std::prev(it), ev.edge};
      if (std::next(it) != line.end() && crossing(ev.edge, *std::next(it)))
        return {ev.edge, *std::next(it)};
    } else {
      const auto it = at[ev.edge];
      if (it != line.begin() && std::next(it) != line.end() &&
          crossing(*std::prev(it), *std::next(it)))
        return {*std::prev(it), *std::next(it)};
      line.erase(it);
    }
  }
  return none;
}

// Whether the polygon runs an edge twice in the same direction (by positions: a face may
// repeat indices or give the same corner twice under two indices): what it says, or "".
std::string repeated_edge(std::span<const Vec3> p) {
  const std::size_t k = p.size();
  std::map<std::array<double, 6>, std::size_t> directed;
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3& a = p[i];
    const Vec3& b = p[(i + 1) % k];
    if (a == b) continue;
    const auto [it, fresh] =
        directed.emplace(std::array<double, 6>{a.x(), a.y(), a.z(), b.x(), b.y(), b.z()}, i);
    if (!fresh) return fmt::format("edge {} runs along edge {} again", i + 1, it->second + 1);
  }
  return {};
}

// The first pair of crossing edges found by binning the edges of q (corners relative to
// their box's low corner, `extent` its size) on a grid of about k cells, or {k, k}.
template <class Crossing>
std::pair<std::size_t, std::size_t> grid_crossing(const std::vector<Point>& q, const Point& extent,
                                                  const Crossing& crossing) {
  constexpr std::size_t kCellsPerEdge = 16;
  const std::size_t k = q.size();
  // Pairs meet in a cell. A pair whose boxes share several cells is tested once, in the
  // cell of their common box's low corner, and a pair whose boxes do not meet not at all:
  // the slanted edges of a many-pointed star share dozens of cells, and testing each pair
  // in each of them made 50,000 corners take seconds.
  const std::array<std::size_t, 2> shape = grid_shape(extent.x(), extent.y(), k);
  const std::size_t gx = shape[0], gy = shape[1];
  const Point cell(extent.x() / static_cast<double>(gx), extent.y() / static_cast<double>(gy));
  std::vector<Point> box_lo(k), box_hi(k);
  std::vector<std::array<std::size_t, 4>> span(k);  // x0, x1, y0, y1
  std::size_t entries = 0;
  for (std::size_t i = 0; i < k; ++i) {
    const Point a = q[i], b = q[(i + 1) % k];
    box_lo[i] = a.cwiseMin(b);
    box_hi[i] = a.cwiseMax(b);
    span[i] = {grid_cell(box_lo[i].x(), 0, cell.x(), gx), grid_cell(box_hi[i].x(), 0, cell.x(), gx),
               grid_cell(box_lo[i].y(), 0, cell.y(), gy),
               grid_cell(box_hi[i].y(), 0, cell.y(), gy)};
    entries += (span[i][1] - span[i][0] + 1) * (span[i][3] - span[i][2] + 1);
  }
  // Edges long beside the cells, and slanted, cover many cells each, and then each cell
  // holds many edges: a star of 50,000 thin spikes put about 100 edges into each of
  // its cells, a million pairs a cell, and took seconds (200,000 spikes, minutes). Such
  // a polygon is swept instead (O(k log k), whatever the shape); the grid, which tests
  // every pair that meets, stays for the others.
  if (entries > kCellsPerEdge * k) return sweep_crossing(q, crossing);
  std::vector<std::vector<std::size_t>> bins(gx * gy);
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t y = span[i][2]; y <= span[i][3]; ++y)
      for (std::size_t x = span[i][0]; x <= span[i][1]; ++x) bins[y * gx + x].push_back(i);
  for (std::size_t b = 0; b < bins.size(); ++b) {
    const std::vector<std::size_t>& bin = bins[b];
    poll_interrupt(b, 1024);
    const std::size_t bx = b % gx, by = b / gx;
    for (std::size_t s = 0; s < bin.size(); ++s)
      for (std::size_t t = s + 1; t < bin.size(); ++t) {
        const std::size_t i = bin[s], j = bin[t];
        const Point common_lo = box_lo[i].cwiseMax(box_lo[j]);
        const Point common_hi = box_hi[i].cwiseMin(box_hi[j]);
        if ((common_lo.array() > common_hi.array()).any()) continue;
        if (grid_cell(common_lo.x(), 0, cell.x(), gx) != bx ||
            grid_cell(common_lo.y(), 0, cell.y(), gy) != by)
          continue;
        if (crossing(i, j)) return {i, j};
      }
  }
  return {k, k};
}

}  // namespace

SelfOverlap find_self_overlap(std::span<const Vec3> p) {
  SelfOverlap r;
  const std::size_t k = p.size();
  if (k < 4) return r;  // a triangle cannot overlap itself
  r.what = repeated_edge(p);
  if (!r.what.empty()) {
    r.found = true;
    return r;
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
  constexpr std::size_t kBrute = 64;
  std::pair<std::size_t, std::size_t> ij{k, k};
  if (k <= kBrute) {
    for (std::size_t i = 0; i < k && ij.first == k; ++i)
      for (std::size_t j = i + 2; j < k; ++j)
        if (crossing(i, j)) {
          ij = {i, j};
          break;
        }
  } else {
    ij = grid_crossing(q, hi - lo, crossing);
  }
  if (ij.first < k) {
    r.found = true;
    r.what = fmt::format("edges {} and {} cross", std::min(ij.first, ij.second) + 1,
                         std::max(ij.first, ij.second) + 1);
  }
  return r;
}

}  // namespace hrad
