#include "core/raycast/face_contacts.h"

#include "core/base/interrupt.h"
#include "core/raycast/ray_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

namespace hrad {

namespace {

// Candidates are found by plane. Normals are binned in cells of kCell per component; a
// polygon is filed in every cell within its normal's slack (up to eight), and looks for
// partners in the one cell that holds -n, its own normal reversed, so every pair within
// the angle meets. Within a cell the polygons are sorted by their plane's offset from
// the scene's centre, n . (x - centre); two polygons a, b within `tolerance` of each
// other at some point p have offsets o_a and o_b with |o_a + o_b| <= 2 tolerance +
// |n_a + n_b| |p - centre|.
constexpr double kCell = 0.1;

struct Plane {
  Vec3 n = Vec3::Zero();  // unit normal
  double offset = 0;      // n . (x - centre) for x in the plane
  Aabb box;
};

using Key = std::array<int, 3>;
struct KeyHash {
  std::size_t operator()(const Key& k) const {
    return (static_cast<std::size_t>(k[0]) * 73856093u) ^
           (static_cast<std::size_t>(k[1]) * 19349663u) ^
           (static_cast<std::size_t>(k[2]) * 83492791u);
  }
};
using NormalCells = std::unordered_map<Key, std::vector<std::uint32_t>, KeyHash>;

int cell_of(double x) { return static_cast<int>(std::floor(x / kCell)); }

// The polygons' corners, read through their index ranges.
struct Corners {
  std::span<const Vec3> vertices;
  std::span<const std::uint32_t> indices;
  std::span<const PolygonRange> polygons;
  const Vec3& operator()(std::size_t i, std::uint32_t k) const {
    return vertices[indices[polygons[i].first + k]];
  }
};

// Each polygon's plane about `centre`. A degenerate polygon is marked in `contact`
// (its tests are never skipped) and gets no plane.
std::vector<Plane> fit_planes(const Corners& corner, const Vec3& centre,
                              std::vector<std::uint8_t>& contact) {
  const std::size_t n = corner.polygons.size();
  std::vector<Plane> plane(n);
  std::vector<Vec3> pts;
  for (std::size_t i = 0; i < n; ++i) {
    poll_interrupt(i);  // a million polygons take seconds here and below
    pts.clear();
    for (std::uint32_t k = 0; k < corner.polygons[i].count; ++k) pts.push_back(corner(i, k));
    Plane& p = plane[i];
    p.n = polygon_normal(pts);
    if (!(p.n.squaredNorm() > 0.5)) {  // degenerate: never skip its tests
      contact[i] = 1;
      continue;
    }
    p.offset = p.n.dot(polygon_centroid(pts) - centre);
    for (const Vec3& x : pts) p.box.extend(x);
  }
  return plane;
}

// Every polygon with a plane, filed in each normal cell within `slack` of its normal,
// each cell sorted by the planes' offsets.
NormalCells file_by_normal(const std::vector<Plane>& plane,
                           const std::vector<std::uint8_t>& contact, double slack) {
  NormalCells cells;
  for (std::size_t i = 0; i < plane.size(); ++i) {
    poll_interrupt(i);
    if (contact[i]) continue;
    const Vec3& v = plane[i].n;
    for (int x = cell_of(v[0] - slack); x <= cell_of(v[0] + slack); ++x)
      for (int y = cell_of(v[1] - slack); y <= cell_of(v[1] + slack); ++y)
        for (int z = cell_of(v[2] - slack); z <= cell_of(v[2] + slack); ++z)
          cells[Key{x, y, z}].push_back(static_cast<std::uint32_t>(i));
  }
  for (auto& [key, members] : cells) {
    throw_if_interrupted();
    std::sort(members.begin(), members.end(),
              [&](std::uint32_t a, std::uint32_t b) { return plane[a].offset < plane[b].offset; });
  }
  return cells;
}

}  // namespace

std::vector<std::uint8_t> find_face_contacts(std::span<const Vec3> vertices,
                                             std::span<const std::uint32_t> indices,
                                             std::span<const PolygonRange> polygons,
                                             std::span<const std::uint32_t> twins,
                                             double tolerance) {
  const std::size_t n = polygons.size();
  std::vector<std::uint8_t> contact(n, 0);
  if (n == 0) return contact;
  const Corners corner{vertices, indices, polygons};
  Aabb all;
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = 0; k < polygons[i].count; ++k) all.extend(corner(i, k));
  const Vec3 centre = all.center();
  const double radius = 0.5 * all.diagonal();
  const double angle = kContactDegrees * std::numbers::pi / 180;
  const double slack = 2 * std::sin(angle / 2);  // |n_a - n_b| at most
  const double window = 2 * tolerance + slack * radius;
  const std::vector<Plane> plane = fit_planes(corner, centre, contact);
  const NormalCells cells = file_by_normal(plane, contact, slack);

  const double cos_min = std::cos(angle);
  // Whether polygon j comes within `tolerance` of polygon i's plane (its corners are not
  // all on one side beyond it).
  const auto reaches = [&](std::size_t i, std::size_t j) {
    const Vec3 at = centre + plane[i].offset * plane[i].n;  // a point of i's plane
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::uint32_t k = 0; k < polygons[j].count; ++k) {
      const double s = plane[i].n.dot(corner(j, k) - at);
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
    return lo <= tolerance && hi >= -tolerance;
  };
  const auto against = [&](std::size_t i, std::size_t j) {
    const Plane& a = plane[i];
    const Plane& b = plane[j];
    if (a.n.dot(b.n) > -cos_min) return false;
    if (!twins.empty() && twins[i] == j) return false;
    if (((a.box.lo.array() - tolerance) > b.box.hi.array()).any() ||
        ((b.box.lo.array() - tolerance) > a.box.hi.array()).any())
      return false;
    return reaches(i, j) && reaches(j, i);
  };

  for (std::size_t i = 0; i < n; ++i) {
    poll_interrupt(i);
    if (contact[i]) continue;
    const Vec3 r = -plane[i].n;
    const auto found = cells.find(Key{cell_of(r[0]), cell_of(r[1]), cell_of(r[2])});
    if (found == cells.end()) continue;
    const std::vector<std::uint32_t>& members = found->second;
    const double want = -plane[i].offset;
    auto k = std::lower_bound(members.begin(), members.end(), want - window,
                              [&](std::uint32_t m, double o) { return plane[m].offset < o; });
    int tested = 0;
    for (; k != members.end() && plane[*k].offset <= want + window; ++k) {
      if (++tested > kContactCandidates || against(i, *k)) {
        contact[i] = 1;  // (j finds i when it looks itself)
        break;
      }
    }
  }
  return contact;
}

}  // namespace hrad
