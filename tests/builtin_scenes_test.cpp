#include "core/scene/builtin_scenes.h"

#include "core/base/input_error.h"
#include "core/scene/builtin/shapes.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

namespace hrad {
namespace {

using builtin::Facing;
using builtin::Frame;
using builtin::Shapes;

// --- helpers ---------------------------------------------------------------------

/// Signed volume enclosed by the given faces (divergence theorem; exact for closed
/// surfaces of planar faces): positive when they face outward.
double signed_volume(const Scene& s, const std::vector<std::size_t>& faces) {
  double v = 0;
  for (std::size_t f : faces) {
    const std::vector<Vec3> p = s.face_vertices(f);
    v += p[0].dot(vector_area(p)) / 3.0;
  }
  return v;
}

std::vector<std::size_t> all_faces(const Scene& s) {
  std::vector<std::size_t> f(s.faces.size());
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = i;
  return f;
}

/// Closed and consistently oriented: every directed edge a->b (by exact coordinates)
/// occurs once, and so does b->a. Returns the number of edges that break this.
std::size_t unpaired_edges(const Scene& s, const std::vector<std::size_t>& faces) {
  using Key = std::array<double, 6>;
  std::map<Key, int> directed;
  auto key = [](const Vec3& a, const Vec3& b) {
    return Key{a.x(), a.y(), a.z(), b.x(), b.y(), b.z()};
  };
  for (std::size_t f : faces) {
    const std::vector<Vec3> p = s.face_vertices(f);
    for (std::size_t i = 0; i < p.size(); ++i) ++directed[key(p[i], p[(i + 1) % p.size()])];
  }
  std::size_t bad = 0;
  for (const auto& [k, n] : directed) {
    const Key rev{k[3], k[4], k[5], k[0], k[1], k[2]};
    const auto it = directed.find(rev);
    if (n != 1 || it == directed.end() || it->second != 1) ++bad;
  }
  return bad;
}

std::vector<std::size_t> faces_of(const Scene& s, const std::string& material) {
  std::vector<std::size_t> out;
  for (std::size_t f = 0; f < s.faces.size(); ++f)
    if (s.face_material(f).name == material) out.push_back(f);
  return out;
}

/// The cabin's fuselage circle (radius, centre height) through its top vertex and
/// its two floor-level vertices (exact for an even number of segments).
std::pair<double, double> hull_circle(const Scene& s) {
  double top = 0, w = 0;
  for (std::size_t f : faces_of(s, "fuselage"))
    for (const Vec3& v : s.face_vertices(f)) {
      top = std::max(top, v.y());
      if (std::abs(v.y()) < 1e-9) w = std::max(w, std::abs(v.x()));
    }
  const double yc = (top * top - w * w) / (2 * top);
  return {top - yc, yc};
}

Aabb bounds_of(const Scene& s, const std::vector<std::size_t>& faces) {
  Aabb b;
  for (std::size_t f : faces)
    for (const Vec3& p : s.face_vertices(f)) b.extend(p);
  return b;
}

/// Builds a scene from shapes drawn by `draw`, for the helper tests.
template <class Draw>
Scene shapes_scene(Draw draw, bool triangles = false) {
  SceneBuilder b("shapes", "test");
  Shapes s(b, "test");
  s.set_triangles(triangles);
  const auto m = s.material("m", Rgb::Constant(0.5), Rgb::Constant(1));
  draw(s, m);
  return b.finish("test");
}

// --- registry and spec parsing -----------------------------------------------------

TEST(BuiltinRegistry, ListsEveryScene) {
  std::vector<std::string> names;
  for (const BuiltinInfo& i : builtin_scenes()) {
    names.push_back(i.name);
    EXPECT_FALSE(i.description.empty()) << i.name;
    for (const BuiltinParam& p : i.params) {
      EXPECT_LE(p.min_value, p.default_value) << i.name << "." << p.name;
      EXPECT_LE(p.default_value, p.max_value) << i.name << "." << p.name;
      EXPECT_FALSE(p.meaning.empty()) << i.name << "." << p.name;
      if (p.integer) {
        EXPECT_EQ(p.default_value, std::floor(p.default_value)) << p.name;
      }
    }
  }
  EXPECT_EQ(names, (std::vector<std::string>{"cornell", "furnace", "office", "lab", "cabin"}));
}

TEST(BuiltinRegistry, RecognisesSpecs) {
  EXPECT_TRUE(is_builtin_spec("builtin:office?desks=3"));
  EXPECT_TRUE(is_builtin_spec("builtin:nosuch"));
  EXPECT_FALSE(is_builtin_spec("office.obj"));
  EXPECT_FALSE(is_builtin_spec("Builtin:office"));
}

/// The message of the InputError thrown for `spec` (fails when none is thrown).
std::string error_for(const std::string& spec) {
  try {
    make_builtin(spec);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), spec);
    EXPECT_EQ(e.line(), 0);
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << spec;
  return "";
}

TEST(BuiltinRegistry, RejectsBadSpecs) {
  const auto has = [](const std::string& msg, const std::string& part) {
    return msg.find(part) != std::string::npos;
  };
  std::string m = error_for("builtin:nosuch");
  EXPECT_TRUE(has(m, "unknown builtin scene 'nosuch'")) << m;
  EXPECT_TRUE(has(m, "cornell, furnace, office, lab, cabin")) << m;
  m = error_for("builtin:office?chairs=3");
  EXPECT_TRUE(has(m, "unknown parameter 'chairs'")) << m;
  EXPECT_TRUE(has(m, "desks, lights, seed")) << m;
  EXPECT_TRUE(has(error_for("builtin:office?desks=abc"), "not a number"));
  EXPECT_TRUE(has(error_for("builtin:office?desks="), "not a number"));
  EXPECT_TRUE(has(error_for("builtin:office?desks=3x"), "not a number"));
  EXPECT_TRUE(has(error_for("builtin:furnace?rho=nan"), "not a number"));
  EXPECT_TRUE(has(error_for("builtin:furnace?emission=inf"), "not a number"));
  EXPECT_TRUE(has(error_for("builtin:office?desks=2.5"), "not an integer"));
  EXPECT_TRUE(has(error_for("builtin:office?desks=0"), "outside [1, 2000]"));
  EXPECT_TRUE(has(error_for("builtin:furnace?rho=1.01"), "outside [0, 1]"));
  EXPECT_TRUE(has(error_for("builtin:furnace?rho=-0.1"), "outside"));
  EXPECT_TRUE(has(error_for("builtin:office?desks=3&desks=4"), "given twice"));
  EXPECT_TRUE(has(error_for("builtin:office?desks"), "name=value"));
  EXPECT_TRUE(has(error_for("builtin:office?desks=3&"), "empty parameter"));
  EXPECT_TRUE(has(error_for("office"), "builtin:"));
}

TEST(BuiltinRegistry, AcceptsGoodParameters) {
  const Scene s = make_builtin("builtin:furnace?rho=0.25&emission=3&size=2.5e0&objects=0");
  EXPECT_EQ(s.name, "furnace");
  EXPECT_EQ(s.source, "builtin:furnace?rho=0.25&emission=3&size=2.5e0&objects=0");
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].reflectance[0], 0.25);
  EXPECT_EQ(s.materials[0].emission[0], 3.0);
  EXPECT_EQ(s.bounds().hi, Vec3::Constant(2.5));
  EXPECT_EQ(s.polygon_count(), 6u);
}

