#include "core/scene/scene_builder.h"
#include "core/scene/coplanar_overlap.h"
#include "core/scene/self_overlap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace hrad {
namespace {

const SourceLoc kHere{"test.obj", 7};

Material grey(double rho, double e = 0) {
  Material m;
  m.name = "m";
  m.reflectance = Rgb::Constant(rho);
  m.emission = Rgb::Constant(e);
  return m;
}

TEST(SceneBuilder, KeepsPlanarConvexQuadAsOnePolygon) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  const std::vector<Vec3> sq = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  b.add_polygon(sq, m, kHere);
  const Scene s = b.finish("test.obj");
  ASSERT_EQ(s.faces.size(), 1u);
  EXPECT_EQ(s.faces[0].count, 4u);
  EXPECT_DOUBLE_EQ(s.total_area(), 1.0);
  EXPECT_TRUE(s.warnings.empty());
}

// Per channel, the lamps' powers add up; the largest-channel sum takes each face's
// largest channel first, so a red and a blue lamp count both.
TEST(SceneBuilder, EmittedPowerPerChannelAndLargestChannel) {
  SceneBuilder b("t", "t");
  Material red = grey(0.5), blue = grey(0.5);
  red.name = "red";
  red.emission = Rgb(2, 0, 0);
  blue.name = "blue";
  blue.emission = Rgb(0, 0, 3);
  const auto r = b.add_material(red, kHere), u = b.add_material(blue, kHere);
  b.add_polygon(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, r, kHere);
  b.add_polygon(std::vector<Vec3>{{0, 0, 1}, {2, 0, 1}, {0, 1, 1}}, u, kHere);  // area 1
  const Scene s = b.finish("test.obj");
  EXPECT_DOUBLE_EQ(s.emitted_power()[0], 2.0);
  EXPECT_DOUBLE_EQ(s.emitted_power()[1], 0.0);
  EXPECT_DOUBLE_EQ(s.emitted_power()[2], 3.0);
  EXPECT_DOUBLE_EQ(s.max_channel_emitted_power(), 5.0);
}

TEST(SceneBuilder, TriangulatesConcavePolygonPreservingArea) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  // An L shape of area 3.
  const std::vector<Vec3> l = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  b.add_polygon(l, m, kHere);
  const Scene s = b.finish("test.obj");
  EXPECT_EQ(s.faces.size(), 4u);
  for (const Face& f : s.faces) EXPECT_EQ(f.count, 3u);
  EXPECT_NEAR(s.total_area(), 3.0, 1e-12);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("1 non-planar or non-convex"), std::string::npos);
}

// MGF and many modellers write a face with a hole as one loop that walks in to the
// hole along a seam and back out: 4x4 wall, 2x2 window, area 12.
// A comb of 2,000 teeth (8,002 corners, most of its corners reflex): ear clipping
// walks on from its last cut and looks only at the reflex corners near each ear, and
// the triangles keep the area exactly.
TEST(SceneBuilder, TriangulatesALargeCombExactly) {
  constexpr int kTeeth = 2000;
  std::vector<Vec3> comb = {{0, 0, 0}, {2.0 * kTeeth, 0, 0}};
  for (int t = kTeeth - 1; t >= 0; --t) {
    const double x = 2.0 * t;
    comb.insert(comb.end(), {{x + 1.5, 1, 0}, {x + 1.5, 3, 0}, {x + 0.5, 3, 0}, {x + 0.5, 1, 0}});
  }
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  b.add_polygon(comb, m, kHere);
  const Scene s = b.finish("test.obj");
  EXPECT_EQ(s.faces.size(), comb.size() - 2);
  // The bar (a trapezoid: its ends slant to the outer teeth) and the teeth, 1 x 2 each.
  EXPECT_NEAR(s.total_area(), (2.0 * kTeeth - 0.5) + 2.0 * kTeeth, 1e-6);
  EXPECT_NEAR(s.total_area(), polygon_area(comb), 1e-6);
}

