#include "core/scene/mgf/mgf_reader.h"

#include "core/base/input_error.h"
#include "core/scene/mgf/mgf_color.h"
#include "core/scene/mgf/mgf_segments.h"
#include "core/scene/mgf/mgf_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>

namespace hrad {
namespace {

constexpr double kPi = std::numbers::pi;

std::string data(const std::string& rel) {
  return std::string(HRAD_SOURCE_DIR) + "/tests/data/mgf/" + rel;
}

Scene parse(const std::string& text, int segments = 16) {
  MgfOptions o;
  o.segments = segments;
  return parse_mgf(text, "test.mgf", o);
}

bool has_warning(const Scene& s, const std::string& fragment) {
  for (const auto& w : s.warnings)
    if (w.find(fragment) != std::string::npos) return true;
  return false;
}

// A grey material and a vertex `c` at `centre` with normal `n`.
std::string prelude(const std::string& centre = "0 0 0", const std::string& n = "0 0 1") {
  return "m g =\n rd 0.5\nv c =\n p " + centre + "\n n " + n + "\n";
}

// Every face's normal points away from (outward) or towards (inward) `centre`.
void expect_facing(const Scene& s, const Vec3& centre, bool outward) {
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const auto p = s.face_vertices(f);
    const double d = s.face_normal(f).dot(polygon_centroid(p) - centre);
    EXPECT_EQ(d > 0, outward) << "face " << f;
  }
}

// ---- colour ---------------------------------------------------------------

TEST(MgfColor, EqualEnergyGreyIsExactlyGrey) {
  const Rgb c = xyY_to_linear_rgb(1.0 / 3.0, 1.0 / 3.0, 0.37);
  EXPECT_EQ(c[0], 0.37);
  EXPECT_EQ(c[1], 0.37);
  EXPECT_EQ(c[2], 0.37);
  // Three printed decimals still count as grey.
  EXPECT_EQ(xyY_to_linear_rgb(0.333, 0.333, 1.0)[1], 1.0);
  // The matrix itself maps XYZ white (1, 1, 1) to RGB white.
  const Eigen::Vector3d w = xyz_to_linear_rgb_matrix() * Eigen::Vector3d::Ones();
  EXPECT_NEAR(w[0], 1.0, 1e-12);
  EXPECT_NEAR(w[1], 1.0, 1e-12);
  EXPECT_NEAR(w[2], 1.0, 1e-12);
}

TEST(MgfColor, KnownChromaticitiesGiveExpectedRgb) {
  // Reference values computed independently with exact rational arithmetic from the
  // Rec. 709 primaries and the equal-energy white.
  const Rgb a = xyY_to_linear_rgb(0.4, 0.35, 1.0);
  EXPECT_NEAR(a[0], 1.502463, 1e-3);
  EXPECT_NEAR(a[1], 0.841464, 1e-3);
  EXPECT_NEAR(a[2], 0.676385, 1e-3);
  // A primary maps onto its own axis.
  const Rgb red = xyY_to_linear_rgb(0.64, 0.33, 1.0);
  EXPECT_NEAR(red[0], 3.902821, 1e-3);
  EXPECT_NEAR(red[1], 0.0, 1e-9);
  EXPECT_NEAR(red[2], 0.0, 1e-9);
  // Luminance is linear in Y.
  EXPECT_NEAR(xyY_to_linear_rgb(0.4, 0.35, 0.25)[2], 0.25 * a[2], 1e-12);
}

TEST(MgfColor, ReflectanceAndEmissionConversion) {
  const std::string tri = "v a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 1 0\nf a b d\n";
  // Grey rd is the RGB reflectance; ed 179 lm/m^2 is 1 W/m^2 per channel.
  Scene s = parse("m x =\n c\n rd 0.5\n ed 179\n" + tri);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].name, "x");
  EXPECT_EQ(s.materials[0].reflectance[1], 0.5);
  EXPECT_DOUBLE_EQ(s.materials[0].emission[0], 1.0);
  EXPECT_TRUE(s.is_grey());
  // A coloured emitter: E = ed / 179 * rgb(x, y, Y = 1).
  s = parse("m x =\n c\n cxy 0.4 0.35\n ed 358\n" + tri);
  EXPECT_NEAR(s.materials[0].emission[0], 2 * 1.502463, 2e-3);
  EXPECT_NEAR(s.materials[0].emission[1], 2 * 0.841464, 2e-3);
  EXPECT_NEAR(s.materials[0].emission[2], 2 * 0.676385, 2e-3);
  EXPECT_FALSE(s.is_grey());
  // rd takes the colour current when rd is given, not a later one.
  s = parse("m x =\n c\n cxy 0.4 0.35\n rd 0.2\n c\n" + tri);
  EXPECT_NEAR(s.materials[0].reflectance[0], 0.2 * 1.502463, 1e-3);
  EXPECT_NEAR(s.materials[0].reflectance[2], 0.2 * 0.676385, 1e-3);
  // A saturated red with rd 0.5 exceeds 1 in R: desaturated towards the grey 0.5
  // until R = 1 (G = B = 0.5 (1 - t), t = 0.5 / 1.451411), and counted.
  s = parse("m x =\n c\n cxy 0.64 0.33\n rd 0.5\n" + tri);
  EXPECT_NEAR(s.materials[0].reflectance[0], 1.0, 1e-12);
  EXPECT_NEAR(s.materials[0].reflectance[1], 0.32775378, 1e-8);
  EXPECT_TRUE(has_warning(s, "1 colour(s) outside the RGB gamut (1 reflectance, 0 emission)"));
}