// The comma form needs no quoting in a shell; the '?'/'&' form still works, and the two
// may be mixed. Either way the scene is the same.
TEST(BuiltinRegistry, CommaFormMatchesQueryForm) {
  const Scene comma = make_builtin("builtin:furnace,rho=0.25,emission=3,objects=0");
  const Scene query = make_builtin("builtin:furnace?rho=0.25&emission=3&objects=0");
  const Scene mixed = make_builtin("builtin:furnace?rho=0.25,emission=3&objects=0");
  EXPECT_EQ(comma.source, "builtin:furnace,rho=0.25,emission=3,objects=0");
  for (const Scene* s : {&query, &mixed}) {
    EXPECT_EQ(s->polygon_count(), comma.polygon_count());
    EXPECT_EQ(s->materials[0].reflectance[0], comma.materials[0].reflectance[0]);
    EXPECT_EQ(s->materials[0].emission[0], comma.materials[0].emission[0]);
  }
  EXPECT_EQ(make_builtin("builtin:cornell,blocks=0").polygon_count(), 6u);
  const auto has = [](const std::string& msg, const std::string& part) {
    return msg.find(part) != std::string::npos;
  };
  EXPECT_TRUE(has(error_for("builtin:office,chairs=3"), "unknown parameter 'chairs'"));
  EXPECT_TRUE(has(error_for("builtin:office,desks=3,desks=4"), "given twice"));
  EXPECT_TRUE(has(error_for("builtin:office,desks=3,"), "empty parameter"));
  EXPECT_TRUE(has(error_for("builtin:office,"), "empty parameter"));
  EXPECT_TRUE(has(error_for("builtin:nosuch,desks=3"), "unknown builtin scene 'nosuch'"));
}

