#include "core/scene/obj_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "core/base/input_error.h"
#include "core/scene/scene_loader.h"

namespace hrad {
namespace {

// The public Cornell boxes are not in the repository: they live in the shared scene
// folder beside the checkout. Without it their tests are skipped, not failed.
const std::string kScenes = HRAD_SOURCE_DIR "/../shared/scenes";
#define SKIP_UNLESS_SHARED_SCENE(path)                                         \
  if (!std::filesystem::is_regular_file(path))                                 \
  GTEST_SKIP() << (path)                                                       \
               << " is absent: the public Cornell boxes come from the shared " \
                  "scene folder ../shared/scenes beside the checkout"
const std::string kData = HRAD_SOURCE_DIR "/tests/data/obj";
constexpr double kPi = std::numbers::pi;

/// The InputError `f` throws (fails the test if it throws nothing).
template <class F>
InputError error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError thrown";
  return InputError("", 0, "");
}

InputError parse_error(const std::string& obj, const std::string& mtl = "") {
  return error_of([&] { parse_obj(obj, mtl, "t.obj"); });
}

bool has_warning(const Scene& s, const std::string& part) {
  return std::any_of(s.warnings.begin(), s.warnings.end(),
                     [&](const std::string& w) { return w.find(part) != std::string::npos; });
}

std::size_t count_faces(const Scene& s, std::uint32_t n) {
  return static_cast<std::size_t>(
      std::count_if(s.faces.begin(), s.faces.end(), [&](const Face& f) { return f.count == n; }));
}

/// The polygons of an OBJ file, read here independently of the reader (v and f
/// statements only, relative indices resolved).
std::vector<std::vector<Vec3>> obj_polygons(const std::string& path) {
  std::ifstream in(path);
  std::vector<Vec3> v;
  std::vector<std::vector<Vec3>> polys;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "v") {
      Vec3 p;
      ls >> p.x() >> p.y() >> p.z();
      v.push_back(p);
    } else if (kw == "f") {
      std::vector<Vec3> poly;
      for (std::string ref; ls >> ref;) {
        const long i = std::stol(ref.substr(0, ref.find('/')));
        poly.push_back(
            v[static_cast<std::size_t>(i > 0 ? i - 1 : static_cast<long>(v.size()) + i)]);
      }
      // A repeat of an earlier polygon (the same positions in the same cyclic order)
      // is one surface, as the reader keeps it.
      bool repeat = false;
      for (const auto& q : polys)
        for (std::size_t r = 0; r < q.size() && !repeat && q.size() == poly.size(); ++r) {
          bool same = true;
          for (std::size_t k = 0; k < q.size() && same; ++k)
            same = q[(r + k) % q.size()] == poly[k];
          repeat = same;
        }
      if (!repeat) polys.push_back(poly);
    }
  }
  return polys;
}

/// Total area of the OBJ's polygons when the non-planar quads are split along
/// their 0-2 diagonal (`diagonal02`) or their 1-3 diagonal; also counts them.
double obj_area(const std::vector<std::vector<Vec3>>& polys, bool diagonal02,
                int* non_planar = nullptr) {
  double a = 0;
  for (const auto& p : polys) {
    if (p.size() == 4 && relative_nonplanarity(p) > 1e-3) {
      if (non_planar) ++*non_planar;
      const std::vector<Vec3> t1 =
          diagonal02 ? std::vector<Vec3>{p[0], p[1], p[2]} : std::vector<Vec3>{p[0], p[1], p[3]};
      const std::vector<Vec3> t2 =
          diagonal02 ? std::vector<Vec3>{p[0], p[2], p[3]} : std::vector<Vec3>{p[1], p[2], p[3]};
      a += polygon_area(t1) + polygon_area(t2);
    } else {
      a += polygon_area(p);
    }
  }
  return a;
}

/// The reader's total area equals the OBJ's, with each non-planar quad split
/// along one of its diagonals (the polygon count tells which it must be).
void expect_area_matches_obj(const Scene& s, const std::string& path, int expect_non_planar) {
  const auto polys = obj_polygons(path);
  int non_planar = 0;
  const double a02 = obj_area(polys, true, &non_planar), a13 = obj_area(polys, false);
  EXPECT_EQ(non_planar, expect_non_planar);
  const double total = s.total_area();
  const double best = std::min(std::abs(total - a02), std::abs(total - a13));
  EXPECT_LE(best, 1e-9 * total) << "reader " << total << ", obj " << a02 << " / " << a13;
}