TEST(MgfColor, CmixMixesInXyzByLuminance) {
  const std::string tri = "v a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 1 0\nf a b d\n";
  // Equal luminances of red and green primaries: RGB proportional to 1/Y_r, 1/Y_g.
  const Scene s = parse(
      "c r =\n cxy 0.64 0.33\nc g =\n cxy 0.30 0.60\nm x =\n c mix =\n cmix 1 r 1 g\n "
      "rd 0.1\n" +
      tri);
  const Rgb red = xyY_to_linear_rgb(0.64, 0.33, 1), green = xyY_to_linear_rgb(0.3, 0.6, 1);
  const Rgb expect = 0.1 * (red + green) / 2;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.materials[0].reflectance[c], expect[c], 1e-9);
}

// ---- primitives -----------------------------------------------------------

TEST(MgfPrimitives, RingAreaEqualsItsTrapezoids) {
  for (int n : {8, 16, 33}) {
    const Scene s = parse(prelude() + "ring c 0.5 2\n", n);
    EXPECT_EQ(s.faces.size(), static_cast<std::size_t>(n));
    const double exact = 0.5 * n * std::sin(2 * kPi / n) * (4.0 - 0.25);
    EXPECT_NEAR(s.total_area(), exact, 1e-12 * exact);
    for (std::size_t f = 0; f < s.faces.size(); ++f) EXPECT_NEAR(s.face_normal(f).z(), 1.0, 1e-12);
  }
  // A disk (rmin = 0) is a fan of triangles, facing the vertex normal.
  const Scene d = parse(prelude("0 0 0", "0 -3 0") + "ring c 0 1\n", 16);
  EXPECT_EQ(d.faces.size(), 16u);
  for (const Face& f : d.faces) EXPECT_EQ(f.count, 3u);
  for (std::size_t f = 0; f < d.faces.size(); ++f) EXPECT_NEAR(d.face_normal(f).y(), -1.0, 1e-12);
  EXPECT_NEAR(d.total_area(), 8 * std::sin(2 * kPi / 16), 1e-12);
}

TEST(MgfPrimitives, CylinderAndConeLateralAreas) {
  const int n = 16;
  const double s_half = std::sin(kPi / n), c_half = std::cos(kPi / n);
  // Open cylinder r = 0.5 between z = 0 and z = 3: n rectangles of 2 r sin(pi/n) x 3.
  Scene s = parse(prelude() + "v top =\n p 0 0 3\ncyl c 0.5 top\n", n);
  EXPECT_EQ(s.faces.size(), 16u);
  EXPECT_NEAR(s.total_area(), n * 2 * 0.5 * s_half * 3, 1e-12);
  expect_facing(s, Vec3(0, 0, 1.5), true);
  // Negative radius: inward.
  s = parse(prelude() + "v top =\n p 0 0 3\ncyl c -0.5 top\n", n);
  expect_facing(s, Vec3(0, 0, 1.5), false);
  // Cone r 1 -> 0.25 over height 2: isosceles trapezoids; the slant between chord
  // midpoints is hypot(h, (r1 - r2) cos(pi/n)).
  s = parse(prelude() + "v top =\n p 0 0 2\ncone c 1 top 0.25\n", n);
  const double slant = std::hypot(2.0, 0.75 * c_half);
  EXPECT_NEAR(s.total_area(), n * (1.0 + 0.25) * s_half * slant, 1e-12);
  // A pointed cone: triangles.
  s = parse(prelude() + "v top =\n p 0 0 2\ncone c 1 top 0\n", n);
  for (const Face& f : s.faces) EXPECT_EQ(f.count, 3u);
  EXPECT_NEAR(s.total_area(), n * s_half * std::hypot(2.0, c_half), 1e-12);
}