// A comb of 20,000 teeth 500 long (80,002 corners): the ears that span its base are
// long slanted triangles whose boxes cover nearly every reflex corner without holding
// one. A grid of the corners, and a k-d tree asked for the box, tested each of those
// corners for each such ear (a comb of 200,002 corners took minutes); the tree asked
// for the triangle visits only nodes near its edges.
TEST(SceneBuilder, TriangulatesACombWithLongTeethExactly) {
  constexpr int kTeeth = 20000;
  constexpr double kLong = 500;
  std::vector<Vec3> comb = {{0, 0, 0}, {2.0 * kTeeth, 0, 0}};
  for (int t = kTeeth - 1; t >= 0; --t) {
    const double x = 2.0 * t;
    comb.insert(
        comb.end(),
        {{x + 1.5, 1, 0}, {x + 1.5, 1 + kLong, 0}, {x + 0.5, 1 + kLong, 0}, {x + 0.5, 1, 0}});
  }
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  b.add_polygon(comb, m, kHere);
  const Scene s = b.finish("test.obj");
  EXPECT_EQ(s.faces.size(), comb.size() - 2);
  EXPECT_NEAR(s.total_area(), polygon_area(comb), 1e-6 * polygon_area(comb));
  EXPECT_NEAR(s.total_area(), (2.0 * kTeeth - 0.5) + kLong * kTeeth, 1e-3);
}

TEST(SceneBuilder, TriangulatesPolygonWithSeamHole) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  const std::vector<Vec3> outer = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}};
  const std::vector<Vec3> hole = {{1, 1, 0}, {1, 3, 0}, {3, 3, 0}, {3, 1, 0}};  // clockwise
  std::vector<std::uint32_t> o, h;
  for (const Vec3& p : outer) o.push_back(b.add_vertex(p, kHere));
  for (const Vec3& p : hole) h.push_back(b.add_vertex(p, kHere));
  const std::vector<std::uint32_t> loop = {o[0], o[1], o[2], o[3], h[0],
                                           h[1], h[2], h[3], h[0], o[3]};
  b.add_polygon(loop, m, kHere);
  const Scene s = b.finish("f");
  EXPECT_NEAR(s.total_area(), 12.0, 1e-12);
  for (std::size_t f = 0; f < s.faces.size(); ++f)
    EXPECT_GT(s.face_normal(f).z(), 0.99) << "a triangle flipped";
}

TEST(SceneBuilder, TriangulatesNonPlanarQuad) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  const std::vector<Vec3> bent = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.3}, {0, 1, 0}};
  b.add_polygon(bent, m, kHere);
  EXPECT_EQ(b.finish("f").faces.size(), 2u);
}

TEST(SceneBuilder, DropsAndCountsDegenerateFaces) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  const std::vector<Vec3> ok = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<Vec3> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const std::vector<Vec3> point = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  b.add_polygon(ok, m, kHere);
  b.add_polygon(line, m, kHere);
  b.add_polygon(point, m, kHere);
  const Scene s = b.finish("f");
  EXPECT_EQ(s.faces.size(), 1u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("2 degenerate"), std::string::npos);
}

// A huge thin sliver (1000 long, 1e-10 wide) is dropped as a sliver, not called
// zero-area.
TEST(SceneBuilder, CallsSliversSlivers) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  const std::vector<Vec3> ok = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<Vec3> sliver = {{0, 0, 0}, {1000, 0, 0}, {1000, 1e-10, 0}, {0, 1e-10, 0}};
  b.add_polygon(ok, m, kHere);
  b.add_polygon(sliver, m, kHere);
  const Scene s = b.finish("f");
  EXPECT_EQ(s.faces.size(), 1u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("1 sliver face(s) dropped"), std::string::npos) << s.warnings[0];
}

// A polygon repeating an earlier one (the same positions in the same cyclic order,
// from any starting vertex, by other vertex indices or through -0) is dropped and
// counted: both copies would reflect and emit. The reverse order (the other side of a
// sheet) and a shifted copy are other polygons.
TEST(SceneBuilder, DropsAndCountsDuplicateFaces) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  const std::vector<Vec3> sq = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<Vec3> rotated = {{1, 1, 0}, {0, 1, 0}, {-0.0, 0, 0}, {1, 0, 0}};
  const std::vector<Vec3> reversed = {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
  const std::vector<Vec3> shifted = {{0, 0, 1e-9}, {1, 0, 1e-9}, {1, 1, 1e-9}, {0, 1, 1e-9}};
  b.add_polygon(sq, m, kHere);
  b.add_polygon(sq, m, kHere);
  b.add_polygon(rotated, m, kHere);
  b.add_polygon(reversed, m, kHere);
  b.add_polygon(shifted, m, kHere);
  const std::uint32_t same[4] = {0, 1, 2, 3};  // the first polygon's own vertices again
  b.add_polygon(same, m, kHere);
  const Scene s = b.finish("f");
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_NE(s.warnings[0].find("3 duplicate face(s) dropped"), std::string::npos) << s.warnings[0];
  // The copy shifted by 1e-9 is not a repeat, but lies in the first one's plane, under
  // it: cut away as an overlap (CutsCoplanarFacesThatOverlapOutOfTheLaterFace).
  EXPECT_NE(s.warnings[1].find("1 lay wholly under earlier faces"), std::string::npos)
      << s.warnings[1];
  EXPECT_EQ(s.faces.size(), 2u);
  EXPECT_DOUBLE_EQ(s.total_area(), 2.0);
}