/// "v x y 0\n" with all 17 significant digits.
std::string fmt_vertex(double x, double y) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "v %.17g %.17g 0\n", x, y);
  return buf;
}

const Material* material_named(const Scene& s, const std::string& name) {
  for (const Material& m : s.materials)
    if (m.name == name) return &m;
  return nullptr;
}

// --- the public Cornell boxes ----------------------------------------------

TEST(ObjCornell, McGuireOriginalKeepsQuadsAndTriangulatesTheBentWall) {
  const std::string path = kScenes + "/cornell-mcguire/CornellBox-Original.obj";
  SKIP_UNLESS_SHARED_SCENE(path);
  const Scene s = read_obj(path);
  EXPECT_EQ(s.name, "CornellBox-Original");
  EXPECT_EQ(s.source, path);
  // 18 quads in the file. Two repeat a side face of a block (each block's "Bottom
  // Face" names the four vertices before its own): dropped as duplicates. Of the other
  // 16, the 15 planar ones are kept and the left wall (non-planar) is split in two.
  EXPECT_EQ(s.polygon_count(), 17u);
  EXPECT_EQ(count_faces(s, 4), 15u);
  EXPECT_EQ(count_faces(s, 3), 2u);
  EXPECT_TRUE(has_warning(s, "2 duplicate face(s) dropped"));
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    if (s.faces[f].count == 3) {
      EXPECT_EQ(s.face_material(f).name, "leftWall");
    }
  }
  EXPECT_TRUE(has_warning(s, "1 non-planar or non-convex polygon(s) triangulated"));
  expect_area_matches_obj(s, path, 1);

  EXPECT_EQ(s.emitter_count(), 1u);
  const Material* light = material_named(s, "light");
  ASSERT_NE(light, nullptr);
  EXPECT_NEAR(light->emission[0], kPi * 17, 1e-12);
  EXPECT_NEAR(light->emission[1], kPi * 12, 1e-12);
  EXPECT_NEAR(light->emission[2], kPi * 4, 1e-12);
  const Material* red = material_named(s, "leftWall");
  ASSERT_NE(red, nullptr);
  EXPECT_DOUBLE_EQ(red->reflectance[0], 0.63);
  EXPECT_DOUBLE_EQ(red->reflectance[1], 0.065);
  EXPECT_DOUBLE_EQ(red->reflectance[2], 0.05);
  EXPECT_EQ(red->emission.matrix(), Vec3::Zero());
}

TEST(ObjCornell, McGuireEmptyLoads) {
  const std::string path = kScenes + "/cornell-mcguire/CornellBox-Empty-RG.obj";
  SKIP_UNLESS_SHARED_SCENE(path);
  const Scene s = read_obj(path);
  EXPECT_EQ(s.polygon_count(), 7u);  // 6 quads, the left wall split in two
  EXPECT_EQ(s.emitter_count(), 1u);
  expect_area_matches_obj(s, path, 1);
}

TEST(ObjCornell, MeasuredBoxIsInMillimetres) {
  const std::string path = kScenes + "/cornell-measured/cornell_box_original_mm.obj";
  SKIP_UNLESS_SHARED_SCENE(path);
  const Scene s = read_obj(path);
  EXPECT_EQ(s.name, "cornell_box_original_mm");
  // 31 faces: 7 quads (the red wall non-planar, split) and 24 box triangles.
  EXPECT_EQ(s.polygon_count(), 32u);
  EXPECT_EQ(count_faces(s, 4), 6u);
  EXPECT_EQ(s.emitter_count(), 1u);
  expect_area_matches_obj(s, path, 1);
  const Vec3 e = s.bounds().extent();
  EXPECT_NEAR(e.x(), 556.0, 1e-9);
  EXPECT_NEAR(e.y(), 548.8, 1e-9);
  EXPECT_NEAR(e.z(), 559.2, 1e-9);
  const Material* light = material_named(s, "light");
  ASSERT_NE(light, nullptr);
  EXPECT_NEAR(light->emission[0], kPi * 18.2331, 1e-12);
  EXPECT_NEAR(light->reflectance[0], 0.78, 1e-15);
}

