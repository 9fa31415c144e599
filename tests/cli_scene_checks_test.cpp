// What the commands say about a scene, end to end: an experiment's scene files are
// read before its result folder is made, and each warning about a scene is printed
// once.
#include "tests/cli_fixture.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace {

using hrad::test::contains;
using hrad::test::read_text;
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

// The probes' irradiance (first channel) from a run's probes.csv.
std::vector<double> probe_values(const std::string& csv) {
  std::vector<double> out;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string cell;
    for (int k = 0; k < 7 && std::getline(row, cell, ','); ++k) {
    }
    out.push_back(std::stod(cell));
  }
  return out;
}

// A floor given again, as two triangles or as two halves that overlap, was solved as
// two floors: probes 35-48 % too bright. Now each part of it is solved once: the copy
// gives the plain box's answer exactly, the halves within the mesh's difference.
TEST_F(SceneChecks, AFloorGivenTwiceIsSolvedOnce) {
  write("room.mtl", "newmtl wall\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0 0 0\nKe 1 1 1\n");
  const std::string lit = box(true);
  const std::string walls = lit.substr(0, lit.find("f 1 2 3 4\n")) +
                            lit.substr(lit.find("f 1 2 3 4\n") + 10);  // without the floor
  write("plain.obj", lit);
  write("twice.obj", lit + "usemtl wall\nf 1 2 3\nf 1 3 4\n");
  write("halves.obj", walls + "v 0.6 0 0\nv 0.6 1 0\nv 0.4 0 0\nv 0.4 1 0\n" +
                          "usemtl wall\nf 1 9 10 4\nf 11 2 3 12\n");
  write("probes.txt",
        "0.5 0.5 0.999 0 0 -1\n0.2 0.7 0.999 0 0 -1\n0.5 0.001 0.5 0 1 0\n"
        "0.5 0.5 0.001 0 0 1\n0.8 0.2 0.001 0 0 1\n");
  std::vector<std::vector<double>> e;
  for (const char* s : {"plain", "twice", "halves"}) {
    const Result r =
        hrad(std::string("solve ") + s + ".obj --probes probes.txt --out " + s + " --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    e.push_back(probe_values(read_text(dir_ / s / "probes.csv")));
    ASSERT_EQ(e.back().size(), 5u);
  }
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(e[1][i], e[0][i]) << "probe " << i;
    EXPECT_NEAR(e[2][i], e[0][i], 0.005 * e[0][i]) << "probe " << i;
  }
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
  EXPECT_EQ(count(r.err, "lay in one plane"), 1) << r.err;
}

}  // namespace
