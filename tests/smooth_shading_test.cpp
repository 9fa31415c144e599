// Smooth and flat shading of leaf elements (core/output/smooth_shading.h): continuity across
// leaves of different depth and across polygons of one surface, constants stay
// constant, creases and materials stay sharp, and a solved scene has no T-vertices.
#include "core/output/smooth_shading.h"

#include "core/output/render.h"
#include "core/scene/builtin_scenes.h"
#include "core/solver/solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>
#include <tuple>

namespace hrad {
namespace {

/// Owns the corners the patches point at.
struct Patches {
  std::deque<std::vector<Vec3>> corners;
  std::vector<ShadingPatch> list;

  void add(std::vector<Vec3> c, double b, std::uint32_t material = 0, double open = 1) {
    corners.push_back(std::move(c));
    const auto& q = corners.back();
    ShadingPatch p;
    p.corners = q;
    for (const Vec3& v : q) p.centre += v / static_cast<double>(q.size());
    p.normal = (q[1] - q[0]).cross(q[2] - q[0]).normalized();
    p.material = material;
    p.area = (q[1] - q[0]).cross(q[2] - q[0]).norm() * (q.size() == 4 ? 1.0 : 0.5);
    p.open = open;
    p.radiosity = Rgb::Constant(b);
    p.reflectance = Rgb::Constant(0.5);
    list.push_back(p);
  }
};

/// The four children of a quad as the hierarchy makes them (core/hierarchy/hierarchy.cpp): per
/// corner, the corner, the next edge's midpoint, the centre, the previous edge's midpoint.
std::array<std::vector<Vec3>, 4> split(const std::vector<Vec3>& c) {
  const Vec3 centre = (c[0] + c[1] + c[2] + c[3]) / 4.0;
  std::array<std::vector<Vec3>, 4> kids;
  for (int i = 0; i < 4; ++i)
    kids[static_cast<std::size_t>(i)] = {c[i], 0.5 * (c[i] + c[(i + 1) % 4]), centre,
                                         0.5 * (c[i] + c[(i + 3) % 4])};
  return kids;
}

std::vector<Vec3> square(double x0, double y0, double x1, double y1) {
  return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
}

/// In z = 0: polygon A = [0,2]^2 split once, its child at [0,1]^2 split again (so
/// (1, 0.5) and (0.5, 1) are T-vertices on A's coarse children), and polygon B =
/// [2,4]x[0,2] as one coarse leaf, on whose left edge A's children meet at (2, 1).
/// Radiosities from `b` in the order the leaves are added (7 of A, then B).
Patches coarse_and_fine(const std::array<double, 8>& b) {
  Patches p;
  const auto a = split(square(0, 0, 2, 2));
  std::size_t n = 0;
  for (const auto& fine : split(a[0])) p.add(fine, b[n++]);
  for (std::size_t i = 1; i < 4; ++i) p.add(a[i], b[n++]);
  p.add(square(2, 0, 4, 2), b[n++]);
  return p;
}

/// The value each polygon of `m` containing point x gives there (triangles:
/// barycentric; quads: bilinear, for parallelograms), within 1e-9.
std::vector<Rgb> values_at(const RenderMesh& m, const Vec3& x) {
  std::vector<Rgb> out;
  constexpr double kEps = 1e-9;
  for (const auto& q : m.polys) {
    const Vec3& p0 = m.positions[q[0]];
    const Vec3 e1 = m.positions[q[1]] - p0;
    const Vec3 e2 = (RenderMesh::is_triangle(q) ? m.positions[q[2]] : m.positions[q[3]]) - p0;
    const Vec3 n = e1.cross(e2);
    const Vec3 d = x - p0;
    if (std::abs(d.dot(n.normalized())) > kEps) continue;  // not in the plane
    // d = u e1 + v e2
    const double u = d.cross(e2).dot(n) / n.squaredNorm();
    const double v = e1.cross(d).dot(n) / n.squaredNorm();
    const auto& b = m.radiosity;
    if (RenderMesh::is_triangle(q)) {
      if (u < -kEps || v < -kEps || u + v > 1 + kEps) continue;
      out.push_back((1 - u - v) * b[q[0]] + u * b[q[1]] + v * b[q[2]]);
    } else {
      EXPECT_LT((m.positions[q[2]] - (p0 + e1 + e2)).norm(), 1e-12) << "not a parallelogram";
      if (u < -kEps || v < -kEps || u > 1 + kEps || v > 1 + kEps) continue;
      out.push_back((1 - u) * (1 - v) * b[q[0]] + u * (1 - v) * b[q[1]] + u * v * b[q[2]] +
                    (1 - u) * v * b[q[3]]);
    }
  }
  return out;
}

/// Largest difference between the values that the polygons meeting at a point give
/// there, over 17 points along every edge of every patch.
double largest_step(const RenderMesh& m, const Patches& p) {
  double worst = 0;
  for (const ShadingPatch& s : p.list) {
    for (std::size_t i = 0; i < s.corners.size(); ++i) {
      const Vec3& a = s.corners[i];
      const Vec3& b = s.corners[(i + 1) % s.corners.size()];
      for (int k = 0; k <= 16; ++k) {
        const auto v = values_at(m, a + (b - a) * (k / 16.0));
        EXPECT_GE(v.size(), 1u);
        for (const Rgb& x : v)
          for (const Rgb& y : v) worst = std::max(worst, (x - y).abs().maxCoeff());
      }
    }
  }
  return worst;
}

constexpr std::array<double, 8> kMixed = {5, 2, 4, 3, 1, 0.5, 2.5, 1.5};

TEST(SmoothShading, ContinuousAcrossCoarseAndFineLeavesAndPolygons) {
  const Patches p = coarse_and_fine(kMixed);
  const RenderMesh smooth = shade_patches(p.list, Shading::Smooth, 1e-9);
  EXPECT_NO_THROW(check_render_mesh(smooth));
  // Along every shared edge, coarse against fine and polygon A against B, both sides
  // agree to rounding (radiosities are of order 1).
  EXPECT_LT(largest_step(smooth, p), 1e-12);
  // The same check fails on the flat mesh: the test can see a step.
  EXPECT_GT(largest_step(shade_patches(p.list, Shading::Flat, 1e-9), p), 1.0);
  // The three coarse leaves with T-vertices (A's children touching the fine ones, B)
  // are fans; the other four of A's fine leaves and one coarse child stay quads.
  std::size_t quads = 0, triangles = 0;
  for (const auto& q : smooth.polys) (RenderMesh::is_triangle(q) ? triangles : quads)++;
  EXPECT_EQ(quads, 5u);
  EXPECT_EQ(triangles, 3u * 5u);  // 4 corners + 1 hanging point each
}

TEST(SmoothShading, RenderedImageHasNoStepAtTheSharedEdges) {
  const Patches p = coarse_and_fine(kMixed);
  Camera cam;
  cam.eye = Vec3(2, 1, 10);
  cam.target = Vec3(2, 1, 0);
  cam.up = Vec3::UnitY();
  const double half = 1.25;  // half-height at z = 0; half-width 1.25 * 5/3 > 2
  cam.fov_y_deg = 2 * std::atan(half / 10) * 180 / std::numbers::pi;
  const int w = 500, h = 300;
  const double pixel = 2 * half / h;  // scene units per pixel
  const auto column_of = [&](double x) { return (x - 2) / pixel + w / 2.0; };
  for (Shading mode : {Shading::Smooth, Shading::Flat}) {
    const Image img = render_radiance(shade_patches(p.list, mode, 1e-9), cam, w, h);
    double step = 0;
    for (double edge : {1.0, 2.0}) {  // fine | coarse inside A, then A | B
      const int right = static_cast<int>(std::ceil(column_of(edge) - 0.5));
      for (int y = h / 2 - 100; y < h / 2 + 100; ++y)
        step = std::max(step, std::abs(img.at(right, y)[0] - img.at(right - 1, y)[0]));
    }
    // Smooth: the two samples are one pixel apart, so they differ by at most the
    // largest gradient (vertex values lie in [0.5, 5], leaves are at least 0.5 wide:
    // under 10 per unit) times a pixel, over pi.
    const double bound = 10 * pixel / std::numbers::pi;
    if (mode == Shading::Smooth)
      EXPECT_LT(step, bound);
    else
      EXPECT_GT(step, 10 * bound);  // flat shading shows the leaves
  }
}

TEST(SmoothShading, ConstantRadiosityStaysConstant) {
  Patches p = coarse_and_fine({2.5, 2.5, 2.5, 2.5, 2.5, 2.5, 2.5, 2.5});
  p.list[1].open = 0.25;  // weights must not matter when every value is the same
  p.list[7].open = 0;
  const RenderMesh m = shade_patches(p.list, Shading::Smooth, 1e-9);
  for (const Rgb& b : m.radiosity) EXPECT_NEAR(b[0], 2.5, 1e-12);
  Camera cam;
  cam.eye = Vec3(2, 1, 6);
  cam.target = Vec3(2, 1, 0);
  cam.up = Vec3::UnitY();
  const Image img = render_radiance(m, cam, 64, 48);
  int covered = 0;
  for (std::size_t i = 0; i < img.radiance.size(); ++i) {
    if (img.coverage[i] == 0) continue;
    ++covered;
    ASSERT_NEAR(img.radiance[i][1], 2.5 / std::numbers::pi, 1e-12) << i;
  }
  EXPECT_GT(covered, 300);  // about 12% of the picture
}

TEST(SmoothShading, CreasesMaterialsAndClosedInLeavesStaySeparate) {
  Patches p;
  p.add(square(0, 0, 1, 1), 1);                            // 0: floor
  p.add({{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, 4);  // 1: wall at x = 0, 90 deg
  p.add(square(1, 0, 2, 1), 3, /*material=*/1);            // 2: same plane, other material
  // 3: the floor continued past y = 1, bent up by 20 degrees: shares its edge y = 1.
  const double t = 20 * std::numbers::pi / 180;
  p.add(
      {{0, 1, 0}, {1, 1, 0}, {1, 1 + std::cos(t), std::sin(t)}, {0, 1 + std::cos(t), std::sin(t)}},
      2);
  p.add(square(0, -1, 1, 0), 0, 0, /*open=*/0);  // 4: closed in, dark
  const RenderMesh m = shade_patches(p.list, Shading::Smooth, 1e-9);
  const auto values = [&](const Vec3& x) {
    std::set<double> v;
    for (const Rgb& b : values_at(m, x)) v.insert(std::round(b[0] * 1e9) / 1e9);
    return v;
  };
  // The crease with the wall (x = 0, y in (0,1)) keeps both sides' own values; so does
  // the material boundary at x = 1. The 20 degree bend at y = 1 blends: one value.
  EXPECT_EQ(values({0, 0.5, 0}).size(), 2u);
  EXPECT_EQ(values({1, 0.5, 0}).size(), 2u);
  EXPECT_EQ(values({0.5, 1, 0}).size(), 1u);
  // The floor's corner (1, 1) blends the floor and the bent leaf (equal areas): 1.5,
  // beside the other material's 3. Along y = 0 the closed-in leaf (open area 0) adds
  // no weight, so the floor keeps its 1; where it is alone (y = -1) its own 0 is used.
  EXPECT_EQ(values({1, 1, 0}), (std::set<double>{1.5, 3}));
  EXPECT_EQ(values({0.5, 0, 0}), (std::set<double>{1}));
  EXPECT_EQ(values({0.5, -1, 0}), (std::set<double>{0}));
}

TEST(SmoothShading, FlatKeepsEachLeafItsOwnConstant) {
  const Patches p = coarse_and_fine(kMixed);
  const RenderMesh m = shade_patches(p.list, Shading::Flat, 1e-9);
  ASSERT_EQ(m.polys.size(), p.list.size());
  for (std::size_t i = 0; i < m.polys.size(); ++i)
    for (int c = 0; c < 4; ++c) EXPECT_EQ(m.radiosity[m.polys[i][c]][0], kMixed[i]);
  // A pentagon is a fan in both modes.
  Patches pent;
  pent.add({{0, 0, 0}, {2, 0, 0}, {3, 1, 0}, {1, 2, 0}, {-1, 1, 0}}, 1);
  EXPECT_EQ(shade_patches(pent.list, Shading::Flat, 1e-9).polys.size(), 3u);
  EXPECT_EQ(shade_patches(pent.list, Shading::Smooth, 1e-9).polys.size(), 5u);
}

TEST(SmoothShading, RejectsBadInput) {
  Patches p;
  p.add(square(0, 0, 1, 1), 1);
  EXPECT_THROW((void)shade_patches(p.list, Shading::Smooth, 0), std::invalid_argument);
  p.list[0].corners = p.list[0].corners.first(2);
  EXPECT_THROW((void)shade_patches(p.list, Shading::Flat, 1e-9), std::invalid_argument);
  EXPECT_EQ(enum_from_name<Shading>("flat"), Shading::Flat);
  try {
    (void)parse_enum<Shading>("gouraud", "shading");
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("allowed: smooth, flat"), std::string::npos) << e.what();
  }
}

TEST(SmoothShading, SolvedCornellBoxHasNoTVertices) {
  // A solved scene: no edge of the smooth mesh has a vertex of a coplanar polygon at
  // its midpoint (the first dyadic point a finer neighbour would have), while the
  // mesh of leaves itself has many (the quadtree's depths differ).
  const Scene scene = make_builtin("builtin:cornell");
  Solver solver(scene, SolverOptions{});
  (void)solver.run();
  const double q = 1e-7 * scene.bounds().diagonal();
  using Key = std::tuple<long long, long long, long long, long long, long long, long long>;
  const auto count_t_vertices = [&](const RenderMesh& m) {
    const auto key = [&](const Vec3& x, const Vec3& n) {
      return Key{std::llround(x.x() / q),   std::llround(x.y() / q),   std::llround(x.z() / q),
                 std::llround(n.x() * 1e3), std::llround(n.y() * 1e3), std::llround(n.z() * 1e3)};
    };
    std::set<Key> corners;
    std::vector<Vec3> normals;
    for (const auto& f : m.polys) {
      const Vec3 n = (m.positions[f[1]] - m.positions[f[0]])
                         .cross(m.positions[f[2]] - m.positions[f[0]])
                         .normalized();
      normals.push_back(n);
      for (int c = 0; c < (RenderMesh::is_triangle(f) ? 3 : 4); ++c)
        corners.insert(key(m.positions[f[c]], n));
    }
    int found = 0;
    for (std::size_t i = 0; i < m.polys.size(); ++i) {
      const auto& f = m.polys[i];
      const int k = RenderMesh::is_triangle(f) ? 3 : 4;
      for (int c = 0; c < k; ++c)
        found +=
            corners.count(key(0.5 * (m.positions[f[c]] + m.positions[f[(c + 1) % k]]), normals[i]));
    }
    return found;
  };
  EXPECT_GT(count_t_vertices(solver.render_mesh(Shading::Flat)), 20);
  EXPECT_EQ(count_t_vertices(solver.render_mesh(Shading::Smooth)), 0);
}

}  // namespace
}  // namespace hrad