// --- materials -------------------------------------------------------------

const char* const kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(ObjMaterials, KeIsRadianceAndEmissionIsPiTimesKe) {
  const Scene s = parse_obj(std::string(kTriangle) + "usemtl lamp\nf 1 2 3\n",
                            "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1 2 0.25\n", "t.obj");
  ASSERT_EQ(s.polygon_count(), 1u);
  const Material& m = s.face_material(0);
  EXPECT_EQ(m.name, "lamp");
  EXPECT_NEAR(m.emission[0], kPi, 1e-15);
  EXPECT_NEAR(m.emission[1], 2 * kPi, 1e-15);
  EXPECT_NEAR(m.emission[2], 0.25 * kPi, 1e-15);
  EXPECT_EQ(m.reflectance.matrix(), Vec3::Constant(0.5));
}

TEST(ObjMaterials, KdAboveOneNamesTheMtlFileAndTheKdLine) {
  const InputError e = error_of([&] { read_obj(kData + "/bad_kd.obj"); });
  EXPECT_EQ(e.file(), kData + "/bad_kd.mtl");
  EXPECT_EQ(e.line(), 6);
  EXPECT_NE(std::string(e.what()).find("'hot'"), std::string::npos) << e.what();
}

TEST(ObjMaterials, InlineMtlErrorsNameTheMtlAndTheLine) {
  const InputError neg = parse_error(kTriangle, "newmtl a\n\nKd -0.1 0 0\n");
  EXPECT_EQ(neg.file(), "t.mtl");
  EXPECT_EQ(neg.line(), 3);
  const InputError ke = parse_error(kTriangle, "newmtl a\nKd 0.5 0.5 0.5\nKe 1 -2 3\n");
  EXPECT_EQ(ke.line(), 3);
  const InputError nan = parse_error(kTriangle, "newmtl a\nKd 0.5 nan 0.5\n");
  EXPECT_EQ(nan.line(), 2);
  const InputError short_kd = parse_error(kTriangle, "newmtl a\nKd 0.5 0.5\n");
  EXPECT_EQ(short_kd.line(), 2);
  EXPECT_NE(std::string(short_kd.what()).find("three numbers"), std::string::npos);
}

// MTL: "If only r is specified, then g and b are assumed to be equal to r"
// (tinyobjloader reads (r, 0, 0); before, hrad refused the line).
TEST(ObjMaterials, OneNumberKdOrKeIsAGrey) {
  const Scene s = parse_obj(std::string(kTriangle) + "usemtl a\nf 1 2 3\n",
                            "newmtl a\nKd 0.7\nKe 2\n", "t.obj");
  const Material& m = s.face_material(0);
  EXPECT_EQ(m.reflectance.matrix(), Vec3::Constant(0.7));
  EXPECT_EQ(m.emission.matrix(), Vec3::Constant(2 * kPi));
}

// Errors quote the file's numbers: not 0.7 printed back as 0.7000000000000001, nor
// pi x Ke; and an emission that 32-bit results cannot hold is refused (Ke 1e40 solved
// with exit 0 and wrote inf into solution.ply).
TEST(ObjMaterials, BadKdAndKeAreQuotedAsWritten) {
  const auto what = [](const char* mtl) { return std::string(parse_error(kTriangle, mtl).what()); };
  EXPECT_NE(what("newmtl a\nKd 1.2 0.7 0.7\n")
                .find("t.mtl:2: material 'a': Kd 1.2 0.7 0.7 is outside [0, 1]"),
            std::string::npos)
      << what("newmtl a\nKd 1.2 0.7 0.7\n");
  EXPECT_NE(what("newmtl a\nKd 0 0 0\nKe -1 1 1\n").find("Ke -1 1 1 is negative"),
            std::string::npos)
      << what("newmtl a\nKd 0 0 0\nKe -1 1 1\n");
  const InputError big = parse_error(kTriangle, "newmtl a\nKd 0 0 0\nKe 1e40 5 5\n");
  EXPECT_EQ(big.line(), 3);
  EXPECT_NE(std::string(big.what()).find("Ke 1e40 5 5 is too large"), std::string::npos)
      << big.what();
  // Just below the cap is fine.
  EXPECT_NO_THROW(parse_obj(std::string(kTriangle) + "usemtl a\nf 1 2 3\n",
                            "newmtl a\nKd 0 0 0\nKe 3e29 0 0\n", "t.obj"));
}

