// End-to-end tests of the camera of `hrad solve`: --camera, --view, the config key,
// SCENE.view, the automatic camera, and what stats.json records of them.
#include "tests/cli_fixture.h"
#include "tests/read_text.h"
#include "tests/thick_box.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <set>
#include <string>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

namespace {

namespace fs = std::filesystem;

using hrad::test::Cli;
using hrad::test::contains;
using hrad::test::read_text;
using hrad::test::Result;

class CliCamera : public Cli {
 protected:
  /// Solves quickly into `out` and returns stats.json's "camera".
  nlohmann::json camera_of(const std::string& args, const std::string& out = "run") const {
    const Result r =
        hrad("solve " + args + " --iterations 1 --set image_width=32 --quiet --out " + out);
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    if (r.status != 0) return nullptr;
    return nlohmann::json::parse(read_text(dir_ / out / "stats.json"))["camera"];
  }
  void write_thick_box() const {
    const auto [obj, mtl] = hrad::test::thick_box_obj();
    write("thick.obj", obj);
    write("thick.mtl", mtl);
  }
};

TEST_F(CliCamera, StatsJsonRecordsTheCameraAndHowItWasChosen) {
  // The built-in scene's own camera.
  nlohmann::json c = camera_of("builtin:cornell");
  EXPECT_EQ(c["source"], "scene");
  EXPECT_EQ(c["eye"], nlohmann::json::parse("[2.78, 2.73, -8.0]"));
  EXPECT_EQ(c["look"], nlohmann::json::parse("[2.78, 2.73, 0.0]"));
  EXPECT_EQ(c["up"], nlohmann::json::parse("[0.0, 1.0, 0.0]"));
  EXPECT_EQ(c["fov"], 39.3);
  EXPECT_TRUE(c["view_file"].is_null());
  EXPECT_EQ(c["spec"], "eye=2.78,2.73,-8:look=2.78,2.73,0:up=0,1,0:fov=39.3");

  // --camera, with up and fov defaulted.
  c = camera_of("builtin:cornell --camera eye=2.5,2.7,-6:look=2.5,2,1");
  EXPECT_EQ(c["source"], "option");
  EXPECT_EQ(c["eye"], nlohmann::json::parse("[2.5, 2.7, -6.0]"));
  EXPECT_EQ(c["up"], nlohmann::json::parse("[0.0, 1.0, 0.0]"));
  EXPECT_EQ(c["fov"], 60.0);

  // The config key; --set beats it; --camera auto asks for the automatic camera.
  write("c.json", R"({"camera": "eye=1,2,-5:look=1,2,0:up=0,1,0:fov=50"})");
  c = camera_of("builtin:cornell --config c.json");
  EXPECT_EQ(c["source"], "config");
  EXPECT_EQ(c["fov"], 50.0);
  const nlohmann::json stats = nlohmann::json::parse(read_text(dir_ / "run" / "stats.json"));
  EXPECT_EQ(stats["config"]["camera"], "eye=1,2,-5:look=1,2,0:up=0,1,0:fov=50");
  c = camera_of("builtin:cornell --config c.json --set camera=eye=1,1,-5:look=1,1,0");
  EXPECT_EQ(c["source"], "option");
  EXPECT_EQ(c["eye"], nlohmann::json::parse("[1.0, 1.0, -5.0]"));
  c = camera_of("builtin:cornell --camera auto");
  EXPECT_EQ(c["source"], "automatic");
  EXPECT_EQ(c["automatic"]["view"], "open side");  // its front is open
  EXPECT_GT(c["automatic"]["rays"].get<int>(), 0);

  // The spec recorded gives the same camera again.
  const nlohmann::json again =
      camera_of("builtin:cornell --camera " + c["spec"].get<std::string>());
  for (const char* key : {"eye", "look", "up", "fov", "spec"}) EXPECT_EQ(again[key], c[key]) << key;
}

TEST_F(CliCamera, ViewFilesGivenOrBesideTheScene) {
  write_thick_box();
  write("thick.view", "# beside the scene\neye 2 5 2\nlook 8 4 8\n");
  write("other.view", "eye 8 5 8\nlook 2 4 2\nup 0 1 0\nfov 70\n");
  nlohmann::json c = camera_of("thick.obj");
  EXPECT_EQ(c["source"], "view file");
  EXPECT_EQ(c["view_file"], "thick.view");
  EXPECT_EQ(c["eye"], nlohmann::json::parse("[2.0, 5.0, 2.0]"));
  c = camera_of("thick.obj --view other.view");
  EXPECT_EQ(c["view_file"], "other.view");
  EXPECT_EQ(c["fov"], 70.0);
  // The camera key on the command line or in the config beats SCENE.view.
  EXPECT_EQ(camera_of("thick.obj --camera eye=5,5,5:look=5,5,9")["source"], "option");
  write("c.json", R"({"camera": "eye=5,5,5:look=9,5,5"})");
  EXPECT_EQ(camera_of("thick.obj --config c.json")["source"], "config");
  // --view beats the config.
  EXPECT_EQ(camera_of("thick.obj --config c.json --view other.view")["view_file"], "other.view");
}

TEST_F(CliCamera, BadCamerasAreNamedAndCreateNoFolder) {
  write_thick_box();
  const auto fails = [&](const std::string& args, const std::string& message) {
    const Result r = hrad("solve " + args + " --out run");
    EXPECT_EQ(r.status, 1) << args;
    EXPECT_TRUE(contains(r.err, message)) << args << "\n" << r.err;
  };
  fails("thick.obj --camera eye=1,2:look=0,0,0",
        "hrad: --camera: option 'camera' = 'eye=1,2:look=0,0,0': 'eye=1,2' needs three numbers");
  fails("thick.obj --camera eye=1,2,3:look=0,0,0:zoom=2", "unknown part 'zoom=2'");
  fails("thick.obj --set camera=look=1,2,3", "no eye=X,Y,Z part");
  fails("thick.obj --camera eye=5,9,5:look=5,1,5",
        "parallel to the scene's up axis (0,1,0); give up=X,Y,Z");
  write("c.json", R"({"camera": "eye=1,2,3:look=0,0,0:fov=-1"})");
  fails("thick.obj --config c.json",
        "c.json: option 'camera' = 'eye=1,2,3:look=0,0,0:fov=-1': fov -1");
  write("bad.view", "eye 1 2 3\nlook 4 5\n");
  fails("thick.obj --view bad.view", "hrad: bad.view:2: 'look' needs 3 numbers, got 2");
  fails("thick.obj --view missing.view", "missing.view: the view file does not exist");
  write("thick.view", "eye 1 2 3\nfocus 4 5 6\n");
  fails("thick.obj", "thick.view:2: unknown keyword 'focus'");
  write("good.view", "eye 2 2 2\nlook 5 5 5\n");
  fails("thick.obj --view good.view --camera eye=2,2,2:look=5,5,5", "--view and --camera");
  EXPECT_FALSE(fs::exists(dir_ / "run"));
}

TEST_F(CliCamera, AutomaticCameraSeesInsideAThickWalledRoom) {
  // Walls 10% of the room thick: the camera of before stood outside a wall, and the
  // picture was one flat colour (the unlit outside of the wall).
  write_thick_box();
  const Result r = hrad("solve thick.obj --iterations 2 --set image_width=80 --quiet --out run");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json c = nlohmann::json::parse(read_text(dir_ / "run" / "stats.json"))["camera"];
  EXPECT_EQ(c["source"], "automatic");
  EXPECT_EQ(c["automatic"]["view"], "interior");
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GT(c["eye"][axis].get<double>(), hrad::test::kWall) << axis;
    EXPECT_LT(c["eye"][axis].get<double>(), hrad::test::kRoom - hrad::test::kWall) << axis;
  }
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load((dir_ / "run" / "render.png").string().c_str(), &w, &h, &n, 3);
  ASSERT_NE(px, nullptr);
  ASSERT_EQ(w, 80);
  std::set<std::array<std::uint8_t, 3>> values;
  for (int i = 0; i < w * h; ++i) values.insert({px[3 * i], px[3 * i + 1], px[3 * i + 2]});
  stbi_image_free(px);
  EXPECT_GE(values.size(), 10u);  // lit walls, floor, block and light, in shades
}

}  // namespace