// Polygons that cover part of their area twice or with both orientations are dropped,
// each counted, the first named by file and line; simple ones, convex or not, with a
// seam hole or with thousands of corners, are kept with their area.
std::string overlap_warning(const Scene& s) {
  for (const std::string& w : s.warnings)
    if (w.find("self-overlapping") != std::string::npos) return w;
  return "";
}

Scene one_polygon(const std::vector<Vec3>& p) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  b.add_polygon(p, m, kHere);
  b.add_polygon(std::vector<Vec3>{{0, 0, 5}, {1, 0, 5}, {0, 1, 5}}, m, {"test.obj", 9});
  return b.finish("test.obj");
}

TEST(SceneBuilder, DropsSelfOverlappingPolygonsNamingTheFirst) {
  // A unit square wound round twice: the vector area says 2.
  const std::vector<Vec3> twice = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_DOUBLE_EQ(polygon_area(twice), 2.0);
  Scene s = one_polygon(twice);
  EXPECT_EQ(s.faces.size(), 1u);  // the triangle only
  EXPECT_NE(overlap_warning(s).find("1 self-overlapping polygon(s) dropped (the first at "
                                    "test.obj:7: edge 5 runs along edge 1 again)"),
            std::string::npos)
      << overlap_warning(s);
  // A pentagram: every turn goes the same way, but it winds twice round its centre.
  std::vector<Vec3> star;
  for (int i = 0; i < 5; ++i) {
    const double a = 2 * 3.141592653589793 * (2 * i) / 5;
    star.emplace_back(std::cos(a), std::sin(a), 0);
  }
  s = one_polygon(star);
  EXPECT_EQ(s.faces.size(), 1u);
  EXPECT_NE(overlap_warning(s).find("test.obj:7: edges 1 and 3 cross"), std::string::npos)
      << overlap_warning(s);
  // A bow-tie: its two lobes cancel, so its vector area is 0; it is no sliver.
  s = one_polygon({{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}});
  EXPECT_EQ(s.faces.size(), 1u);
  EXPECT_NE(overlap_warning(s).find("edges 1 and 3 cross"), std::string::npos);
  for (const std::string& w : s.warnings) EXPECT_EQ(w.find("sliver"), std::string::npos) << w;
  // Two of them: counted, the first named.
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  b.add_polygon(star, m, {"a.obj", 3});
  b.add_polygon(twice, m, {"a.obj", 4});
  b.add_polygon(std::vector<Vec3>{{0, 0, 5}, {1, 0, 5}, {0, 1, 5}}, m, kHere);
  EXPECT_NE(overlap_warning(b.finish("a.obj"))
                .find("2 self-overlapping polygon(s) dropped (the "
                      "first at a.obj:3: edges 1 and 3 cross)"),
            std::string::npos);
}

TEST(SceneBuilder, KeepsSimplePolygonsThatTouchThemselves) {
  // A square with a square hole, written as one loop with a seam (MGF's way): the seam
  // runs both ways and the hole's corners repeat, but nothing crosses.
  const std::vector<Vec3> holed = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {0, 0, 0},
                                   {1, 1, 0}, {1, 3, 0}, {3, 3, 0}, {3, 1, 0}, {1, 1, 0}};
  Scene s = one_polygon(holed);
  EXPECT_EQ(overlap_warning(s), "");
  EXPECT_NEAR(s.total_area(), 16 - 4 + 0.5, 1e-12);
  // A circle of 20,000 corners (the binned test) is kept whole; the same circle with two
  // corners swapped crosses itself, and the crossing is found.
  std::vector<Vec3> circle;
  constexpr int kN = 20000;
  for (int i = 0; i < kN; ++i) {
    const double a = 2 * 3.141592653589793 * i / kN;
    circle.emplace_back(std::cos(a), std::sin(a), 0);
  }
  EXPECT_EQ(overlap_warning(one_polygon(circle)), "");
  std::swap(circle[100], circle[101]);
  EXPECT_NE(overlap_warning(one_polygon(circle)).find("edges 100 and 102 cross"), std::string::npos)
      << overlap_warning(one_polygon(circle));
}