TEST(ObjMaterials, FacesWithoutMaterialGetTheDefaultGrey) {
  const Scene s = parse_obj(std::string(kTriangle) + "f 1 2 3\nf 3 2 1\n", "", "t.obj");
  ASSERT_EQ(s.polygon_count(), 2u);
  EXPECT_EQ(s.face_material(0).reflectance.matrix(), Vec3::Constant(0.5));
  EXPECT_TRUE(has_warning(s, "2 face(s) named no material")) << s.warnings.front();
}

TEST(ObjMaterials, UnknownUsemtlGetsTheDefaultWithACountedWarning) {
  const Scene s = parse_obj(std::string(kTriangle) + "usemtl ghost\nf 1 2 3\nf 3 2 1\n",
                            "newmtl real\nKd 0.2 0.2 0.2\n", "t.obj");
  EXPECT_EQ(s.face_material(0).reflectance.matrix(), Vec3::Constant(0.5));
  EXPECT_TRUE(has_warning(s,
                          "t.obj:4: usemtl 'ghost' names no material of the .mtl file(s); "
                          "its 2 face(s)"));
}

TEST(ObjMaterials, TinyobjloaderWarningsAreSurfacedWithTheFile) {
  const Scene s = parse_obj(std::string(kTriangle) + "usemtl a\nf 1 2 3\n",
                            "newmtl a\nd 0.5\nTr 0.5\n", "t.obj");
  EXPECT_TRUE(has_warning(s, "t.mtl: tinyobjloader: Both `d` and `Tr`"));
}

TEST(ObjMaterials, DuplicateMaterialKeepsTheFirst) {
  const Scene s = parse_obj(std::string(kTriangle) + "usemtl a\nf 1 2 3\n",
                            "newmtl a\nKd 0.1 0.1 0.1\nnewmtl a\nKd 0.9 0.9 0.9\n", "t.obj");
  EXPECT_EQ(s.face_material(0).reflectance.matrix(), Vec3::Constant(0.1));
  EXPECT_TRUE(has_warning(s, "t.mtl:3: material 'a' is defined again"));
}

// --- geometry --------------------------------------------------------------

TEST(ObjGeometry, KeepsPlanarQuadsTriangulatesConcavePolygons) {
  const Scene s = read_obj(kData + "/shapes.obj");
  EXPECT_EQ(s.name, "shapes");
  // The square stays a quad; the concave pentagon (area 2.5) becomes 3 triangles.
  ASSERT_EQ(s.polygon_count(), 5u);
  EXPECT_EQ(s.faces[0].count, 4u);
  EXPECT_EQ(s.face_material(0).name, "lamp");
  EXPECT_NEAR(s.face_material(0).emission[2], 3 * kPi, 1e-15);
  double pentagon = 0;
  for (std::size_t f = 1; f < 4; ++f) {
    EXPECT_EQ(s.faces[f].count, 3u);
    EXPECT_EQ(s.face_material(f).name, "wall");
    pentagon += s.face_area(f);
  }
  EXPECT_NEAR(pentagon, 2.5, 1e-12);
  EXPECT_TRUE(has_warning(s, "1 non-planar or non-convex polygon(s) triangulated"));
  // The last face: "v/vt/vn" references, and a usemtl naming nothing.
  EXPECT_EQ(s.faces[4].count, 3u);
  EXPECT_TRUE(has_warning(s, "usemtl 'nowhere'"));
}