TEST(BuiltinRegistry, SpecHelpersKnowBothForms) {
  EXPECT_EQ(builtin_base("builtin:office,desks=4"), "builtin:office");
  EXPECT_EQ(builtin_base("builtin:office?desks=4&lights=2"), "builtin:office");
  EXPECT_EQ(builtin_base("builtin:office"), "builtin:office");
  EXPECT_EQ(builtin_base("rooms/a,b.obj"), "rooms/a,b.obj");
  EXPECT_EQ(normal_builtin_spec("builtin:office?desks=4&lights=2"),
            "builtin:office,desks=4,lights=2");
  EXPECT_EQ(normal_builtin_spec("builtin:office,desks=4"), "builtin:office,desks=4");
  EXPECT_EQ(normal_builtin_spec("a?b&c.obj"), "a?b&c.obj");
  using V = std::vector<std::string>;
  EXPECT_EQ(split_scene_list("builtin:furnace,builtin:cornell"),
            (V{"builtin:furnace", "builtin:cornell"}));
  EXPECT_EQ(split_scene_list("builtin:cornell,blocks=0,light=2,room.obj,builtin:office,desks=4"),
            (V{"builtin:cornell,blocks=0,light=2", "room.obj", "builtin:office,desks=4"}));
  EXPECT_EQ(split_scene_list("builtin:office?desks=4&lights=2,x.mgf"),
            (V{"builtin:office?desks=4&lights=2", "x.mgf"}));
  // A file's "name=value" piece is not a parameter; empty pieces are dropped.
  EXPECT_EQ(split_scene_list("a.obj,b=1.obj,,builtin:lab,"),
            (V{"a.obj", "b=1.obj", "builtin:lab"}));
  EXPECT_TRUE(split_scene_list(",").empty());
}

// --- every scene with its defaults -------------------------------------------------

class BuiltinDefaults : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltinDefaults, BuildsCleanly) {
  const std::string spec = "builtin:" + GetParam();
  const Scene s = make_builtin(spec);
  EXPECT_EQ(s.name, GetParam());
  EXPECT_EQ(s.source, spec);
  EXPECT_GT(s.emitter_count(), 0u);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  // Triangles and quads, and convex pieces of those where boxes that overlap share
  // a plane (the office's and the lab's chair bases, core/scene/coplanar_overlap.h).
  for (const Face& f : s.faces) ASSERT_TRUE(f.count >= 3 && f.count <= 8) << f.count;
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_GT((s.camera->target - s.camera->eye).norm(), 0.1);
  if (GetParam() != "cornell") {  // rooms are seen from inside
    const Aabb b = s.bounds();
    EXPECT_TRUE((s.camera->eye.array() > b.lo.array()).all() &&
                (s.camera->eye.array() < b.hi.array()).all());
  }
  // Luminaires face down (the furnace emits everywhere).
  if (GetParam() != "furnace") {
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
      if (s.face_material(f).emits()) {
        ASSERT_LT(s.face_normal(f).y(), -0.999) << f;
      }
    }
  }
}

TEST_P(BuiltinDefaults, IsDeterministic) {
  const std::string spec = "builtin:" + GetParam();
  const Scene a = make_builtin(spec), b = make_builtin(spec);
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i) ASSERT_EQ(a.vertices[i], b.vertices[i]);
  EXPECT_EQ(a.indices, b.indices);
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (std::size_t f = 0; f < a.faces.size(); ++f)
    ASSERT_EQ(a.faces[f].material, b.faces[f].material);
}

INSTANTIATE_TEST_SUITE_P(Builtin, BuiltinDefaults,
                         ::testing::Values("cornell", "furnace", "office", "lab", "cabin"));

TEST(BuiltinCounts, NearThePapersScenes) {
  EXPECT_EQ(make_builtin("builtin:cornell").polygon_count(), 16u);
  EXPECT_EQ(make_builtin("builtin:furnace").polygon_count(), 20u);
  const std::size_t office = make_builtin("builtin:office").polygon_count();
  EXPECT_GE(office, 4500u);
  EXPECT_LE(office, 5500u);
  const std::size_t lab = make_builtin("builtin:lab").polygon_count();
  EXPECT_GE(lab, 27000u);
  EXPECT_LE(lab, 33000u);
  const Scene cabin = make_builtin("builtin:cabin");
  EXPECT_GE(cabin.polygon_count(), 165000u);
  EXPECT_LE(cabin.polygon_count(), 200000u);
  for (const Face& f : cabin.faces) ASSERT_EQ(f.count, 3u);  // all tessellated
}