// A star of many thin spikes: its slanted edges' boxes each cover dozens of the
// crossing test's grid cells, and each cell holds dozens of edges. The grid tested every
// pair in every cell it shared: 50,000 corners took seconds, 200,000 over a minute. The
// sweep takes a fraction of a second at 200,000, with or without a crossing.
std::vector<Vec3> star(int corners) {
  std::vector<Vec3> p;
  for (int i = 0; i < corners; ++i) {
    const double a = 2 * 3.141592653589793 * i / corners, r = i % 2 == 0 ? 1.0 : 0.9;
    p.emplace_back(r * std::cos(a), 0, -r * std::sin(a));
  }
  return p;
}

// Its time is hrad_micro_bench's SelfOverlapStar (a test must not time itself); here the
// answers, on a star big enough that the grid's minutes would run past the test's
// timeout.
TEST(SceneBuilder, ChecksAManyPointedStarForCrossings) {
  std::vector<Vec3> p = star(200000);
  EXPECT_FALSE(find_self_overlap(p).found);
  std::swap(p[5000], p[5002]);  // two outer corners: spikes cross their neighbours
  const SelfOverlap o = find_self_overlap(p);
  EXPECT_TRUE(o.found);
  EXPECT_NE(o.what.find("cross"), std::string::npos) << o.what;
  // The whole load, triangulation included.
  const std::vector<Vec3> s = star(50000);
  const Scene scene = one_polygon(s);
  EXPECT_EQ(scene.faces.size(), s.size() - 2 + 1);  // and one_polygon's triangle
}

// More corners than kMaxPolygonVertices: refused with the file, line and count before
// any work on the polygon.
TEST(SceneBuilder, RefusesAPolygonWithTooManyCorners) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  std::vector<std::uint32_t> idx;
  for (int i = 0; i < 3; ++i) idx.push_back(b.add_vertex(Vec3(i, i * i, 0), kHere));
  idx.resize(kMaxPolygonVertices + 1, idx[0]);
  try {
    b.add_polygon(idx, m, SourceLoc{"big.obj", 12});
    FAIL() << "not refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("big.obj:12: a face of 1048577 vertices: at most 1048576"),
              std::string::npos)
        << e.what();
  }
}

