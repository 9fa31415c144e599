// End-to-end tests of the image options of `hrad solve`: --hdr (a Portable Float Map of
// the radiance), --exposure (stops over the automatic exposure), --shading, and the
// "image" block of stats.json.
#include "core/output/pfm.h"
#include "tests/cli_fixture.h"
#include "tests/read_text.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>
#include <string>

namespace {

using hrad::test::Cli;
using hrad::test::contains;
using hrad::test::read_text;
using hrad::test::Result;

// Every face of the furnace emits E = 1 and reflects nothing, so B = 1 everywhere and
// every pixel (the camera stands inside the closed room) shows L = B / pi.
constexpr const char* kFurnace = "solve 'builtin:furnace?rho=0' --iterations 1 --quiet";

nlohmann::json stats(const std::filesystem::path& dir) {
  return nlohmann::json::parse(read_text(dir / "stats.json"));
}

TEST_F(Cli, HdrImageHoldsTheRadianceOfAKnownScene) {
  const Result r = hrad(std::string(kFurnace) + " --set image_width=64 --hdr hdr/f.pfm --out run");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string bytes = read_text(dir_ / "hdr" / "f.pfm");
  const std::string header = "PF\n64 48\n-1.0\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  const hrad::Image img = hrad::decode_pfm(bytes);
  for (std::size_t i = 0; i < img.radiance.size(); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(img.radiance[i][c], 1 / std::numbers::pi, 1e-6) << "pixel " << i;
  const nlohmann::json j = stats(dir_ / "run");
  EXPECT_EQ(j["outputs"]["hdr"], "hdr/f.pfm");
  EXPECT_EQ(j["image"]["shading"], "smooth");
  EXPECT_EQ(j["image"]["width"], 64);
  EXPECT_EQ(j["image"]["height"], 48);
  // Automatic exposure: the key 0.18 over the log-average luminance 1 / pi.
  EXPECT_NEAR(j["image"]["exposure"]["automatic"].get<double>(), 0.18 * std::numbers::pi, 1e-6);
  EXPECT_EQ(j["image"]["exposure"]["stops"], 0.0);
  EXPECT_EQ(j["image"]["exposure"]["applied"], j["image"]["exposure"]["automatic"]);
}

TEST_F(Cli, ExposureStopsScaleTheAutomaticExposure) {
  ASSERT_EQ(hrad(std::string(kFurnace) + " --set image_width=16 --exposure -1.5 --out a").status,
            0);
  const nlohmann::json e = stats(dir_ / "a")["image"]["exposure"];
  EXPECT_EQ(e["stops"], -1.5);
  EXPECT_NEAR(e["applied"].get<double>(), e["automatic"].get<double>() * std::exp2(-1.5), 1e-12);
  EXPECT_EQ(stats(dir_ / "a")["config"]["exposure"], -1.5);
  // The config key does the same.
  write("c.json", R"({"exposure": 2, "shading": "flat"})");
  ASSERT_EQ(hrad(std::string(kFurnace) + " --set image_width=16 --config c.json --out b").status,
            0);
  const nlohmann::json b = stats(dir_ / "b")["image"];
  EXPECT_NEAR(b["exposure"]["applied"].get<double>(), 4 * b["exposure"]["automatic"].get<double>(),
              1e-12);
  EXPECT_EQ(b["shading"], "flat");
}

TEST_F(Cli, BadImageOptionsAreNamedAndCreateNoFolder) {
  const struct {
    const char* args;
    const char* says;
  } cases[] = {
      {"--shading gouraud", "shading"}, {"--exposure 100", "exposure"},
      {"--exposure nan", "exposure"},   {"--set shading=", "shading"},
      {"--hdr out.exr", ".pfm"},
  };
  for (const auto& c : cases) {
    const Result r = hrad(std::string(kFurnace) + " " + c.args + " --out run");
    EXPECT_EQ(r.status, 1) << c.args;
    EXPECT_TRUE(contains(r.err, c.says)) << c.args << ": " << r.err;
    EXPECT_EQ(entries(), 0) << c.args;
  }
}

}  // namespace

namespace {

hrad::Image read_pfm_file(const std::filesystem::path& p) { return hrad::decode_pfm(read_text(p)); }

// The largest difference between two pictures of the same size, relative to the
// brightest pixel of the first.
double largest_difference(const hrad::Image& a, const hrad::Image& b) {
  double most = 0, brightest = 0;
  for (std::size_t i = 0; i < a.radiance.size(); ++i) {
    most = std::max(most, (a.radiance[i] - b.radiance[i]).abs().maxCoeff());
    brightest = std::max(brightest, a.radiance[i].maxCoeff());
  }
  return most / brightest;
}

}  // namespace

// `hrad render` draws a solved scene again from its solution.ply: with the solve's
// defaults it gives the solve's picture (up to the mesh's 32-bit floats), and another
// camera, width, samples or exposure changes only what it should.
TEST_F(Cli, RenderDrawsASolveAgainFromItsMesh) {
  ASSERT_EQ(
      hrad("solve builtin:cornell --set image_width=64 --hdr solve.pfm --out run --quiet").status,
      0);
  Result r = hrad("render run --hdr again.pfm");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "64 x 48 pixels, 4 samples per pixel")) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "run" / "rerender.png"));
  const hrad::Image solve = read_pfm_file(dir_ / "solve.pfm");
  const hrad::Image again = read_pfm_file(dir_ / "again.pfm");
  ASSERT_EQ(again.width, 64);
  ASSERT_EQ(again.height, 48);
  // 32-bit floats hold positions and radiosity to about 1e-7 of their size (measured
  // here: 5e-8 of the brightest pixel).
  EXPECT_LT(largest_difference(solve, again), 1e-5);
  // Another camera (nearer the box) and size: the box fills more of the picture.
  r = hrad(
      "render run/solution.ply --camera eye=2.78,2.73,-2:look=2.78,2.73,0:fov=60 "
      "--width 32 --samples 1 --exposure 1 --image near/n.png");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "32 x 24 pixels, 1 samples per pixel")) << r.out;
  EXPECT_TRUE(contains(r.out, "(+1 stops over automatic)")) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "near" / "n.png"));
  // What cannot be done is said.
  r = hrad("render run --camera auto");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "does not load")) << r.err;
  r = hrad("render nowhere");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "nowhere: neither a solve's output folder nor a solution.ply"))
      << r.err;
  write("bad.ply", "ply\nformat ascii 1.0\n");
  r = hrad("render bad.ply --camera eye=0,0,-1:look=0,0,0");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "bad.ply")) << r.err;
}