TEST(MgfPrimitives, SphereConvergesToFourPiRSquared) {
  const double r = 2.0;
  double previous_error = 1.0;
  for (int n : {8, 16, 32}) {
    const Scene s = parse(prelude("1 2 3") + "sph c 2\n", n);
    const int bands = n / 2;
    EXPECT_EQ(s.faces.size(), static_cast<std::size_t>(n * bands));
    const double err = 1.0 - s.total_area() / (4 * kPi * r * r);
    EXPECT_GT(err, 0.0);  // inscribed: always a little smaller
    EXPECT_LT(err, previous_error / 3.0);
    previous_error = err;
    expect_facing(s, Vec3(1, 2, 3), true);
  }
  EXPECT_LT(previous_error, 0.01);  // n = 32: within 1%
  // n = 16 (the default) is within 4%.
  EXPECT_LT(1.0 - parse(prelude() + "sph c 1\n").total_area() / (4 * kPi), 0.04);
  // Negative radius: same surface, facing inward.
  const Scene in = parse(prelude("1 2 3") + "sph c -2\n");
  expect_facing(in, Vec3(1, 2, 3), false);
}

TEST(MgfPrimitives, PrismIsAClosedOutwardSolid) {
  const std::string base = "v a =\n p 0 0 0\nv b =\n p 0 1 0\nv d =\n p 1 1 0\nv e =\n p 1 0 0\n";
  // The base faces -z (right-hand rule), so the prism extends +z: a unit cube.
  Scene s = parse("m g =\n rd 0.5\n" + base + "prism a b d e 2\n");
  EXPECT_EQ(s.faces.size(), 6u);
  EXPECT_NEAR(s.total_area(), 2 * 1 + 4 * 2, 1e-12);
  EXPECT_NEAR(s.bounds().hi.z(), 2.0, 1e-12);
  expect_facing(s, Vec3(0.5, 0.5, 1), true);
  // Negative length: extruded the other way, every face inward.
  s = parse("m g =\n rd 0.5\n" + base + "prism a b d e -2\n");
  EXPECT_NEAR(s.bounds().lo.z(), -2.0, 1e-12);
  expect_facing(s, Vec3(0.5, 0.5, -1), false);
}

TEST(MgfPrimitives, TorusAreaApproachesFourPiSquaredRr) {
  // rmin 1, rmax 3: major radius 2, tube radius 1.
  const Scene s = parse(prelude() + "torus c 1 3\n", 32);
  EXPECT_EQ(s.faces.size(), 32u * 32u);
  const double ratio = s.total_area() / (4 * kPi * kPi * 2 * 1);
  EXPECT_GT(ratio, 0.99);
  EXPECT_LT(ratio, 1.0);
  EXPECT_NEAR(s.bounds().hi.z(), 1.0, 1e-9);
  double outer = 0;  // furthest distance from the axis: rmax, reached at every meridian
  for (const Vec3& v : s.vertices) outer = std::max(outer, std::hypot(v.x(), v.y()));
  EXPECT_NEAR(outer, 3.0, 1e-9);
}

// Directed edges (by vertex index) of the scene's faces: `unmatched` counts edges
// without exactly one reverse edge, `repeated` directed edges used twice. A closed,
// consistently oriented, watertight mesh has neither; an open one has only its rim
// unmatched. Vertex indices, not positions: the shapes share their points.
struct EdgeCount {
  std::size_t unmatched = 0, repeated = 0, edges = 0;
};
EdgeCount count_edges(const Scene& s) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const Face& f : s.faces)
    for (std::uint32_t k = 0; k < f.count; ++k)
      ++directed[{s.indices[f.first + k], s.indices[f.first + (k + 1) % f.count]}];
  EdgeCount c;
  for (const auto& [e, n] : directed) {
    c.edges += static_cast<std::size_t>(n);
    if (n > 1) ++c.repeated;
    const auto it = directed.find({e.second, e.first});
    if (it == directed.end() || it->second != 1) ++c.unmatched;
  }
  // Distinct vertices at one position would hide a crack from the index test.
  std::set<std::array<double, 3>> positions;
  for (const Vec3& v : s.vertices) positions.insert({v.x() + 0.0, v.y() + 0.0, v.z() + 0.0});
  EXPECT_EQ(positions.size(), s.vertices.size()) << "vertices repeated by position";
  return c;
}