// A floor given again as two triangles was solved as a second floor (probes 35-48 %
// too bright) without a word. What a later face shares with an earlier one in its
// plane, facing the same way, is cut out of the later face: the covered area counts
// once, the rest stays as convex pieces with the later face's material, and the cut is
// reported with the area. The reversed face (a sheet's other side), faces that only
// touch along an edge and a parallel plane are left alone; small overlaps (below 1e-3
// of the scene's area) are cut without a report.
TEST(SceneBuilder, CutsCoplanarFacesThatOverlapOutOfTheLaterFace) {
  const auto build = [](const std::vector<std::vector<Vec3>>& polys, double later_emits = 0) {
    SceneBuilder b("t", "t");
    const auto m = b.add_material(grey(0.5, 1), kHere);
    const auto lit = b.add_material(grey(0.5, later_emits), kHere);
    for (std::size_t i = 0; i < polys.size(); ++i) b.add_polygon(polys[i], i == 0 ? m : lit, kHere);
    return b.finish("test.obj");
  };
  const auto warning = [](const Scene& s, const char* what) {
    for (const std::string& w : s.warnings)
      if (w.find(what) != std::string::npos) return w;
    return std::string();
  };
  const char* cut = "lay in one plane with an earlier face";
  const std::vector<Vec3> floor = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  const std::vector<Vec3> t1 = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}},
                          t2 = {{0, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  // The floor again as two triangles: both lie under it and go.
  Scene s = build({floor, t1, t2}, 7.0);
  EXPECT_EQ(s.faces.size(), 1u);
  EXPECT_DOUBLE_EQ(s.total_area(), 4.0);
  EXPECT_EQ(s.emitter_count(), 1u);  // the first face's material: the floor's own emission
  std::string w = warning(s, cut);
  EXPECT_NE(w.find("2 face(s) lay in one plane with an earlier face, facing the same way, and "
                   "overlapped it (4 units² in common"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("2 lay wholly under earlier faces and were dropped"), std::string::npos) << w;
  EXPECT_EQ(warning(s, "lie in one plane"), "");  // nothing left to report
  // Half of the floor again, shifted: 2 units² shared, the other half kept, with the
  // later face's emission, in the later face's orientation.
  s = build({floor, {{1, 0, 0}, {3, 0, 0}, {3, 2, 0}, {1, 2, 0}}}, 7.0);
  EXPECT_NEAR(s.total_area(), 6.0, 1e-12);
  ASSERT_EQ(s.faces.size(), 2u);
  EXPECT_NEAR(s.face_area(1), 2.0, 1e-12);
  EXPECT_NEAR(s.face_normal(1).z(), 1.0, 1e-12);
  EXPECT_NEAR(s.emitted_power()[0], 7.0 * 2.0 + 1.0 * 4.0, 1e-9);
  w = warning(s, cut);
  EXPECT_NE(w.find("1 face(s)"), std::string::npos) << w;
  EXPECT_NE(w.find("(2 units² in common"), std::string::npos) << w;
  EXPECT_NE(w.find("kept as 1 convex piece(s)"), std::string::npos) << w;
  // A square over the middle of the floor's edge: an L-shaped remains, in convex
  // pieces, of the right area; later faces are cut by every earlier one (a third face
  // over both loses what either covers).
  s = build({floor,
             {{1, 1, 0}, {3, 1, 0}, {3, 3, 0}, {1, 3, 0}},
             {{0.5, 0.5, 0}, {2.5, 0.5, 0}, {2.5, 2.5, 0}, {0.5, 2.5, 0}}});
  EXPECT_NEAR(s.total_area(), 4.0 + 3.0 + (4.0 - 2.25 - 1.25), 1e-9);
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    EXPECT_GT(s.face_area(f), 0);
    EXPECT_NEAR(s.face_normal(f).z(), 1.0, 1e-12);
  }
  EXPECT_EQ(warning(s, "lie in one plane"), "");
  // Left alone: the other side, a neighbour along an edge, a parallel plane.
  for (const std::vector<Vec3>& other :
       {std::vector<Vec3>{{0, 0, 0}, {0, 2, 0}, {2, 2, 0}, {2, 0, 0}},
        std::vector<Vec3>{{2, 0, 0}, {4, 0, 0}, {4, 2, 0}, {2, 2, 0}},
        std::vector<Vec3>{{0, 0, 1e-3}, {2, 0, 1e-3}, {2, 2, 1e-3}, {0, 2, 1e-3}}}) {
    s = build({floor, other});
    EXPECT_EQ(s.faces.size(), 2u);
    EXPECT_NEAR(s.total_area(), 8.0, 1e-12);
    EXPECT_EQ(warning(s, cut), "");
  }
  // A tiny overlap in a large scene is cut, below the report's share.
  s = build({{{0, 0, 0}, {100, 0, 0}, {100, 100, 0}, {0, 100, 0}},
             {{0, 0, 5}, {0.1, 0, 5}, {0.1, 0.1, 5}},
             {{0, 0, 5}, {0.1, 0, 5}, {0.1, 0.1, 5}, {0, 0.1, 5}}});
  EXPECT_EQ(warning(s, cut), "");
  EXPECT_NEAR(s.total_area(), 1e4 + 0.01, 1e-9);
}

// A face that would need more than kMaxOverlapPieces pieces is left whole, and each
// pair it makes with an earlier face is reported, from the same pass that cuts.
TEST(SceneBuilder, ReportsOverlapsItCannotCut) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      const double x = i / 12.0 + 0.02, y = j / 12.0 + 0.02;
      b.add_polygon(
          std::vector<Vec3>{{x, y, 0}, {x + 0.04, y, 0}, {x + 0.04, y + 0.04, 0}, {x, y + 0.04, 0}},
          m, kHere);
    }
  b.add_polygon(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, m, kHere);
  const Scene s = b.finish("t.obj");
  EXPECT_EQ(s.faces.size(), 145u);
  EXPECT_NEAR(s.total_area(), 1.0 + 144 * 0.0016, 1e-9);
  bool reported = false;
  for (const std::string& w : s.warnings)
    if (w.find("144 pair(s) of faces lie in one plane") != std::string::npos &&
        w.find("(0.23 units² in common") != std::string::npos)
      reported = true;
  EXPECT_TRUE(reported) << (s.warnings.empty() ? "" : s.warnings.front());
}

