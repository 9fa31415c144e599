// What the commands say about a scene, end to end: an experiment's scene files are
// read before its result folder is made, and each warning about a scene is printed
// once.
#include "tests/cli_fixture.h"

#include <gtest/gtest.h>

#include <string>

namespace {

using hrad::test::contains;
using hrad::test::Result;
namespace fs = std::filesystem;

using SceneChecks = hrad::test::Cli;

// A closed unit box facing in (with room.mtl), 17 lines; its ceiling emits when `lit`.
std::string box(bool lit) {
  std::string s = "mtllib room.mtl\n";
  for (const char* v : {"0 0 0", "1 0 0", "1 1 0", "0 1 0", "0 0 1", "1 0 1", "1 1 1", "0 1 1"})
    s += std::string("v ") + v + "\n";
  return s +
         "usemtl wall\nf 1 2 3 4\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n"
         "usemtl " +
         (lit ? "light" : "wall") + "\nf 5 8 7 6\n";
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// An experiment whose scene file does not parse made its result folder (manifest
// "failed", a runs.csv with no run), and --resume failed the same way. Every scene
// file is read before the folder is made, and the error names the file and line.
TEST_F(SceneChecks, AnExperimentsSceneThatDoesNotParseMakesNoFolder) {
  write("room.mtl", "newmtl wall\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0 0 0\nKe 1 1 1\n");
  write("broken.obj", box(true) + "f 1 2 99\n");
  write("exp.json",
        R"({"name": "x", "scenes": ["builtin:cornell", "broken.obj"], "sweep": {"threads": [1]}})");
  refused("experiment exp.json --out x --no-plot",
          "broken.obj:18: vertex index 99 is out of range");
  refused("experiment exp.json --dry-run --no-estimate", "broken.obj:18:");
  EXPECT_FALSE(fs::exists(dir_ / "x"));
}

// "no face emits light" came with "scene has no emitter" (the same fact, twice) from
// solve, and again for every run of an experiment.
TEST_F(SceneChecks, EachWarningAboutASceneIsPrintedOnce) {
  write("room.mtl", "newmtl wall\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0 0 0\nKe 1 1 1\n");
  write("dark.obj", box(false));
  Result r = hrad("solve dark.obj --out run --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(count(r.err, "hrad: warning:"), 1) << r.err;
  EXPECT_EQ(count(r.err, "emit"), 1) << r.err;
  r = hrad("reference dark.obj --random-probes 2 --out ref --quiet");
  EXPECT_EQ(count(r.err, "emit"), 1) << r.err;
  write("exp.json",
        R"({"name": "x", "scenes": ["dark.obj"], "sweep": {"threads": [1]}, "repetitions": 2})");
  r = hrad("experiment exp.json --out x --no-plot");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(count(r.err, "emit"), 1) << r.err;
  // A floor given again as two triangles: the overlap warning, once.
  write("twice.obj", box(true) + "usemtl wall\nf 1 2 3\nf 1 3 4\n");
  r = hrad("solve twice.obj --iterations 1 --out run2 --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(count(r.err, "lie in one plane"), 1) << r.err;
}

}  // namespace
