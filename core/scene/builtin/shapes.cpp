#include "core/scene/builtin/shapes.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace hrad::builtin {

namespace {

/// n + 1 coordinates from lo to hi; the end points are exactly lo and hi, so that
/// faces meeting along an edge compute bit-identical vertices there.
std::vector<double> ticks(double lo, double hi, int n) {
  std::vector<double> t(static_cast<std::size_t>(n) + 1);
  for (int k = 0; k < n; ++k) t[k] = lo + (hi - lo) * k / n;
  t[n] = hi;
  return t;
}

/// Points around a circle in the local xz plane, index n wraps to 0 exactly. The
/// angle runs so that (point(i), point(i+1), up) turn clockwise seen from above,
/// which makes the cylinder bands face outward (see cylinder()).
Vec3 ring_point(double radius, double y, int i, int n) {
  const int k = i % n;
  const double a = 2 * std::numbers::pi * k / n;
  return {radius * std::cos(a), y, -radius * std::sin(a)};
}

}  // namespace

Frame Frame::yawed(const Vec3& origin, double yaw) {
  Frame f = at(origin);
  const double c = std::cos(yaw), s = std::sin(yaw);
  f.rotation << c, 0, s, 0, 1, 0, -s, 0, c;
  return f;
}

Frame Frame::along(const Vec3& a, const Vec3& b) {
  const Vec3 y = (b - a).normalized();
  const Vec3 x = y.unitOrthogonal();
  const Vec3 z = x.cross(y);  // (x, y, x × y) is right-handed
  Frame f = at(a);
  f.rotation.col(0) = x;
  f.rotation.col(1) = y;
  f.rotation.col(2) = z;
  return f;
}

int cells_for(double length, double cell) {
  return std::max(1, static_cast<int>(std::lround(length / cell)));
}

std::uint32_t Shapes::material(std::string name, const Rgb& reflectance, const Rgb& emission) {
  Material m;
  m.name = std::move(name);
  m.reflectance = reflectance;
  m.emission = emission;
  return b_.add_material(std::move(m), at_);
}

void Shapes::emit(std::span<const Vec3> p, std::uint32_t m) {
  if (triangles_ && p.size() == 4) {
    const Vec3 t0[3] = {p[0], p[1], p[2]};
    const Vec3 t1[3] = {p[0], p[2], p[3]};
    b_.add_polygon(std::span<const Vec3>(t0), m, at_);
    b_.add_polygon(std::span<const Vec3>(t1), m, at_);
    return;
  }
  b_.add_polygon(p, m, at_);
}

void Shapes::tri(const Frame& f, const Vec3& a, const Vec3& b, const Vec3& c, std::uint32_t m) {
  const Vec3 p[3] = {f(a), f(b), f(c)};
  emit(p, m);
}

void Shapes::quad(const Frame& f, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                  std::uint32_t m) {
  const Vec3 p[4] = {f(a), f(b), f(c), f(d)};
  emit(p, m);
}

void Shapes::grid(const Frame& f, const Vec3& corner, const Vec3& u, const Vec3& v, int nu, int nv,
                  std::uint32_t m) {
  surface(
      f, nu, nv,
      [&](int i, int j) -> Vec3 {
        return corner + (static_cast<double>(i) / nu) * u + (static_cast<double>(j) / nv) * v;
      },
      m);
}

void Shapes::box(const Frame& f, const Vec3& lo, const Vec3& hi, const BoxMaterials& m,
                 unsigned faces, Facing facing, const Eigen::Vector3i& cells) {
  const std::vector<double> t[3] = {ticks(lo.x(), hi.x(), cells.x()),
                                    ticks(lo.y(), hi.y(), cells.y()),
                                    ticks(lo.z(), hi.z(), cells.z())};
  // Face k lies on axis a = k / 2 at its low (even k) or high end. (u, v) are the two
  // other axes ordered so that u x v is the outward normal: for the high face
  // (a+1, a+2) cyclically, for the low face the reverse.
  for (int k = 0; k < 6; ++k) {
    if (!(faces & (1u << k))) continue;
    const int a = k / 2;
    const bool high = k % 2 == 1;
    int u = (a + 1) % 3, v = (a + 2) % 3;
    if (high == (facing == Facing::Inward)) std::swap(u, v);
    const double fixed = high ? t[a].back() : t[a].front();
    auto point = [&](int i, int j) {
      Vec3 p;
      p[a] = fixed;
      p[u] = t[u][i];
      p[v] = t[v][j];
      return p;
    };
    surface(f, cells[u], cells[v], point, m[k]);
  }
}