TEST(BuiltinCounts, ScaleWithParameters) {
  auto n = [](const std::string& spec) { return make_builtin(spec).polygon_count(); };
  EXPECT_GT(n("builtin:office?desks=40"), n("builtin:office") + 20 * 150);
  EXPECT_LT(n("builtin:office?desks=4"), n("builtin:office"));
  EXPECT_EQ(n("builtin:office?lights=20"), n("builtin:office") + 8 * 5);
  EXPECT_GT(n("builtin:lab?workstations=60"), n("builtin:lab") + 19 * 500);
  EXPECT_LT(n("builtin:cabin?rows=10"), n("builtin:cabin") / 2);
  EXPECT_GT(n("builtin:cabin?rows=10&seats_per_row=10"), n("builtin:cabin?rows=10"));
  EXPECT_GT(n("builtin:cabin?rows=10&segments=128"), n("builtin:cabin?rows=10"));
  EXPECT_EQ(n("builtin:cornell?blocks=0"), 6u);
  EXPECT_EQ(n("builtin:furnace?objects=0"), 6u);
}

TEST(BuiltinCounts, SeedChangesLayoutOnly) {
  const Scene a = make_builtin("builtin:office?seed=1"), b = make_builtin("builtin:office?seed=2");
  EXPECT_NE(a.vertices, b.vertices);
  EXPECT_EQ(a.bounds().lo, b.bounds().lo);
  EXPECT_EQ(a.bounds().hi, b.bounds().hi);
}

// How long builtin:cabin takes to generate is measured in
// experiments/micro/scene_bench.cpp (BM_CabinGeneration), not bounded here.

// --- the furnace is closed ---------------------------------------------------------

TEST(BuiltinFurnace, IsWatertightAndConsistentlyOriented) {
  for (const std::string spec : {"builtin:furnace", "builtin:furnace?size=3.7&objects=0"}) {
    const Scene s = make_builtin(spec);
    EXPECT_EQ(unpaired_edges(s, all_faces(s)), 0u) << spec;
    Vec3 total = Vec3::Zero();
    for (std::size_t f = 0; f < s.faces.size(); ++f) total += vector_area(s.face_vertices(f));
    EXPECT_LT(total.norm(), 1e-12) << spec;
  }
}

TEST(BuiltinFurnace, RoomFacesInwardObjectsOutwardAndClearOfWalls) {
  const double size = 2.0;
  const Scene s = make_builtin("builtin:furnace?size=2");
  std::vector<std::size_t> room, objects;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const std::vector<Vec3> p = s.face_vertices(f);
    bool on_wall = false;
    for (int a = 0; a < 3 && !on_wall; ++a)
      for (double w : {0.0, size}) {
        bool all = true;
        for (const Vec3& v : p) all = all && v[a] == w;
        on_wall = on_wall || all;
      }
    if (on_wall) {
      room.push_back(f);
    } else {
      objects.push_back(f);
      for (const Vec3& v : p)  // at least 0.1 x size from every wall
        ASSERT_TRUE((v.array() > 0.1 * size).all() && (v.array() < 0.9 * size).all());
    }
  }
  ASSERT_EQ(room.size(), 6u);
  ASSERT_EQ(objects.size(), 14u);
  double wall_area = 0;
  for (std::size_t f : room) wall_area += s.face_area(f);
  EXPECT_NEAR(wall_area, 6 * size * size, 1e-12);  // the walls tile the cube's surface
  EXPECT_NEAR(signed_volume(s, room), -size * size * size, 1e-12);
  const double r = 0.18 * size, cube = std::pow(0.25 * size, 3), octa = 4.0 / 3.0 * r * r * r;
  EXPECT_NEAR(signed_volume(s, objects), cube + octa, 1e-12);
  EXPECT_EQ(unpaired_edges(s, room), 0u);
  EXPECT_EQ(unpaired_edges(s, objects), 0u);
}

// --- orientation and containment of the rooms --------------------------------------