// Called without the input polygons, every face counts as its own: a copy of a face
// appended to a finished scene is cut away.
TEST(SceneBuilder, CutsOverlapsWithoutInputPolygons) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5, 1), kHere);
  b.add_polygon(std::vector<Vec3>{{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}}, m, kHere);
  b.add_polygon(std::vector<Vec3>{{0, 0, 1}, {0, 2, 1}, {2, 2, 1}, {2, 0, 1}}, m, kHere);
  Scene s = b.finish("t.obj");
  Face copy = s.faces[0];
  s.faces.push_back(copy);
  std::vector<std::uint32_t> source;
  const CoplanarCuts c = remove_coplanar_overlaps(s, source);
  EXPECT_EQ(c.faces_cut, 1u);
  EXPECT_EQ(c.faces_dropped, 1u);
  EXPECT_NEAR(c.area, 4.0, 1e-12);
  EXPECT_EQ(s.faces.size(), 2u);
  EXPECT_EQ(source.size(), 2u);
}

TEST(SceneBuilder, RejectsBadVerticesWithFileAndLine) {
  SceneBuilder b("t", "t");
  try {
    b.add_vertex(Vec3(0, std::nan(""), 0), kHere);
    FAIL() << "NaN accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "test.obj");
    EXPECT_EQ(e.line(), 7);
    EXPECT_STREQ(e.what(), "test.obj:7: coordinate is NaN");
  }
  EXPECT_THROW(b.add_vertex(Vec3(1e31, 0, 0), kHere), InputError);
  EXPECT_THROW(b.add_vertex(Vec3(0, 0, -HUGE_VAL), kHere), InputError);
  EXPECT_NO_THROW(b.add_vertex(Vec3(1e29, 0, 0), kHere));
}

TEST(SceneBuilder, RejectsReflectanceOutsideUnitInterval) {
  SceneBuilder b("t", "t");
  EXPECT_THROW(b.add_material(grey(1.2), kHere), InputError);
  EXPECT_THROW(b.add_material(grey(-0.1), kHere), InputError);
  EXPECT_THROW(b.add_material(grey(0.5, -1), kHere), InputError);
  EXPECT_NO_THROW(b.add_material(grey(1.0), kHere));
  EXPECT_NO_THROW(b.add_material(grey(0.0), kHere));
}

TEST(SceneBuilder, RejectsOutOfRangeIndexAndShortFaces) {
  SceneBuilder b("t", "t");
  const auto m = b.add_material(grey(0.5), kHere);
  b.add_vertex(Vec3(0, 0, 0), kHere);
  b.add_vertex(Vec3(1, 0, 0), kHere);
  b.add_vertex(Vec3(0, 1, 0), kHere);
  const std::uint32_t bad[3] = {0, 1, 3};
  EXPECT_THROW(b.add_polygon(bad, m, kHere), InputError);
  const std::uint32_t two[2] = {0, 1};
  EXPECT_THROW(b.add_polygon(two, m, kHere), InputError);
}

TEST(SceneBuilder, EmptySceneIsAnErrorAndDarkSceneAWarning) {
  SceneBuilder empty("t", "t");
  EXPECT_THROW(empty.finish("empty.obj"), InputError);

  SceneBuilder dark("t", "t");
  const std::vector<Vec3> tri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  dark.add_polygon(tri, dark.default_material(), kHere);
  const Scene s = dark.finish("f");
  EXPECT_EQ(s.emitter_count(), 0u);
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_NE(s.warnings[0].find("1 face(s) named no material"), std::string::npos);
  EXPECT_NE(s.warnings[1].find("no face emits"), std::string::npos);
}

}  // namespace
}  // namespace hrad