void Shapes::hexahedron(const Frame& f, const std::array<Vec3, 8>& c, std::uint32_t m,
                        unsigned faces) {
  // Corner cycles of the faces x-, x+, y-, y+, z-, z+, each counter-clockwise seen
  // from outside (the same orientation box() gives an axis-aligned box).
  static constexpr int kCycles[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                        {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (int k = 0; k < 6; ++k) {
    if (!(faces & (1u << k))) continue;
    const int* q = kCycles[k];
    quad(f, c[q[0]], c[q[1]], c[q[2]], c[q[3]], m);
  }
}

void Shapes::box_cells(const Frame& f, const Vec3& lo, const Vec3& hi, std::uint32_t m, double cell,
                       unsigned faces, Facing facing) {
  const Vec3 e = hi - lo;
  box(f, lo, hi, m, faces, facing,
      Eigen::Vector3i(cells_for(e.x(), cell), cells_for(e.y(), cell), cells_for(e.z(), cell)));
}

void Shapes::cylinder(const Frame& f, double radius, double y0, double y1, int segments, int rings,
                      std::uint32_t m, unsigned caps) {
  const std::vector<double> ys = ticks(y0, y1, rings);
  // Band cells (i along the circle, j along y): d/di x d/dj points away from the axis.
  surface(
      f, segments, rings, [&](int i, int j) { return ring_point(radius, ys[j], i, segments); }, m);
  const Vec3 c0(0, y0, 0), c1(0, y1, 0);
  for (int i = 0; i < segments; ++i) {
    if (caps & kYNeg)
      tri(f, c0, ring_point(radius, y0, i + 1, segments), ring_point(radius, y0, i, segments), m);
    if (caps & kYPos)
      tri(f, c1, ring_point(radius, y1, i, segments), ring_point(radius, y1, i + 1, segments), m);
  }
}

void Shapes::rod(const Vec3& a, const Vec3& b, double radius, int segments, std::uint32_t m,
                 unsigned caps) {
  cylinder(Frame::along(a, b), radius, 0.0, (b - a).norm(), segments, 1, m, caps);
}

void Shapes::sphere(const Frame& f, const Vec3& center, double radius, int slices, int stacks,
                    std::uint32_t m) {
  // Latitude j runs from the south pole (j = 0) to the north pole (j = stacks).
  auto point = [&](int i, int j) -> Vec3 {
    if (j == 0) return center - Vec3(0, radius, 0);
    if (j == stacks) return center + Vec3(0, radius, 0);
    const double lat = std::numbers::pi * j / stacks;
    const double r = radius * std::sin(lat);
    return center + ring_point(r, -radius * std::cos(lat), i, slices);
  };
  for (int i = 0; i < slices; ++i) {
    tri(f, point(i, 0), point(i + 1, 1), point(i, 1), m);
    for (int j = 1; j + 1 < stacks; ++j)
      quad(f, point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1), m);
    tri(f, point(i, stacks), point(i, stacks - 1), point(i + 1, stacks - 1), m);
  }
}

void Shapes::prism(const Frame& f, std::span<const Eigen::Vector2d> profile, double z0, double z1,
                   int nz, int per_edge, std::uint32_t m, unsigned caps) {
  // The perimeter with every edge cut into per_edge pieces (exact at the corners).
  std::vector<Eigen::Vector2d> ring;
  const std::size_t k = profile.size();
  for (std::size_t e = 0; e < k; ++e) {
    const Eigen::Vector2d& a = profile[e];
    const Eigen::Vector2d& b = profile[(e + 1) % k];
    ring.push_back(a);
    for (int s = 1; s < per_edge; ++s)
      ring.push_back(a + (b - a) * (static_cast<double>(s) / per_edge));
  }
  const int n = static_cast<int>(ring.size());
  const std::vector<double> zs = ticks(z0, z1, nz);
  // For a counter-clockwise profile, edge x z is the outward normal of each band.
  surface(
      f, n, nz,
      [&](int i, int j) {
        const Eigen::Vector2d& q = ring[i % n];
        return Vec3(q.x(), q.y(), zs[j]);
      },
      m);
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& q : profile) c += q;
  c /= static_cast<double>(k);
  for (const double z : {z0, z1}) {
    const bool top = z == z1;
    if (!(caps & (top ? kZPos : kZNeg))) continue;
    auto at = [&](int i) { return Vec3(ring[i % n].x(), ring[i % n].y(), z); };
    if (n == 4 && !triangles_) {
      if (top)
        quad(f, at(0), at(1), at(2), at(3), m);
      else
        quad(f, at(3), at(2), at(1), at(0), m);
      continue;
    }
    const Vec3 cz(c.x(), c.y(), z);
    for (int i = 0; i < n; ++i) {
      if (top)
        tri(f, cz, at(i), at(i + 1), m);
      else
        tri(f, cz, at(i + 1), at(i), m);
    }
  }
}

void Shapes::table(const Frame& f, double w, double d, double h, double t, double leg, double inset,
                   std::uint32_t top, std::uint32_t legs) {
  box(f, Vec3(-w / 2, h - t, -d / 2), Vec3(w / 2, h, d / 2), top);
  const double lx = w / 2 - inset - leg / 2, lz = d / 2 - inset - leg / 2;
  for (const double sx : {-1.0, 1.0})
    for (const double sz : {-1.0, 1.0}) {
      const Vec3 c(sx * lx, 0, sz * lz);
      box(f, c + Vec3(-leg / 2, 0, -leg / 2), c + Vec3(leg / 2, h - t, leg / 2), legs,
          kAllFaces & ~kYNeg & ~kYPos);
    }
}

void Shapes::luminaire(const Vec3& c, double w, double h, double d, std::uint32_t housing,
                       std::uint32_t emitter) {
  const BoxMaterials m{housing, housing, emitter, housing, housing, housing};
  box(Frame{}, Vec3(c.x() - w / 2, c.y() - h, c.z() - d / 2),
      Vec3(c.x() + w / 2, c.y(), c.z() + d / 2), m, kAllFaces & ~kYPos);
}

}  // namespace hrad::builtin