TEST(BuiltinOrientation, FloorsFaceUpCeilingsDownWallsInward) {
  struct Case {
    std::string spec, floor, ceiling, wall;
  };
  for (const Case& c : {Case{"builtin:office", "floor", "ceiling", "wall"},
                        Case{"builtin:lab", "floor", "ceiling", "wall"},
                        Case{"builtin:cabin?rows=4", "floor", "", ""}}) {
    const Scene s = make_builtin(c.spec);
    const auto floor = faces_of(s, c.floor);
    ASSERT_FALSE(floor.empty()) << c.spec;
    for (std::size_t f : floor) ASSERT_GT(s.face_normal(f).y(), 0.999) << c.spec;
    for (std::size_t f : faces_of(s, c.ceiling)) ASSERT_LT(s.face_normal(f).y(), -0.999);
    const Vec3 mid = s.bounds().center();
    for (std::size_t f : faces_of(s, c.wall)) {
      const Vec3 n = s.face_normal(f), to_mid = mid - polygon_centroid(s.face_vertices(f));
      ASSERT_NEAR(n.y(), 0.0, 1e-12);
      ASSERT_GT(n.dot(to_mid), 0.0) << c.spec;
    }
  }
  // Cornell: the floor (y = 0) faces up, the red wall (x = 5.56) faces -x.
  const Scene s = make_builtin("builtin:cornell");
  int floors = 0;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const std::vector<Vec3> p = s.face_vertices(f);
    if (p[0].y() == 0 && p[1].y() == 0 && p[2].y() == 0) {
      ++floors;
      EXPECT_GT(s.face_normal(f).y(), 0.999);
    }
  }
  EXPECT_EQ(floors, 1);
  const auto red = faces_of(s, "red");
  ASSERT_EQ(red.size(), 1u);
  EXPECT_LT(s.face_normal(red[0]).x(), -0.999);
}

TEST(BuiltinOrientation, CabinFuselageFacesTheAxis) {
  const Scene s = make_builtin("builtin:cabin?rows=3&segments=16");
  const auto hull = faces_of(s, "fuselage");
  ASSERT_FALSE(hull.empty());
  const auto [R, yc] = hull_circle(s);
  EXPECT_NEAR(yc, 0.3 * R, 1e-9);
  for (std::size_t f : hull) {
    const Vec3 c = polygon_centroid(s.face_vertices(f));
    const Vec3 to_axis(-c.x(), yc - c.y(), 0);
    ASSERT_GT(s.face_normal(f).dot(to_axis.normalized()), 0.9);
  }
}

TEST(BuiltinOrientation, NothingPokesThroughTheRoom) {
  // Every vertex lies inside the box spanned by the room's own surfaces.
  for (const std::string spec :
       {"builtin:office", "builtin:lab?workstations=9", "builtin:cornell"}) {
    const Scene s = make_builtin(spec);
    std::vector<std::size_t> shell;
    for (const char* m : {"wall", "floor", "ceiling", "white", "red", "green"})
      for (std::size_t f : faces_of(s, m)) shell.push_back(f);
    const Aabb room = bounds_of(s, shell);
    const Aabb all = s.bounds();
    EXPECT_EQ(all.lo, room.lo) << spec;
    EXPECT_EQ(all.hi, room.hi) << spec;
  }
  // Cabin: every vertex within the fuselage circle (bins, seats, strips).
  const Scene s = make_builtin("builtin:cabin?rows=3&segments=8&seats_per_row=10");
  const auto [R, yc] = hull_circle(s);
  EXPECT_GT(R, 2.5);  // widened for 5 seats a side
  for (const Vec3& v : s.vertices) {
    ASSERT_GE(v.y(), -1e-12);
    ASSERT_LE(std::hypot(v.x(), v.y() - yc), R + 1e-9);
  }
}

// --- the shape helpers -------------------------------------------------------------

