#include "core/scene/probes.h"

#include "core/base/input_error.h"
#include "core/scene/builtin_scenes.h"
#include "core/scene/scene.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <limits>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace hrad {
namespace {

std::filesystem::path temp_path(const std::string& name) {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::temp_directory_path() /
         (std::string("hrad_") + info->name() + "_" + std::to_string(::getpid()) + "_" + name);
}

/// Expects parse_probes(text) to fail at `line` with a message containing `what`.
void expect_error(const std::string& text, int line, const std::string& what) {
  try {
    (void)parse_probes(text, "p.txt");
    ADD_FAILURE() << "no error for: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "p.txt");
    EXPECT_EQ(e.line(), line) << e.what();
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("p.txt:" + std::to_string(line) + ": ", 0), 0u) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

TEST(Probes, ParsesPointsCommentsBlankLinesAndNormalisesNormals) {
  const std::string text =
      "# probes for the office\n"
      "\n"
      "1 2 3 0 0 1\n"
      "  -0.5\t+2.5e-1  1e3   0 2 0   # on the floor\r\n"
      "   \t\n"
      "0 0 0 3 0 4";  // no final newline
  const auto probes = parse_probes(text, "p.txt");
  ASSERT_EQ(probes.size(), 3u);
  EXPECT_EQ(probes[0].p, Vec3(1, 2, 3));
  EXPECT_EQ(probes[0].n, Vec3(0, 0, 1));
  EXPECT_EQ(probes[1].p, Vec3(-0.5, 0.25, 1000));
  EXPECT_EQ(probes[1].n, Vec3(0, 1, 0));
  EXPECT_NEAR((probes[2].n - Vec3(0.6, 0, 0.8)).norm(), 0, 1e-15);
  EXPECT_TRUE(parse_probes("", "p.txt").empty());
  EXPECT_TRUE(parse_probes("# nothing\n\n", "p.txt").empty());
}

TEST(Probes, ReportsBadLinesWithFileAndLine) {
  expect_error("1 2 3 0 0 1\n1 2 3 0 0\n", 2, "expected 6 numbers");
  expect_error("1 2 3 0 0 1 7\n", 1, "found 7 fields");
  expect_error("# c\n\n1 2 x 0 0 1\n", 3, "field 3 'x' is not a number");
  expect_error("1 2 3 0 0 1,\n", 1, "field 6 '1,' is not a number");
  expect_error("1 2 3 nan 0 1\n", 1, "not finite");
  expect_error("1 2 3 0 0 inf\n", 1, "not finite");
  expect_error("1 2 3 0 0 1\n\n\n4 5 6 0 0 0\n", 4, "normal");
  expect_error("1 2 3 0 0 1e-400\n", 1, "field 6 '1e-400' is out of double range");
  expect_error("1e999 2 3 0 0 1\n", 1, "field 1 '1e999' is out of double range");
}

TEST(Probes, ReadsFilesAndNamesMissingOnes) {
  const auto path = temp_path("probes.txt");
  {
    std::ofstream out(path);
    out << "0.5 0.5 0 0 0 1\n1 1 1 0 -1 0\nbad\n";
  }
  try {
    (void)read_probes(path.string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.line(), 3);
  }
  {
    std::ofstream out(path);
    out << "0.5 0.5 0 0 0 1\n1 1 1 0 -1 0\n";
  }
  EXPECT_EQ(read_probes(path.string()).size(), 2u);
  std::filesystem::remove(path);
  try {
    (void)read_probes(path.string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 0);
    EXPECT_NE(std::string(e.what()).find("the probe file does not exist"), std::string::npos);
  }
}

TEST(Probes, CsvHasHeaderAndNineSignificantDigits) {
  const std::vector<Probe> probes = {{Vec3(1, 2, 3), Vec3(0, 0, 1)},
                                     {Vec3(1.0 / 3, -2.5e-7, 1e20), Vec3(0, -1, 0)}};
  const std::vector<Rgb> e = {Rgb(0.1, 0, 123456789.0), Rgb(2.0 / 3, 1e-300, 7)};
  const auto path = temp_path("probes.csv");
  write_probes_csv(path, probes, e);
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  std::filesystem::remove(path);
  EXPECT_EQ(s.str(),
            "x,y,z,nx,ny,nz,E_r,E_g,E_b\n"
            "1,2,3,0,0,1,0.1,0,123456789\n"
            "0.333333333,-2.5e-07,1e+20,0,-1,0,0.666666667,1e-300,7\n");
  EXPECT_THROW(write_probes_csv(path, probes, {Rgb::Zero()}), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path));
  // No non-finite value reaches the file.
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(write_probes_csv(path, probes, {Rgb(1, 1, 1), Rgb(inf, 0, 0)}),
               std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path));
}

// Random surface probes lie on the scene's faces (lifted by 1e-6 of the diagonal along
// the face normal, which is theirs), spread by area, reproducible from the seed, and
// round-trip through the probe file format.
TEST(Probes, RandomSurfaceProbesLieOnFacesByArea) {
  const Scene scene = make_builtin("builtin:furnace?objects=0");  // unit room, 6 faces
  const auto a = random_surface_probes(scene, 600, 5);
  const auto b = random_surface_probes(scene, 600, 5);
  const auto c = random_surface_probes(scene, 600, 6);
  ASSERT_EQ(a.size(), 600u);
  const double lift = 1e-6 * scene.bounds().diagonal();
  int per_face[6] = {0, 0, 0, 0, 0, 0};
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].p, b[i].p);
    bool on_a_face = false;
    for (std::size_t f = 0; f < scene.faces.size(); ++f) {
      const Vec3 n = scene.face_normal(f);
      const Vec3 v0 = scene.vertices[scene.indices[scene.faces[f].first]];
      if ((a[i].n - n).norm() < 1e-12 && std::abs(n.dot(a[i].p - v0) - lift) < 1e-12) {
        on_a_face = true;
        ++per_face[f];
      }
    }
    EXPECT_TRUE(on_a_face) << i;
  }
  // Six equal faces: 100 each expected, 5 sigma (about 46) allowed.
  for (int n : per_face) EXPECT_NEAR(n, 100, 46);
  EXPECT_NE(a[0].p, c[0].p);
  const auto back = parse_probes(probes_text(a, "random"), "r.txt");
  ASSERT_EQ(back.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_LT((back[i].p - a[i].p).norm(), 1e-8);
}

}  // namespace
}  // namespace hrad