TEST(MgfPrimitives, ClosedShapesAreWatertight) {
  const std::string base =
      "v a =\n p 0 0 0\nv b =\n p 0 2 0\nv d =\n p 1 2 0\nv e =\n p 1 1 0\nv f =\n p 2 1 0\n"
      "v g =\n p 2 0 0\n";
  // Odd and even counts; plain and under a rotating, scaling, mirroring transform.
  for (int n : {3, 7, 16, 33}) {
    for (const std::string xf : {"", "xf -rz 30 -s 2.5 -mx -t 1 2 3\n"}) {
      const std::string end = xf.empty() ? "" : "xf\n";
      for (const std::string& shape :
           {std::string("sph c 1.5\n"), std::string("sph c -1.5\n"), std::string("torus c 0.5 2\n"),
            std::string("torus c 0 2\n"), std::string("torus c -0.5 -2\n")}) {
        const Scene s = parse(prelude("1 1 1", "0.3 0.4 1") + xf + shape + end, n);
        const EdgeCount c = count_edges(s);
        EXPECT_EQ(c.unmatched, 0u) << shape << " n " << n << " " << xf;
        EXPECT_EQ(c.repeated, 0u) << shape << " n " << n;
        // No facet dropped as degenerate or sliver, none triangulated.
        EXPECT_FALSE(has_warning(s, "dropped") || has_warning(s, "triangulated"))
            << shape << " n " << n;
      }
    }
    // An L-shaped (concave) prism: SceneBuilder triangulates its ends over the same
    // vertices.
    const Scene p = parse("m g =\n rd 0.5\n" + base + "prism a b d e f g 1\n", n);
    const EdgeCount c = count_edges(p);
    EXPECT_EQ(c.unmatched, 0u);
    EXPECT_EQ(c.repeated, 0u);
  }
  // Every pole facet is a triangle on the one pole vertex: no zero-area slivers.
  const Scene s = parse(prelude() + "sph c 1\n", 16);
  int at_pole = 0;
  for (const Face& f : s.faces)
    for (std::uint32_t k = 0; k < f.count; ++k)
      if (s.vertices[s.indices[f.first + k]].z() == 1.0) {
        ++at_pole;
        EXPECT_EQ(f.count, 3u);
      }
  EXPECT_EQ(at_pole, 16);
}

TEST(MgfPrimitives, OpenShapesHaveOnlyTheirRimsOpen) {
  for (int n : {5, 16}) {
    // cyl and cone are open-ended (MGF: no caps): both end circles are the rim.
    Scene s = parse(prelude() + "v top =\n p 0 0 3\ncyl c 0.5 top\n", n);
    EdgeCount c = count_edges(s);
    EXPECT_EQ(c.unmatched, 2u * n);
    EXPECT_EQ(c.repeated, 0u);
    EXPECT_EQ(s.vertices.size(), 2u * n);  // the seam at 2 pi is the point at 0
    s = parse(prelude() + "v top =\n p 0 0 3\ncone c 0.5 top 0\n", n);
    c = count_edges(s);
    EXPECT_EQ(c.unmatched, 1u * n);  // the apex is one point
    EXPECT_EQ(s.vertices.size(), n + 1u);
    s = parse(prelude() + "ring c 0 1\n", n);
    EXPECT_EQ(count_edges(s).unmatched, 1u * n);
    s = parse(prelude() + "ring c 0.5 1\n", n);
    EXPECT_EQ(count_edges(s).unmatched, 2u * n);
  }
}