TEST(ObjGeometry, PolygonsWithMoreThan255VerticesSurvive) {
  // tinyobjloader counts face vertices in 8 bits; a 300-gon must stay a 300-gon.
  const int n = 300;
  std::string obj;
  for (int i = 0; i < n; ++i)
    obj += fmt_vertex(std::cos(2 * kPi * i / n), std::sin(2 * kPi * i / n));
  obj += "f";
  for (int i = 1; i <= n; ++i) obj += " " + std::to_string(i);
  // The triangle faces the other way: one facing the same way would lie under the
  // 300-gon and be cut away (core/scene/coplanar_overlap.h).
  const Scene s = parse_obj(obj + "\nf 3 2 1\n", "", "t.obj");
  ASSERT_EQ(s.polygon_count(), 2u);
  EXPECT_EQ(s.faces[0].count, 300u);
  EXPECT_NEAR(s.face_area(0), 0.5 * n * std::sin(2 * kPi / n), 1e-12);
  EXPECT_EQ(s.faces[1].count, 3u);
}

// A backslash at the end of a line continues it (OBJ and MTL); every other line keeps
// its number. Before, "f 1 2 \" was a malformed vertex reference.
TEST(ObjGeometry, BackslashContinuesALine) {
  const Scene s = parse_obj("v 0 0 0\nv 1 0 \\\n 0\nv 1 1 0\r\nusemtl a\nf 1 2 \\\r\n 3\n",
                            "newmtl a\nKd 0.2 \\\n0.4 0.6\n", "t.obj");
  ASSERT_EQ(s.polygon_count(), 1u);
  EXPECT_EQ(s.vertices[1], Vec3(1, 0, 0));
  EXPECT_EQ(s.face_material(0).reflectance.matrix(), Vec3(0.2, 0.4, 0.6));
  EXPECT_EQ(parse_error("v 0 0 \\\n0\nv 1 nan 0\n").line(), 3);
}

TEST(ObjGeometry, RelativeIndicesAndLineEndings) {
  // CRLF and lone CR end lines too; the bad index is on line 5 either way.
  for (const std::string nl : {"\n", "\r\n", "\r"}) {
    const Scene s = parse_obj("v 0 0 0" + nl + "v 1 0 0" + nl + "v 0 1 0" + nl + "f -3 -2 -1" + nl,
                              "", "t.obj");
    EXPECT_EQ(s.polygon_count(), 1u);
    const InputError e =
        parse_error("v 0 0 0" + nl + "v 1 0 0" + nl + "v 0 1 0" + nl + nl + "f 1 2 4" + nl);
    EXPECT_EQ(e.line(), 5) << e.what();
  }
}

TEST(ObjGeometry, IgnoredStatementsAreCounted) {
  const Scene s =
      parse_obj(std::string(kTriangle) +
                    "vn 0 0 1\nvt 0 0\ng a\no b\ns 1\nl 1 2\np 1\nfrobnicate 3\nf 1 2 3\n",
                "", "t.obj");
  EXPECT_EQ(s.polygon_count(), 1u);
  EXPECT_TRUE(has_warning(s, "t.obj: 2 line, point, curve or surface statement(s) ignored"));
  EXPECT_TRUE(has_warning(s,
                          "1 line(s) with unknown statements ignored (the first, line 11: "
                          "'frobnicate')"));
}

// --- errors ----------------------------------------------------------------

TEST(ObjErrors, BadCoordinatesNameTheObjLine) {
  const std::string head = "# c\nv 0 0 0\n";
  for (const std::string bad :
       {"1 nan 2", "1e400 0 0", "1 -inf 2", "1abc 2 3", "1e31 0 0", "1 2"}) {
    const InputError e = parse_error(head + "v " + bad + "\nv 0 1 0\nf 1 2 3\n");
    EXPECT_EQ(e.file(), "t.obj") << bad;
    EXPECT_EQ(e.line(), 3) << bad << ": " << e.what();
  }
}

TEST(ObjErrors, BadIndicesNameTheFaceLine) {
  for (const std::string bad :
       {"1 2 99", "1 2 0", "-1 -2 -4", "1 2", "1 2 x", "1 2 3/a/1", "1 2 99999999999"}) {
    const InputError e = parse_error(std::string(kTriangle) + "\nf " + bad + "\n");
    EXPECT_EQ(e.line(), 5) << bad << ": " << e.what();
  }
  EXPECT_NE(std::string(parse_error(std::string(kTriangle) + "f 1 2 99\n").what())
                .find("vertex index 99 is out of range (the file has 3 vertices)"),
            std::string::npos);
  EXPECT_NE(std::string(parse_error(std::string(kTriangle) + "f 1 2 0\n").what())
                .find("index 0 is invalid"),
            std::string::npos);
}

