// Tests of the error metrics (core/reference/error_metrics.h) and of reading solution.ply back
// (core/scene/ply_reader.h), on hand-made inputs with known answers; and of the `reference`
// and `compare` commands end to end.
#include "core/reference/error_metrics.h"
#include "core/base/input_error.h"
#include "core/output/ply_writer.h"
#include "core/scene/ply_reader.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hrad {
namespace {

namespace fs = std::filesystem;

const std::string kHeader = "x,y,z,nx,ny,nz,E_r,E_g,E_b\n";

// Floor = 1e-3 x mean reference (1 + 2 + 0) / 3 = 1e-3. Errors per probe (largest
// channel): 0.1 / 1, 0.2 / 2, 0.001 / max(0, 1e-3) = 1.
const std::string kRef = kHeader +
                         "0,0,0,0,0,1,1,1,1\n"
                         "1,0,0,0,0,1,2,2,2\n"
                         "2,0,0,0,1,0,0,0,0\n";
const std::string kResult = kHeader +
                            "0,0,0,0,0,1,1.1,1,1\n"
                            "1,0,0,0,0,1,2,2,1.8\n"
                            "2,0,0,0,1,0,0.001,0,0\n";

TEST(ErrorMetrics, ProbeRelativeErrorWithFloor) {
  const ProbeComparison c =
      compare_probes(parse_probe_table(kResult, "a.csv"), parse_probe_table(kRef, "r.csv"));
  EXPECT_DOUBLE_EQ(c.floor, 1e-3);
  ASSERT_EQ(c.probes.size(), 3u);
  EXPECT_NEAR(c.probes[0].rel_error, 0.1, 1e-12);
  EXPECT_NEAR(c.probes[1].rel_error, 0.1, 1e-12);
  EXPECT_NEAR(c.probes[2].rel_error, 1.0, 1e-12);
  EXPECT_NEAR(c.mean, 0.4, 1e-12);
  EXPECT_NEAR(c.max, 1.0, 1e-12);
  EXPECT_EQ(c.worst, 2u);
  EXPECT_NEAR(c.rms, std::sqrt((0.01 + 0.01 + 1.0) / 3), 1e-12);
  EXPECT_FALSE(c.has_se);
  // Median of (0.1, 0.1, 1); signed errors of the channel means: +0.1/3 / 1,
  // -0.2/3 / 2, +0.001/3 / 1e-3; bias their mean; one probe low.
  EXPECT_NEAR(c.median, 0.1, 1e-12);
  EXPECT_NEAR(c.probes[0].signed_error, 0.1 / 3, 1e-12);
  EXPECT_NEAR(c.probes[1].signed_error, -0.2 / 3 / 2, 1e-12);
  EXPECT_NEAR(c.probes[2].signed_error, 1.0 / 3, 1e-9);
  EXPECT_NEAR(c.bias, (0.1 / 3 - 0.1 / 3 + 1.0 / 3) / 3, 1e-9);
  EXPECT_EQ(c.low, 1u);
  // An explicit floor of 0.01 turns the dark probe's error into 0.001 / 0.01.
  const ProbeComparison f =
      compare_probes(parse_probe_table(kResult, "a.csv"), parse_probe_table(kRef, "r.csv"), 0.01);
  EXPECT_NEAR(f.probes[2].rel_error, 0.1, 1e-12);
  // Against itself: zero.
  const ProbeComparison z =
      compare_probes(parse_probe_table(kRef, "r.csv"), parse_probe_table(kRef, "r.csv"));
  EXPECT_EQ(z.max, 0);
}

// A reference that is zero at every probe has no scale for a relative error: compare
// printed "median inf, mean -nan". Without --floor it is an error naming the file; with
// one the errors are absolute over that floor.
TEST(ErrorMetrics, AnAllZeroReferenceNeedsAFloor) {
  const std::string zero = kHeader + "0,0,0,0,0,1,0,0,0\n1,0,0,0,0,1,0,0,0\n";
  const std::string some = kHeader + "0,0,0,0,0,1,0.5,0.5,0.5\n1,0,0,0,0,1,0,0,0\n";
  try {
    (void)compare_probes(parse_probe_table(some, "a.csv"), parse_probe_table(zero, "r.csv"));
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("r.csv: the reference irradiance is zero at every probe"),
              std::string::npos)
        << e.what();
  }
  const ProbeComparison c =
      compare_probes(parse_probe_table(some, "a.csv"), parse_probe_table(zero, "r.csv"), 0.25);
  EXPECT_NEAR(c.max, 2.0, 1e-12);  // 0.5 over the floor 0.25
  EXPECT_TRUE(std::isfinite(c.mean));
  EXPECT_TRUE(std::isfinite(c.bias));
}