TEST(MgfSegments, RuleFollowsTheShapeAgainstTheScene) {
  // The rule itself: chords of at most 2 % of the diagonal, clamped to [16, 128].
  EXPECT_EQ(automatic_segments(0.001, 10), kMinSegments);
  EXPECT_EQ(automatic_segments(1e6, 10), kMaxSegments);
  EXPECT_EQ(automatic_segments(40 * 0.02 * 10 / (2 * kPi), 10), 40);
  EXPECT_EQ(automatic_segments(1, 0), kMinSegments);
  // A big sphere and a small one 10 apart: D from both spheres' exact extents.
  const std::string two = prelude() + "v far =\n p 10 0 0\nsph c 2\nsph far 0.1\n";
  const double diagonal = Vec3(12.1, 4, 4).norm();
  const int big = static_cast<int>(std::ceil(2 * kPi * 2 / (kSegmentEdge * diagonal)));
  ASSERT_EQ(big, 48);
  MgfOptions automatic;  // segments = 0
  const Scene s = parse_mgf(two, "t.mgf", automatic);
  EXPECT_EQ(s.faces.size(), static_cast<std::size_t>(big * big / 2 + 16 * 8));
  EXPECT_NEAR(s.bounds().diagonal(), diagonal, 1e-12);
  // Scale-invariant: the same scene 1000 times larger (and rotated) is cut the same.
  const Scene scaled = parse_mgf("xf -s 1000 -rx 30\n" + two + "xf\n", "t.mgf", automatic);
  EXPECT_EQ(scaled.faces.size(), s.faces.size());
  // A fixed count overrides the rule for every shape.
  EXPECT_EQ(parse(two, 16).faces.size(), 2u * 16 * 8);
  // Polygons keep their file order around the deferred shapes.
  const Scene order = parse_mgf(prelude() +
                                    "v a =\n p 5 5 5\nv b =\n p 6 5 5\nv d =\n p 5 6 5\n"
                                    "f a b d\nsph c 1\nf d b a\n",
                                "t.mgf", automatic);
  EXPECT_NEAR(order.face_normal(0).z(), 1.0, 1e-12);
  EXPECT_NEAR(order.face_normal(order.faces.size() - 1).z(), -1.0, 1e-12);
  EXPECT_NEAR(order.face_vertices(order.faces.size() - 1)[0].x(), 5.0, 1e-12);
}

TEST(MgfFiles, PrimitivesFileCountsEveryPiece) {
  MgfOptions sixteen;
  sixteen.segments = 16;
  const Scene s = read_mgf(data("primitives.mgf"), sixteen);
  // sph 16x8, cyl 16, cone 16, ring 16, torus 16x16, prism 6, emitting disk 16.
  EXPECT_EQ(s.faces.size(), 128u + 16 + 16 + 16 + 256 + 6 + 16);
  EXPECT_EQ(s.emitter_count(), 16u);
  EXPECT_EQ(s.name, "primitives");
}

// ---- files, transforms, includes ------------------------------------------

TEST(MgfFiles, BoxRoom) {
  const Scene s = read_mgf(data("box_room.mgf"));
  ASSERT_EQ(s.faces.size(), 6u);
  EXPECT_NEAR(s.total_area(), 6.0, 1e-12);
  EXPECT_EQ(s.emitter_count(), 1u);
  EXPECT_EQ(s.vertices.size(), 8u);  // named vertices are shared between faces
  expect_facing(s, Vec3(0.5, 0.5, 0.5), false);
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const Material& m = s.face_material(f);
    if (m.emits()) {
      EXPECT_NEAR(s.face_normal(f).z(), -1.0, 1e-12);
      EXPECT_DOUBLE_EQ(m.emission[2], 1.0);
    }
  }
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

TEST(MgfFiles, ArraysAndIncludes) {
  const Scene s = read_mgf(data("arrays.mgf"));
  // 3 (xf array) + 4 (include array, scaled 0.5) + 1 (nested xf).
  ASSERT_EQ(s.faces.size(), 8u);
  EXPECT_NEAR(s.total_area(), 3 + 4 * 0.25 + 1, 1e-12);
  int row = 0, grid = 0, rotated = 0;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    Aabb b;
    for (const Vec3& p : s.face_vertices(f)) b.extend(p);
    if (b.lo.z() > 4.9) {
      ++grid;
      EXPECT_TRUE(std::abs(b.lo.x()) < 1e-12 || std::abs(b.lo.x() - 1) < 1e-12);
      EXPECT_TRUE(std::abs(b.lo.y() - 10) < 1e-12 || std::abs(b.lo.y() - 11) < 1e-12);
      EXPECT_NEAR(b.extent().x(), 0.5, 1e-12);
    } else if (b.lo.x() > 18.9) {
      ++rotated;  // (x, y) -> (-y, x) after translating by (0, -20, 0)
      EXPECT_NEAR(b.lo.x(), 19.0, 1e-9);
      EXPECT_NEAR(b.hi.x(), 20.0, 1e-9);
      EXPECT_NEAR(b.lo.y(), 0.0, 1e-9);
    } else {
      ++row;
      EXPECT_NEAR(std::fmod(b.lo.x(), 2.0), 0.0, 1e-12);
    }
    EXPECT_NEAR(s.face_normal(f).z(), 1.0, 1e-12);
  }
  EXPECT_EQ(row, 3);
  EXPECT_EQ(grid, 4);
  EXPECT_EQ(rotated, 1);
}