TEST(ObjErrors, NulByteIsAnError) {
  EXPECT_EQ(parse_error(std::string(kTriangle) + std::string("f 1 2\0 3\n", 9)).line(), 4);
}

TEST(ObjErrors, MissingFile) {
  const InputError e = error_of([&] { read_obj(kData + "/no_such_file.obj"); });
  EXPECT_EQ(e.file(), kData + "/no_such_file.obj");
  EXPECT_EQ(e.line(), 0);
}

TEST(ObjErrors, MissingMaterialLibraryNamesTheMtllibLine) {
  const InputError e = error_of([&] { read_obj(kData + "/missing_mtl.obj"); });
  EXPECT_EQ(e.file(), kData + "/missing_mtl.obj");
  EXPECT_EQ(e.line(), 5);
  EXPECT_NE(std::string(e.what()).find("no_such_library.mtl"), std::string::npos);
}

TEST(ObjErrors, SceneWithoutPolygonsThrows) {
  EXPECT_EQ(parse_error(kTriangle).line(), 0);
  EXPECT_EQ(parse_error("").file(), "t.obj");
  // Only a degenerate face: dropped, so nothing is left.
  EXPECT_EQ(parse_error("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").line(), 0);
}

// --- the scene loader ------------------------------------------------------

TEST(LoaderDispatch, ObjByExtension) {
  const Scene s = load_scene(kData + "/shapes.obj");
  EXPECT_EQ(s.name, "shapes");
  EXPECT_EQ(s.polygon_count(), 5u);
}

TEST(LoaderDispatch, MgfByExtension) {
  // MGF materials are two-sided by default: the triangle gets a back face, which
  // emits only with `emitter_sides = both`; `sides = one` leaves it alone.
  const Scene s = load_scene(kData + "/loader_triangle.mgf");
  EXPECT_EQ(s.polygon_count(), 2u);
  EXPECT_EQ(s.emitter_count(), 1u);
  EXPECT_EQ(s.back_faces, 1u);
  EXPECT_EQ(s.dark_back_faces, 1u);
  const Scene both =
      load_scene(kData + "/loader_triangle.mgf", {Sides::Auto, 0, EmitterSides::Both});
  EXPECT_EQ(both.emitter_count(), 2u);
  EXPECT_EQ(both.emitter_sides, "both");
  EXPECT_EQ(s.sides, "auto");
  EXPECT_NEAR(s.face_normal(0).dot(s.face_normal(1)), -1.0, 1e-12);
  const Scene one = load_scene(kData + "/loader_triangle.mgf", {Sides::One, 0});
  EXPECT_EQ(one.polygon_count(), 1u);
  EXPECT_EQ(one.back_faces, 0u);
  EXPECT_EQ(one.sides, "one");
}

TEST(LoaderDispatch, ObjIsOneSidedUnlessAsked) {
  EXPECT_EQ(load_scene(kData + "/shapes.obj").back_faces, 0u);
  const Scene two = load_scene(kData + "/shapes.obj", {Sides::Two, 0});
  EXPECT_EQ(two.back_faces, two.polygon_count() / 2);
  EXPECT_EQ(two.polygon_count(), 2 * load_scene(kData + "/shapes.obj").polygon_count());
}

TEST(LoaderDispatch, Builtin) {
  const Scene s = load_scene("builtin:cornell");
  EXPECT_GT(s.polygon_count(), 0u);
  EXPECT_GT(s.emitter_count(), 0u);
  EXPECT_THROW(load_scene("builtin:no_such_scene"), InputError);
}

TEST(LoaderDispatch, UnknownFormatIsAnError) {
  const InputError e = error_of([] { load_scene("scene.ply"); });
  EXPECT_EQ(e.file(), "scene.ply");
  EXPECT_NE(std::string(e.what()).find("expected .obj, .mgf or builtin:NAME"), std::string::npos);
  EXPECT_THROW(load_scene("no_extension"), InputError);
  // The extension is case-insensitive: this is read as OBJ (and is missing).
  EXPECT_EQ(std::string(error_of([] { load_scene("missing.OBJ"); }).what()),
            "missing.OBJ: the file does not exist");
}

}  // namespace
}  // namespace hrad