TEST(BuiltinShapes, BoxesAreClosedAndFaceTheRightWay) {
  const Vec3 lo(1, 2, 3), hi(2, 4, 7);  // volume 8
  for (const bool tris : {false, true}) {
    Scene out = shapes_scene([&](Shapes& s, auto m) { s.box(Frame{}, lo, hi, m); }, tris);
    EXPECT_EQ(out.polygon_count(), tris ? 12u : 6u);
    EXPECT_EQ(unpaired_edges(out, all_faces(out)), 0u);
    EXPECT_NEAR(signed_volume(out, all_faces(out)), 8.0, 1e-12);
    Scene in = shapes_scene(
        [&](Shapes& s, auto m) { s.box(Frame{}, lo, hi, m, builtin::kAllFaces, Facing::Inward); },
        tris);
    EXPECT_NEAR(signed_volume(in, all_faces(in)), -8.0, 1e-12);
  }
  // Cut into cells (3 x 1 x 2): 2*(1*2) + 2*(3*2) + 2*(3*1) = 22 quads, still closed.
  Scene grid = shapes_scene([&](Shapes& s, auto m) {
    s.box(Frame{}, lo, hi, m, builtin::kAllFaces, Facing::Outward, Eigen::Vector3i(3, 1, 2));
  });
  EXPECT_EQ(grid.polygon_count(), 22u);
  EXPECT_EQ(unpaired_edges(grid, all_faces(grid)), 0u);
  EXPECT_NEAR(signed_volume(grid, all_faces(grid)), 8.0, 1e-12);
  // A yawed box keeps its volume and orientation; masks drop faces.
  Scene yawed = shapes_scene([&](Shapes& s, auto m) {
    s.box(Frame::yawed(Vec3(5, 0, 5), 0.7), lo, hi, m);
    s.box(Frame{}, lo, hi, m, builtin::kNoBottom);
  });
  EXPECT_EQ(yawed.polygon_count(), 11u);
  std::vector<std::size_t> first(6);
  for (std::size_t i = 0; i < 6; ++i) first[i] = i;
  EXPECT_NEAR(signed_volume(yawed, first), 8.0, 1e-9);
}

TEST(BuiltinShapes, RoundSolidsAreClosedWithOutwardFaces) {
  const double r = 0.5, h = 2.0;
  Scene cyl = shapes_scene(
      [&](Shapes& s, auto m) { s.cylinder(Frame::at(Vec3(1, 1, 1)), r, 0, h, 12, 3, m); });
  EXPECT_EQ(cyl.polygon_count(), 12u * 3 + 24);
  EXPECT_EQ(unpaired_edges(cyl, all_faces(cyl)), 0u);
  // Inscribed 12-gon: area 3 r^2.
  EXPECT_NEAR(signed_volume(cyl, all_faces(cyl)), 3 * r * r * h, 1e-9);

  Scene rod =
      shapes_scene([&](Shapes& s, auto m) { s.rod(Vec3(0, 0, 0), Vec3(1, 2, 2), r, 12, m); });
  EXPECT_NEAR(signed_volume(rod, all_faces(rod)), 3 * r * r * 3.0, 1e-9);

  Scene sph = shapes_scene(
      [&](Shapes& s, auto m) { s.sphere(Frame{}, Vec3(0.3, 0.2, 0.1), 1.0, 24, 12, m); });
  EXPECT_EQ(sph.polygon_count(), 24u * 10 + 48);
  EXPECT_TRUE(sph.warnings.empty());
  EXPECT_EQ(unpaired_edges(sph, all_faces(sph)), 0u);
  const double v = signed_volume(sph, all_faces(sph));
  EXPECT_GT(v, 0.95 * 4.0 / 3.0 * std::numbers::pi);
  EXPECT_LT(v, 4.0 / 3.0 * std::numbers::pi);

  const std::array<Eigen::Vector2d, 5> pentagon = {
      Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 0), Eigen::Vector2d(2, 1), Eigen::Vector2d(1, 2),
      Eigen::Vector2d(0, 1)};  // area 3, counter-clockwise
  Scene pr = shapes_scene([&](Shapes& s, auto m) { s.prism(Frame{}, pentagon, -1, 1, 4, 2, m); });
  EXPECT_EQ(unpaired_edges(pr, all_faces(pr)), 0u);
  EXPECT_NEAR(signed_volume(pr, all_faces(pr)), 3.0 * 2, 1e-12);

  // A frustum as a hexahedron (corner index x + 2y + 4z).
  std::array<Vec3, 8> c;
  for (int i = 0; i < 8; ++i) {
    const double s = (i & 4) ? 1.0 : 0.5;  // the z = 1 end is larger
    c[i] = Vec3((i & 1) ? s : -s, (i & 2) ? s : -s, (i & 4) ? 1.0 : 0.0);
  }
  Scene hex = shapes_scene([&](Shapes& s, auto m) { s.hexahedron(Frame{}, c, m); });
  EXPECT_EQ(unpaired_edges(hex, all_faces(hex)), 0u);
  // Frustum volume h (A1 + sqrt(A1 A2) + A2) / 3 with h = 1, A1 = 1, A2 = 4.
  EXPECT_NEAR(signed_volume(hex, all_faces(hex)), 7.0 / 3.0, 1e-12);
}

}  // namespace
}  // namespace hrad