TEST(MgfTransform, TranslateScaleRotateMirror) {
  const std::string tri = "m g =\n rd 0.5\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 2 0\n";
  Scene s = parse(tri + "xf -s 3 -t 10 0 0\nf a b d\nxf\n");
  EXPECT_NEAR(s.bounds().lo.x(), 10, 1e-12);
  EXPECT_NEAR(s.bounds().hi.x(), 13, 1e-12);
  EXPECT_NEAR(s.bounds().hi.y(), 6, 1e-12);
  EXPECT_NEAR(s.total_area(), 9.0, 1e-12);
  // Order matters: translate first, then scale.
  s = parse(tri + "xf -t 10 0 0 -s 3\nf a b d\nxf\n");
  EXPECT_NEAR(s.bounds().lo.x(), 30, 1e-12);
  // -rz 90 is counter-clockwise about +z: x -> y.
  s = parse(tri + "xf -rz 90\nf a b d\nxf\n");
  EXPECT_NEAR(s.bounds().hi.y(), 1, 1e-12);
  EXPECT_NEAR(s.bounds().lo.x(), -2, 1e-12);
  EXPECT_NEAR(s.face_normal(0).z(), 1, 1e-12);
  // -rx 90: y -> z; the normal +z turns to -y.
  s = parse(tri + "xf -rx 90\nf a b d\nxf\n");
  EXPECT_NEAR(s.bounds().hi.z(), 2, 1e-12);
  EXPECT_NEAR(s.face_normal(0).y(), -1, 1e-12);
  // Mirroring keeps the surface facing its mirror image: -mz turns +z into -z.
  s = parse(tri + "xf -mz\nf a b d\nxf\n");
  EXPECT_NEAR(s.face_normal(0).z(), -1, 1e-12);
  s = parse(tri + "xf -mx\nf a b d\nxf\n");
  EXPECT_NEAR(s.bounds().lo.x(), -1, 1e-12);
  EXPECT_NEAR(s.face_normal(0).z(), 1, 1e-12);
  // A mirrored sphere still faces outward.
  s = parse(prelude("5 0 0") + "xf -my\nsph c 1\nxf\n");
  expect_facing(s, Vec3(5, 0, 0), true);
  // Vertices are transformed when used, not when defined.
  s = parse(
      "m g =\n rd 0.5\nxf -t 0 0 7\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 1 0\n"
      "xf\nf a b d\n");
  EXPECT_NEAR(s.bounds().hi.z(), 0, 1e-12);
}

TEST(MgfTransform, RepeatAndMultiDimensionalArrays) {
  const std::string tri = "m g =\n rd 0.5\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 1 0\n";
  // -i 3 repeats the following translation three times.
  Scene s = parse(tri + "xf -i 3 -t 2 0 0\nf a b d\nxf\n");
  EXPECT_NEAR(s.bounds().lo.x(), 6, 1e-12);
  // A 2 x 3 array: 6 instances, on a grid.
  s = parse(tri + "xf -a 2 -t 5 0 0 -a 3 -t 0 5 0\nf a b d\nxf\n");
  EXPECT_EQ(s.faces.size(), 6u);
  EXPECT_NEAR(s.bounds().hi.x(), 6, 1e-12);
  EXPECT_NEAR(s.bounds().hi.y(), 11, 1e-12);
  // Arrays nest through xf contexts; entities after the array run once (the other
  // side of the first instance's triangle: the same side again would be a duplicate).
  s = parse(tri + "xf -a 2 -t 0 0 1\nxf -a 2 -t 3 0 0\nf a b d\nxf\nxf\nf a d b\n");
  EXPECT_EQ(s.faces.size(), 5u);
}

