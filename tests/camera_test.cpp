// Cameras: the --camera spec and the view file (core/scene/camera_spec.h), and the automatic
// camera (core/output/auto_camera.h).
#include "core/base/input_error.h"
#include "core/output/auto_camera.h"
#include "core/output/render.h"
#include "core/scene/builtin_scenes.h"
#include "core/scene/camera_spec.h"
#include "core/scene/scene_loader.h"
#include "tests/error_text.h"
#include "tests/thick_box.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>

namespace hrad {
namespace {

namespace fs = std::filesystem;

using test::contains;
using test::error_of;

/// A folder of its own for the running test, removed at the end.
class TempDir {
 public:
  TempDir() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("hrad-camera-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~TempDir() { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }

 private:
  fs::path dir_;
};

// --- the spec -----------------------------------------------------------------------

TEST(CameraSpec, ParsesPartsInAnyOrder) {
  CameraSpec s = parse_camera_spec("eye=1,2.5,-3:look=0,0,1e-3:up=0,0,1:fov=35.5");
  EXPECT_EQ(s.eye, Vec3(1, 2.5, -3));
  EXPECT_EQ(s.look, Vec3(0, 0, 1e-3));
  ASSERT_TRUE(s.up && s.fov_deg);
  EXPECT_EQ(*s.up, Vec3(0, 0, 1));
  EXPECT_EQ(*s.fov_deg, 35.5);
  s = parse_camera_spec("look=4,5,6:eye=1,2,3");
  EXPECT_EQ(s.eye, Vec3(1, 2, 3));
  EXPECT_EQ(s.look, Vec3(4, 5, 6));
  EXPECT_FALSE(s.up || s.fov_deg);
  // Defaults: the given up, 60 degrees.
  const Camera c = resolve_camera(s, Vec3::UnitZ());
  EXPECT_EQ(c.up, Vec3::UnitZ());
  EXPECT_EQ(c.fov_y_deg, kDefaultFovDeg);
  EXPECT_EQ(c.target, Vec3(4, 5, 6));
  EXPECT_TRUE(is_auto_camera("auto"));
  EXPECT_FALSE(is_auto_camera("Auto"));
}

TEST(CameraSpec, RejectsMalformedTextNamingTheBadPart) {
  const std::map<std::string, std::string> cases = {
      {"", "empty camera"},
      {"eye=1,2:look=0,0,0", "'eye=1,2' needs three numbers eye=X,Y,Z, got 2"},
      {"eye=1,2,3,4:look=0,0,0", "'eye=1,2,3,4' needs three numbers"},
      {"eye=1,x,3:look=0,0,0", "'eye=1,x,3': 'x' is not a finite number"},
      {"eye=1,,3:look=0,0,0", "'eye=1,,3': '' is not a finite number"},
      {"eye=1,inf,3:look=0,0,0", "'inf' is not a finite number"},
      {"eye=1, 2,3:look=0,0,0", "' 2' is not a finite number"},
      {"eye=1,2,3", "no look=X,Y,Z part"},
      {"look=1,2,3:fov=40", "no eye=X,Y,Z part"},
      {"eye=1,2,3:look=0,0,0:pos=1,1,1", "unknown part 'pos=1,1,1'"},
      {"eye=1,2,3:look=0,0,0:up", "unknown part 'up'"},
      {"eye=1,2,3::look=0,0,0", "empty part"},
      {"eye=1,2,3:look=0,0,0:", "empty part"},
      {"eye=1,2,3:eye=0,0,0", "eye is given twice"},
      {"eye=1,2,3:look=0,0,0:fov=abc", "'fov=abc': 'abc' is not a number"},
      {"eye=1,2,3:look=0,0,0:fov=180", "fov 180 is outside (0, 180) degrees"},
      {"eye=1,2,3:look=0,0,0:fov=0", "fov 0 is outside"},
      {"eye=1,2,3:look=1,2,3", "look is the same point as eye"},
      {"eye=0,0,0:look=0,5,0:up=0,2,0", "up (0,2,0) is parallel to the view"},
      {"eye=0,0,0:look=1,0,0:up=0,0,0", "up must not be zero"},
      {"eye=0,0,0 look=1,0,0", "'eye=0,0,0 look=1,0,0' needs three numbers"},
      {"eye=1e31,0,0:look=0,0,0", "eye (1e+31,0,0) is beyond +-1e30"},
      {"eye=0,0,0:look=0,-2e30,0", "look (0,-2e+30,0) is beyond +-1e30"},
  };
  for (const auto& [text, message] : cases) {
    // (clang 14, the TSan build's compiler, cannot capture a structured binding.)
    const std::string& spec = text;
    const std::string e = error_of<std::invalid_argument>([&] { (void)parse_camera_spec(spec); });
    EXPECT_TRUE(contains(e, message)) << "'" << text << "' gave: " << e;
  }
}

// `--camera` could not fix only the up axis: "up=X,Y,Z" alone (or after "auto:") asks
// for the automatic camera with that up, along +x, +y or +z.
TEST(CameraSpec, UpAloneAsksForTheAutomaticCameraWithThatUp) {
  EXPECT_EQ(automatic_camera_up("up=0,0,1"), 2);
  EXPECT_EQ(automatic_camera_up("auto:up=2.5,0,0"), 0);
  EXPECT_EQ(automatic_camera_up("up=0,1,0"), 1);
  EXPECT_FALSE(automatic_camera_up("auto").has_value());
  EXPECT_FALSE(automatic_camera_up("eye=0,0,0:look=1,0,0:up=0,0,1").has_value());
  EXPECT_TRUE(contains(error_of([] { (void)automatic_camera_up("up=0,1,1"); }),
                       "takes up along +x, +y or +z"));
  EXPECT_TRUE(contains(error_of([] { (void)automatic_camera_up("up=0,0,-1"); }), "not (0,0,-1)"));
  EXPECT_TRUE(
      contains(error_of([] { (void)automatic_camera_up("up=0,1"); }), "needs three numbers"));
}

// A room 4 wide, 3 deep and 3 high (z up) faces as much area along y as along z: OBJ
// (y up by convention) calls it y-up; MGF, drawn z-up by RenderPark and Radiance, z-up
// (its image came out rotated 90 degrees); a declared up wins over both.
TEST(SceneUpAxis, MgfRoomsAreZUpUnlessClearlyNot) {
  Scene room;
  const auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
    const auto first = static_cast<std::uint32_t>(room.indices.size());
    for (const Vec3& v : {a, b, c, d}) {
      room.indices.push_back(static_cast<std::uint32_t>(room.vertices.size()));
      room.vertices.push_back(v);
    }
    room.faces.push_back(Face{first, 4, 0});
  };
  quad({0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0});  // floor and ceiling: 24 along z
  quad({0, 0, 3}, {0, 3, 3}, {4, 3, 3}, {4, 0, 3});
  quad({0, 0, 0}, {0, 0, 3}, {4, 0, 3}, {4, 0, 0});  // two walls: 24 along y
  quad({0, 3, 0}, {4, 3, 0}, {4, 3, 3}, {0, 3, 3});
  room.source = "room.obj";
  EXPECT_EQ(room.up_axis(), 1);
  room.source = "rooms/room.MGF";
  EXPECT_EQ(room.up_axis(), 2);
  room.declared_up = 0;
  EXPECT_EQ(room.up_axis(), 0);
}

TEST(CameraSpec, ResolvingNamesAViewAlongTheDefaultUp) {
  const CameraSpec s = parse_camera_spec("eye=0,10,0:look=0,0,0");
  const std::string e =
      error_of<std::invalid_argument>([&] { (void)resolve_camera(s, Vec3::UnitY()); });
  EXPECT_TRUE(contains(e, "parallel to the scene's up axis (0,1,0); give up=X,Y,Z")) << e;
  EXPECT_EQ(resolve_camera(s, Vec3::UnitZ()).up, Vec3::UnitZ());
  // A far eye is no reason: the products overflowed, and every view was "parallel".
  const CameraSpec far = parse_camera_spec("eye=1e29,1e29,1e29:look=0,0,0");
  EXPECT_EQ(resolve_camera(far, Vec3::UnitY()).eye, Vec3::Constant(1e29));
}

TEST(CameraSpec, SpecStringReadsBackExactly) {
  Camera c;
  c.eye = Vec3(0.1, 1.0 / 3.0, -2e-17);
  c.target = Vec3(1e30, 5, 7.25);
  c.up = Vec3(0.2, 0.9, 0.1);
  c.fov_y_deg = 39.3;
  const std::string text = camera_spec_string(c);
  EXPECT_TRUE(text.rfind("eye=0.1,", 0) == 0) << text;
  const Camera back = resolve_camera(parse_camera_spec(text), Vec3::UnitY());
  EXPECT_EQ(back.eye, c.eye);
  EXPECT_EQ(back.target, c.target);
  EXPECT_EQ(back.up, c.up);
  EXPECT_EQ(back.fov_y_deg, c.fov_y_deg);
}

// --- the view file ------------------------------------------------------------------

TEST(ViewFile, ReadsKeywordsWithCommentsAndBlankLines) {
  const TempDir dir;
  const fs::path f = dir.write("room.view",
                               "# the room from its door\n\n  eye 1 1.7 -2  # standing\n"
                               "look\t4 1 3\nfov 50\n");
  const CameraSpec s = read_view_file(f);
  EXPECT_EQ(s.eye, Vec3(1, 1.7, -2));
  EXPECT_EQ(s.look, Vec3(4, 1, 3));
  EXPECT_FALSE(s.up);
  ASSERT_TRUE(s.fov_deg);
  EXPECT_EQ(*s.fov_deg, 50);
  EXPECT_EQ(*read_view_file(dir.write("up.view", "up 0 0 1\neye 1 2 3\nlook 0 0 0\n")).up,
            Vec3::UnitZ());
}

TEST(ViewFile, ErrorsNameTheFileAndLine) {
  const TempDir dir;
  const std::map<std::string, std::string> cases = {
      {"eye 1 2 3\nlook 0 0\n", "v.view:2: 'look' needs 3 numbers, got 2"},
      {"# c\neye 1 2 3\nlook 0 0 0\nfov 30 40\n", "v.view:4: 'fov' needs 1 number, got 2"},
      {"eye 1 2 3\n\nlook 0 zero 0\n", "v.view:3: 'zero' is not a finite number"},
      {"eye 1 2 3\nlook 0 0 0\nposition 1 1 1\n", "v.view:3: unknown keyword 'position'"},
      {"eye 1 2 3\nlook 0 0 0\neye 1 1 1\n", "v.view:3: 'eye' is given twice (first on line 1)"},
      {"eye 1 2 3\nlook 0 0 0\nfov 200\n", "v.view:3: fov 200 is outside (0, 180)"},
      {"eye 1 2 3\nlook 0 0 0\nup 0 0 0\n", "v.view:3: up must not be zero"},
      {"eye 1 2 3\n", "v.view: no 'look X Y Z' line"},
      {"# nothing\n", "v.view: no 'eye X Y Z' line"},
      {"eye 1 2 3\nlook 1 2 3\n", "v.view:2: look is the same point as eye"},
      {"eye 0 0 0\nlook 0 1 0\nup 0 3 0\n", "v.view:3: up (0,3,0) is parallel to the view"},
  };
  for (const auto& [text, message] : cases) {
    const fs::path f = dir.write("v.view", text);
    std::string e = error_of<InputError>([&] { (void)read_view_file(f); });
    // Messages start with the path as given; compare from the file name on.
    if (const auto at = e.find("v.view"); at != std::string::npos) e = e.substr(at);
    EXPECT_TRUE(contains(e, message)) << text << "gave: " << e;
  }
  const std::string e = error_of<InputError>([&] { (void)read_view_file("no/such.view"); });
  EXPECT_TRUE(contains(e, "no/such.view: the view file does not exist")) << e;
}

// --- the automatic camera -----------------------------------------------------------

Scene load_thick_box(const TempDir& dir) {
  const auto [obj, mtl] = test::thick_box_obj();
  dir.write("thick.mtl", mtl);
  return load_scene(dir.write("thick.obj", obj).string());
}

/// Distinct 8-bit colours that each cover at least 1% of a 160 x 120 picture (the
/// background not counted), each face shown in its reflectance shaded by its
/// orientation (an image of a flat-lit box would look the same from every side).
int colours_seen(const Scene& scene, const Camera& cam) {
  RenderMesh mesh = render_mesh_from_emission(scene);  // every face has its own vertices
  const Vec3 light = Vec3(0.3, 0.8, 0.5).normalized();
  for (const auto& q : mesh.polys) {
    const std::array<Vec3, 3> p = {mesh.positions[q[0]], mesh.positions[q[1]],
                                   mesh.positions[q[2]]};
    const double shade = 0.2 + std::abs(polygon_normal(p).dot(light));
    for (int c = 0; c < (RenderMesh::is_triangle(q) ? 3 : 4); ++c)
      mesh.radiosity[q[c]] += shade * mesh.reflectance[q[c]];
  }
  const Image img = render_radiance(mesh, cam, 160, 120);
  std::map<std::array<std::uint8_t, 3>, int> count;
  for (std::size_t i = 0; i < img.radiance.size(); ++i)
    if (img.coverage[i] > 0) ++count[tone_map(img.radiance[i], 1.0, ToneMap{})];
  int seen = 0;
  for (const auto& [colour, n] : count) seen += n >= 0.01 * 160 * 120;
  return seen;
}

TEST(AutoCamera, SeesAThickWalledRoomFromItsFreeInterior) {
  const TempDir dir;
  const Scene scene = load_thick_box(dir);
  ASSERT_FALSE(scene.camera);
  const AutoCamera a = automatic_camera(scene);
  EXPECT_EQ(a.view, "interior");
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GT(a.camera.eye[axis], test::kWall) << axis;
    EXPECT_LT(a.camera.eye[axis], test::kRoom - test::kWall) << axis;
  }
  EXPECT_EQ(a.camera.up, Vec3::UnitY());
  // Not one flat colour: several walls (and the floor or the block) are in view.
  EXPECT_GE(colours_seen(scene, a.camera), 3);
  // The camera of before looks at the outside of one wall.
  EXPECT_EQ(colours_seen(scene, scene.default_camera()), 1);
  EXPECT_GT(a.rays, 0u);
}

TEST(AutoCamera, IsDeterministic) {
  const TempDir dir;
  const Scene scene = load_thick_box(dir);
  const AutoCamera a = automatic_camera(scene), b = automatic_camera(scene);
  EXPECT_EQ(a.camera.eye, b.camera.eye);
  EXPECT_EQ(a.camera.target, b.camera.target);
}

TEST(AutoCamera, LooksAtOpenScenesFromOutside) {
  // The Cornell box (open front) and a lone cube (outward faces): from outside.
  const TempDir dir;
  const std::string cube =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
      "f 1 5 7 3\nf 2 4 8 6\nf 1 2 6 5\nf 3 7 8 4\nf 1 3 4 2\nf 5 6 8 7\n";
  for (const Scene& scene :
       {make_builtin("builtin:cornell"), load_scene(dir.write("cube.obj", cube).string())}) {
    const AutoCamera a = automatic_camera(scene);
    const Aabb b = scene.bounds();
    EXPECT_EQ(a.view, "open side") << scene.name;
    EXPECT_FALSE((a.camera.eye.array() > b.lo.array()).all() &&
                 (a.camera.eye.array() < b.hi.array()).all())
        << scene.name;
    EXPECT_GE(colours_seen(scene, a.camera), 1) << scene.name;  // it is in view
  }
}

TEST(AutoCamera, CastsAFixedNumberOfRaysOnTheOfficeAndTheCabin) {
  for (const char* spec : {"builtin:office", "builtin:cabin"}) {
    const Scene scene = make_builtin(spec);
    const AutoCamera a = automatic_camera(scene);
    EXPECT_EQ(a.view, "interior") << spec;
    const Aabb b = scene.bounds();
    EXPECT_TRUE((a.camera.eye.array() > b.lo.array()).all() &&
                (a.camera.eye.array() < b.hi.array()).all())
        << spec;
    std::printf("%s: %zu polygons, automatic camera in %.4f s, %llu rays\n", spec,
                scene.polygon_count(), a.seconds, static_cast<unsigned long long>(a.rays));
    // Its cost is a fixed number of rays, whatever the scene's size (typically 0.01 s and
    // 0.05 s here, not bounded by the clock): 5 x 5 x 5 candidates x 48 sphere rays, and
    // for the 16 kept, 8 azimuths x 2 pitches x (8 x 6 score rays + 1 for the look point).
    EXPECT_EQ(a.rays, 125u * 48 + 16u * 16 * (8 * 6 + 1)) << spec;
  }
}

}  // namespace
}  // namespace hrad