TEST(ErrorMetrics, ProbeStandardErrorColumns) {
  // Columns in another order, plus SE and an extra column: SE 0.06 gives
  // z = 0.1/0.06, 0.2/0.06, 0.001/0.06: two of three within 2 SE.
  const std::string ref =
      "E_r,E_g,E_b,SE_r,SE_g,SE_b,x,y,z,nx,ny,nz,samples\n"
      "1,1,1,0.06,0.06,0.06,0,0,0,0,0,1,100\n"
      "2,2,2,0.06,0.06,0.06,1,0,0,0,0,1,100\n"
      "0,0,0,0.06,0.06,0.06,2,0,0,0,1,0,100\n";
  const ProbeTable r = parse_probe_table(ref, "r.csv");
  ASSERT_EQ(r.std_error.size(), 3u);
  const ProbeComparison c = compare_probes(parse_probe_table(kResult, "a.csv"), r);
  EXPECT_TRUE(c.has_se);
  EXPECT_NEAR(c.probes[0].z, 0.1 / 0.06, 1e-9);
  EXPECT_NEAR(c.probes[1].z, 0.2 / 0.06, 1e-9);
  EXPECT_EQ(c.within_2se, 2u);
  EXPECT_NEAR(c.mean, 0.4, 1e-12);
}

TEST(ErrorMetrics, MismatchedProbeSetsAreErrors) {
  const ProbeTable r = parse_probe_table(kRef, "r.csv");
  const ProbeTable fewer = parse_probe_table(kHeader + "0,0,0,0,0,1,1,1,1\n", "a.csv");
  EXPECT_THROW((void)compare_probes(fewer, r), std::invalid_argument);
  const ProbeTable moved = parse_probe_table(kHeader +
                                                 "0,0,0,0,0,1,1,1,1\n"
                                                 "1,0.01,0,0,0,1,2,2,2\n"
                                                 "2,0,0,0,1,0,0,0,0\n",
                                             "a.csv");
  try {
    (void)compare_probes(moved, r);
    FAIL() << "a moved probe was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("probe 1"), std::string::npos) << e.what();
  }
}

TEST(ErrorMetrics, BadProbeCsvNamesFileAndLine) {
  try {
    (void)parse_probe_table("x,y,z,nx,ny,nz,E_r,E_g\n", "a.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(std::string(e.what()).find("E_b"), std::string::npos);
  }
  try {
    (void)parse_probe_table(kHeader + "0,0,0,0,0,1,1,1,1\n0,0,0,0,0,1,1,x,1\n", "a.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("E_g"), std::string::npos);
  }
  EXPECT_THROW((void)parse_probe_table(kHeader + "0,0,0,0,0,1,1,1\n", "a.csv"), InputError);
  EXPECT_THROW((void)parse_probe_table("", "a.csv"), InputError);
}

/// The unit square z = 0 (facing +z) as n x n quads with radiosity f(x) at the vertices.
RenderMesh square_mesh(int n, double (*f)(double)) {
  RenderMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = static_cast<double>(i) / n, y = static_cast<double>(j) / n;
      m.positions.emplace_back(x, y, 0);
      m.radiosity.push_back(Rgb::Constant(f(x)));
      m.reflectance.push_back(Rgb::Zero());
    }
  const auto v = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      m.polys.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
  return m;
}

double linear(double x) { return x; }
double half(double) { return 0.5; }

TEST(ErrorMetrics, SurfaceL1AndL2) {
  // B = x interpolated bilinearly is exact on any grid: no error.
  const SurfaceComparison same =
      compare_surfaces(square_mesh(1, linear), square_mesh(8, linear), 20000);
  EXPECT_EQ(same.unmatched, 0u);
  EXPECT_GE(same.samples, 20000u);
  EXPECT_NEAR(same.l1_all, 0, 1e-5);
  EXPECT_NEAR(same.reference_mean[0], 0.5, 1e-3);
  // Constant 0.5 against x on [0,1]: L1 = (1/4) / (1/2) = 0.5,
  // L2 = sqrt(1/12) / (1/2) = 0.5774 (sampling error ~1/sqrt(N) per 8x8 cell, small).
  const SurfaceComparison c = compare_surfaces(square_mesh(3, half), square_mesh(8, linear), 20000);
  EXPECT_NEAR(c.l1_all, 0.5, 5e-3);
  EXPECT_NEAR(c.l2_all, std::sqrt(1.0 / 12) / 0.5, 5e-3);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c.l1[k], 0.5, 5e-3);
  // Different areas: not the same scene.
  RenderMesh bigger = square_mesh(2, half);
  for (Vec3& p : bigger.positions) p *= 2;
  EXPECT_THROW((void)compare_surfaces(bigger, square_mesh(2, linear)), std::invalid_argument);
}