// ---- contexts -------------------------------------------------------------

TEST(MgfContexts, RedefinitionTemplatesAndDefaults) {
  // Faces before any `m` get the default grey, with a counted warning.
  Scene s = parse("v a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 1 0\nf a b d\nf a d b\n");
  EXPECT_EQ(s.materials[0].reflectance[0], 0.5);
  EXPECT_TRUE(has_warning(s, "2 face(s) named no material"));
  // `v b = a` copies a; redefining a after use does not move the first face.
  s = parse(
      "m g =\n rd 0.5\nv a =\n p 0 0 0\nv b = a\n p 1 0 0\nv d =\n p 0 1 0\nf a b d\n"
      "v a =\n p 0 0 5\nf a b d\n");
  ASSERT_EQ(s.faces.size(), 2u);
  EXPECT_NEAR(s.face_vertices(0)[0].z(), 0, 1e-12);
  EXPECT_NEAR(s.face_vertices(1)[0].z(), 5, 1e-12);
  // A material changed after use becomes a second Scene material; reselecting an
  // unchanged one does not.
  // (Four different triangles: a copy of an earlier polygon would be dropped.)
  s = parse(
      "m g =\n rd 0.5\nm h = g\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 1 0\n"
      "v e =\n p 1 1 0\nm g\nf a b d\nm h\nf a d b\nm g\nf b e d\n rd 0.25\nf b d e\n");
  ASSERT_EQ(s.faces.size(), 4u);
  EXPECT_EQ(s.faces[0].material, s.faces[2].material);
  EXPECT_EQ(s.face_material(1).name, "h");
  EXPECT_EQ(s.face_material(1).reflectance[0], 0.5);
  EXPECT_EQ(s.face_material(3).reflectance[0], 0.25);
  // A bare `m` is the unnamed black absorber.
  s = parse("m\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 1 0\nf a b d\n");
  EXPECT_EQ(s.materials[0].reflectance[0], 0.0);
}

TEST(MgfContexts, WarningsForUnknownAndIgnoredEntities) {
  const Scene s = parse(
      "m g =\n rd 0.5\n rs 0.1 0.02\n sides 1\n ir 1.5 0\n c\n cct 3000\nfoo 1 2\nfoo\nbar\n"
      "o thing\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 1 0\nf a b d\no\no\n");
  EXPECT_EQ(s.faces.size(), 1u);
  EXPECT_TRUE(has_warning(s, "3 unknown MGF entities ignored: bar (1), foo (2)"));
  EXPECT_TRUE(has_warning(s, "1 td/rs/ts value(s) ignored"));
  EXPECT_FALSE(has_warning(s, "cspec/cct"));  // cct is converted, not ignored
  EXPECT_TRUE(has_warning(s, "1 'o' end(s) without a begin"));
}

TEST(MgfContexts, ContinuationLinesAndCrLf) {
  const Scene s = parse(
      "m g =\r\n rd 0.5\r\nv a =\r\n p 0 \\\r\n 0 0\r\nv b =\n p 1 0 0\n"
      "v d =\n p 0 1 0\nf a \\\n b \\\n d\n");
  EXPECT_EQ(s.faces.size(), 1u);
  EXPECT_NEAR(s.total_area(), 0.5, 1e-12);
}

// ---- bad input ------------------------------------------------------------