TEST(ErrorMetrics, PlyRoundTrip) {
  const RenderMesh m = square_mesh(2, linear);
  const RenderMesh back = decode_ply(encode_ply(m), "m.ply");
  ASSERT_EQ(back.positions.size(), m.positions.size());
  ASSERT_EQ(back.polys, m.polys);
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_NEAR((back.positions[i] - m.positions[i]).norm(), 0, 1e-7);
    EXPECT_NEAR(back.radiosity[i][0], m.radiosity[i][0], 1e-7);
  }
  std::string bytes = encode_ply(m);
  EXPECT_THROW((void)decode_ply(bytes.substr(0, bytes.size() - 3), "m.ply"), InputError);
  bytes.replace(bytes.find("radiosity_g"), 11, "radiosity_x");
  EXPECT_THROW((void)decode_ply(bytes, "m.ply"), InputError);
  EXPECT_THROW((void)decode_ply("not a ply\n", "m.ply"), InputError);
}

// End to end: `hrad reference` writes probes.csv with SE columns and reference.json;
// `hrad compare` of the result against itself is zero and exits 0; mismatched probe
// sets exit 1 and name both files.
class ReferenceCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hrad-ref-test-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  int hrad(const std::string& args, std::string* err = nullptr) const {
    const std::string cmd = "cd '" + dir_.string() + "' && '" HRAD_BINARY "' " + args +
                            " > out.txt 2> err.txt < /dev/null";
    const int rc = std::system(cmd.c_str());
    if (err) {
      std::ifstream in(dir_ / "err.txt");
      std::stringstream s;
      s << in.rdbuf();
      *err = s.str();
    }
    return (rc != -1 && WIFEXITED(rc)) ? WEXITSTATUS(rc) : -1;
  }
  fs::path dir_;
};

TEST_F(ReferenceCli, ReferenceThenCompare) {
  std::ofstream(dir_ / "p.txt") << "0.7 0 0.2 0 1 0\n0.1 0.9 0.1 1 -1 1\n";
  std::ofstream(dir_ / "q.txt") << "0.7 0 0.2 0 1 0\n";
  ASSERT_EQ(hrad("reference builtin:furnace --probes p.txt --out run --rel-error 0.02 --quiet"), 0);
  ASSERT_TRUE(fs::exists(dir_ / "run" / "reference.json"));
  const ProbeTable t = read_probe_table(dir_ / "run");
  ASSERT_EQ(t.probes.size(), 2u);
  ASSERT_EQ(t.std_error.size(), 2u);
  for (const Rgb& e : t.irradiance) EXPECT_NEAR(e[0], 2.0, 0.1);  // E / (1 - 0.5)
  std::ifstream j(dir_ / "run" / "reference.json");
  const nlohmann::json ref = nlohmann::json::parse(j);
  EXPECT_EQ(ref["converged"], true);
  EXPECT_EQ(ref["probes"], 2);

  EXPECT_EQ(hrad("compare run/probes.csv run --json c.json"), 0);
  std::ifstream cj(dir_ / "c.json");
  const nlohmann::json c = nlohmann::json::parse(cj);
  EXPECT_EQ(c["probes"]["max"], 0.0);
  EXPECT_EQ(c["probes"]["within_2se"], 2);

  // Random surface probes: written to probes.txt, which `solve --probes` reads back.
  ASSERT_EQ(hrad("reference builtin:furnace --random-probes 5 --seed 3 --out rnd --rel-error 0.05 "
                 "--quiet"),
            0);
  const ProbeTable rnd = read_probe_table(dir_ / "rnd");
  ASSERT_EQ(rnd.probes.size(), 5u);
  for (const Rgb& e : rnd.irradiance) EXPECT_NEAR(e[0], 2.0, 0.2);
  ASSERT_EQ(hrad("solve builtin:furnace --probes rnd/probes.txt --out srnd"), 0);
  EXPECT_EQ(hrad("compare srnd rnd --json r.json"), 0);
  std::string none;
  EXPECT_EQ(hrad("reference builtin:furnace --out neither", &none), 1);
  EXPECT_NE(none.find("--random-probes"), std::string::npos) << none;
  EXPECT_FALSE(fs::exists(dir_ / "neither"));

  ASSERT_EQ(hrad("reference builtin:furnace --probes q.txt --out one --rel-error 0.05 --quiet"), 0);
  std::string err;
  EXPECT_EQ(hrad("compare one run", &err), 1);
  EXPECT_NE(err.find("not the same probe set"), std::string::npos) << err;
  // Bad input creates nothing.
  EXPECT_EQ(hrad("reference builtin:nosuch --probes p.txt --out bad", &err), 1);
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

}  // namespace
}  // namespace hrad