void expect_error(const std::string& file, const std::string& in_file, int line,
                  const std::string& fragment) {
  try {
    read_mgf(data(file));
    ADD_FAILURE() << file << ": no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), data(in_file)) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(MgfErrors, EachBadFileNamesFileAndLine) {
  expect_error("bad/undefined_vertex.mgf", "bad/undefined_vertex.mgf", 6, "undefined vertex 'b'");
  expect_error("bad/not_a_number.mgf", "bad/not_a_number.mgf", 3, "'zero' is not a number");
  expect_error("bad/argument_count.mgf", "bad/argument_count.mgf", 4, "expected 2 argument(s)");
  expect_error("bad/undefined_material.mgf", "bad/undefined_material.mgf", 4,
               "undefined material 'missing'");
  expect_error("bad/missing_include.mgf", "bad/missing_include.mgf", 3, "cannot open included");
  expect_error("bad/recursive.mgf", "bad/recursive.mgf", 2, "nested deeper than 32");
  expect_error("bad/nan_coordinate.mgf", "bad/nan_coordinate.mgf", 4, "not a finite number");
  expect_error("bad/reflectance.mgf", "bad/reflectance.mgf", 3, "1.5 is outside [0, 1]");
  expect_error("bad/ies.mgf", "bad/ies.mgf", 2,
               "goniometric (IES LM-63) luminaires are not supported");
  expect_error("bad/cxy_outside.mgf", "bad/cxy_outside.mgf", 4, "is not a chromaticity");
  expect_error("bad/cspec_negative.mgf", "bad/cspec_negative.mgf", 4, "is negative");
  expect_error("bad/cct_low.mgf", "bad/cct_low.mgf", 3, "below 1000 K");
  expect_error("bad/xf_end.mgf", "bad/xf_end.mgf", 3, "without a matching xf begin");
  expect_error("bad/ring_normal.mgf", "bad/ring_normal.mgf", 4, "has no normal");
  expect_error("bad/include_error.mgf", "bad/sub/broken.inc", 3, "expected 3 argument(s)");
  expect_error("bad/huge_coordinate.mgf", "bad/huge_coordinate.mgf", 11, "beyond");
  expect_error("bad/open_array.mgf", "bad/open_array.mgf", 4, "not ended");
  expect_error("bad/array_count.mgf", "bad/array_count.mgf", 2, "outside [1, 100000]");
  expect_error("bad/xf_option.mgf", "bad/xf_option.mgf", 2, "unknown transform option '-q'");
  expect_error("bad/continued.mgf", "bad/continued.mgf", 4, "undefined vertex 'b'");
  expect_error("bad/empty.mgf", "bad/empty.mgf", 0, "no polygon");
  expect_error("no_such_file.mgf", "no_such_file.mgf", 0, "cannot open");
}

TEST(MgfErrors, MalformedPrimitivesAndLimits) {
  auto line_of = [](const std::string& text, MgfOptions o = {}) {
    try {
      parse_mgf(text, "t.mgf", o);
    } catch (const InputError& e) {
      return e.line();
    }
    return -1;
  };
  EXPECT_EQ(line_of(prelude() + "sph c 0\n"), 6);
  EXPECT_EQ(line_of(prelude() + "cone c 1 c 2\n"), 6);                    // coincident ends
  EXPECT_EQ(line_of(prelude() + "v t =\n p 0 0 1\ncone c 1 t -2\n"), 8);  // signs
  EXPECT_EQ(line_of(prelude() + "ring c 2 1\n"), 6);
  EXPECT_EQ(line_of(prelude() + "prism c c c 1\n"), 6);  // zero-area base
  EXPECT_EQ(line_of(prelude() + "cxy 0.7 0.5\n"), 6);
  EXPECT_EQ(line_of(prelude() + "sides 3\n"), 6);
  EXPECT_EQ(line_of(prelude() + "v\nf c c\n"), 7);
  // Work limit: a 1000 x 1000 array of spheres is refused, not ground through.
  MgfOptions small;
  small.max_work = 100000;
  EXPECT_EQ(line_of(prelude() + "xf -a 1000 -t 1 0 0 -a 1000 -t 0 1 0\nsph c 1\nxf\n", small), 7);
  // Instances: xf -a 100000 -a 100000 around one face grew past 4 GB; it is refused at
  // its xf line before anything is expanded, and so are nested arrays that multiply past
  // max_instances (the default, 1,000,000, is reached here by 1001 x 1000).
  const std::string face = "v a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 1 0\n";
  EXPECT_EQ(line_of(prelude() + face + "xf -a 100000 -a 100000\nf a b d\nxf\n"), 12);
  EXPECT_EQ(
      line_of(prelude() + face + "xf -a 1001 -t 1 0 0\nxf -a 1000 -t 0 1 0\nf a b d\nxf\nxf\n"),
      13);
  MgfOptions tiny;
  tiny.max_instances = 10;
  EXPECT_EQ(line_of(prelude() + face + "xf -a 5\nxf -a 3\nf a b d\nxf\nxf\n", tiny), 13);
  EXPECT_EQ(line_of(prelude() + face + "xf -a 5\nxf -a 2\nf a b d\nxf\nxf\n", tiny), -1);
  MgfOptions bad;
  bad.segments = 2;
  EXPECT_THROW(parse_mgf(prelude() + "sph c 1\n", "t.mgf", bad), std::invalid_argument);
}

}  // namespace
}  // namespace hrad
