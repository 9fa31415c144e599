// Tests of the Monte Carlo reference (core/reference/path_tracer.h): closed forms, the furnace,
// agreement with the hierarchical solver on the Cornell box, determinism, and the
// standard error's honesty and 1/sqrt(N) decay.
#include "core/reference/path_tracer.h"
#include "core/scene/builtin_scenes.h"
#include "core/scene/scene_builder.h"
#include "core/solver/solver.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hrad {
namespace {

Material lamp(double exitance) {
  Material m;
  m.name = "lamp";
  m.reflectance = Rgb::Zero();
  m.emission = Rgb::Constant(exitance);
  return m;
}

/// One emitting polygon `pts` facing -z, alone in an otherwise empty (black) world.
Scene lone_emitter(const std::vector<Vec3>& pts, double exitance) {
  SceneBuilder b("lone", "test");
  const auto m = b.add_material(lamp(exitance), {"t", 0});
  b.add_polygon(std::span<const Vec3>(pts), m, {"t", 0});
  return b.finish("t");
}

/// Form factor from a point to a parallel a x b rectangle with one corner on the
/// point's normal, at distance h (standard closed form).
double corner_rectangle_ff(double a, double b, double h) {
  const double x = a / h, y = b / h;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * std::numbers::pi);
}

PathTracerOptions quick(double rel, std::uint64_t max_samples = 1u << 20) {
  PathTracerOptions o;
  o.rel_error = rel;
  o.max_samples = max_samples;
  return o;
}

/// |got - want| within 4 standard errors plus `slack` (relative), and converged.
void expect_close(const ProbeEstimate& e, double want, double slack = 0) {
  EXPECT_TRUE(e.converged);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(e.irradiance[c], want, 4 * e.std_error[c] + slack * want)
        << "channel " << c << ", SE " << e.std_error[c] << ", samples " << e.samples;
}

// A 2 x 2 square (half side a = 1) at height h = 1.5 over a probe facing it: E = M F,
// F four corner rectangles. Direct light only (the lamp reflects nothing).
TEST(PathTracer, ParallelSquareOnAxis) {
  const double a = 1, h = 1.5, m = 3.0;
  const Scene scene =
      lone_emitter({Vec3(-a, -a, h), Vec3(-a, a, h), Vec3(a, a, h), Vec3(a, -a, h)}, m);
  ASSERT_LT(scene.face_normal(0).z(), 0);  // facing the probe
  const double want = m * 4 * corner_rectangle_ff(a, a, h);
  const PathTracer pt(scene);
  const Probe probe{Vec3::Zero(), Vec3::UnitZ()};
  const ReferenceResult r = pt.estimate(std::span(&probe, 1), quick(2e-3));
  expect_close(r.probes[0], want);
  EXPECT_LT(r.probes[0].std_error[0], 2.5e-3 * want);
  // The same probe turned away sees nothing; so does one behind the lamp.
  const Probe away{Vec3::Zero(), -Vec3::UnitZ()};
  const Probe behind{Vec3(0, 0, 2 * h), -Vec3::UnitZ()};  // sees the lamp's back
  for (const Probe& p : {away, behind}) {
    const ReferenceResult z = pt.estimate(std::span(&p, 1), quick(1e-2, 4096));
    EXPECT_EQ(z.probes[0].irradiance.maxCoeff(), 0);
  }
}

// A disc of radius a at distance h (a regular 256-gon, whose irradiance is within
// 1e-4 of the disc's): E = M a^2 / (a^2 + h^2), here M / 5.
TEST(PathTracer, ParallelDiscOnAxis) {
  const double a = 1, h = 2, m = 1.0;
  std::vector<Vec3> pts;
  const int n = 256;
  for (int k = 0; k < n; ++k) {
    const double phi = -2 * std::numbers::pi * k / n;  // clockwise seen from below: faces -z
    pts.emplace_back(a * std::cos(phi), a * std::sin(phi), h);
  }
  const Scene scene = lone_emitter(pts, m);
  ASSERT_LT(scene.face_normal(0).z(), 0);
  const PathTracer pt(scene);
  const Probe probe{Vec3::Zero(), Vec3::UnitZ()};
  const ReferenceResult r = pt.estimate(std::span(&probe, 1), quick(2e-3));
  expect_close(r.probes[0], m * a * a / (a * a + h * h), 3e-4);
}

// builtin:furnace (every face emits E and reflects rho, closed): the radiosity is
// E / (1 - rho) everywhere, so the irradiance at any point inside, on a wall or in the
// air, facing any way, is E / (1 - rho) as well.
TEST(PathTracer, Furnace) {
  const std::vector<Probe> probes = {
      {Vec3(0.7, 0.0, 0.2), Vec3::UnitY()},                // on the floor
      {Vec3(0.1, 0.9, 0.1), Vec3(1, -1, 1).normalized()},  // in the air
      {Vec3(0.325, 0.45, 0.325), Vec3::UnitY()},           // on top of the cube
  };
  for (const double rho : {0.5, 0.9}) {
    const Scene scene = make_builtin(fmt::format("builtin:furnace?rho={}&emission=2", rho));
    const PathTracer pt(scene);
    const ReferenceResult r = pt.estimate(probes, quick(5e-3));
    for (const ProbeEstimate& e : r.probes) expect_close(e, 2 / (1 - rho));
  }
}

// Closed form with no light at all: an empty furnace (E = 0) gives exactly zero, and
// a zero channel converges at once.
TEST(PathTracer, DarkSceneIsZero) {
  const Scene scene = make_builtin("builtin:furnace?emission=0");
  const PathTracer pt(scene);
  const Probe p{Vec3(0.5, 0.1, 0.5), Vec3::UnitY()};
  const ReferenceResult r = pt.estimate(std::span(&p, 1), quick(1e-2, 4096));
  EXPECT_EQ(r.probes[0].irradiance.maxCoeff(), 0);
  EXPECT_TRUE(r.probes[0].converged);
  EXPECT_EQ(r.probes[0].samples, 64u * 16u);
}

// Direct light on the Cornell floor, with every reflectance set to 0: the light
// (1.30 x 1.05 m at height 5.478, exitance 15) is parallel to the floor and unoccluded
// from these three floor points, so E = M F with F from four signed corner rectangles.
// The solver's final gather must give the same (it is exact for unoccluded pairs).
TEST(PathTracer, CornellDirectLightClosedForm) {
  Scene scene = make_builtin("builtin:cornell");
  for (Material& m : scene.materials) m.reflectance = Rgb::Zero();
  const double h = 5.488 - 0.01, x1 = 2.13, x2 = 3.43, z1 = 2.27, z2 = 3.32;
  const std::vector<Probe> probes = {{Vec3(1.0, 0, 4.5), Vec3::UnitY()},
                                     {Vec3(4.8, 0, 1.0), Vec3::UnitY()},
                                     {Vec3(0.5, 0, 3.0), Vec3::UnitY()}};
  const ReferenceResult r = PathTracer(scene).estimate(probes, quick(2e-3));
  SolverOptions so;
  so.eps = 1e-2;
  Solver solver(scene, so);
  (void)solver.run();
  const std::vector<Rgb> gathered = solver.probe_irradiance(probes);
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Vec3& p = probes[i].p;
    const auto f = [&](double x, double z) { return corner_rectangle_ff(x - p.x(), z - p.z(), h); };
    const double want = 15.0 * (f(x2, z2) - f(x1, z2) - f(x2, z1) + f(x1, z1));
    expect_close(r.probes[i], want);
    EXPECT_NEAR(gathered[i][0], want, 1e-3 * want) << "solver, probe " << i;
  }
}

std::vector<Probe> cornell_probes() {
  return {{Vec3(2.78, 0.0, 2.8), Vec3::UnitY()},     // floor, centre (between the blocks)
          {Vec3(1.0, 0.0, 4.5), Vec3::UnitY()},      // floor, back right
          {Vec3(2.78, 5.488, 1.0), -Vec3::UnitY()},  // ceiling, front
          {Vec3(0.0, 2.5, 2.8), Vec3::UnitX()},      // green wall
          {Vec3(5.56, 2.5, 2.8), -Vec3::UnitX()},    // red wall
          {Vec3(2.78, 2.7, 5.592), -Vec3::UnitZ()},  // back wall
          {Vec3(2.78, 2.7, 1.0), Vec3::UnitZ()}};    // in the air, facing the back
}

// The reference and `hrad solve`'s final gather agree on the Cornell box: a gross
// mismatch of definitions (a factor pi, exitance for radiance, a missing bounce) would
// be off by far more. Measured at eps 1e-3 the solver is 3-7% *below* the reference on
// these probes (1-11% on tests/data/cornell_probes.txt; it converges towards it as eps
// and min_area shrink; see docs/accuracy.md), so the bounds are 10% per probe and channel
// and 6% on the mean.
TEST(PathTracer, AgreesWithSolverOnCornell) {
  const Scene scene = make_builtin("builtin:cornell");
  const std::vector<Probe> probes = cornell_probes();
  PathTracerOptions o = quick(1e-2);
  o.threads = 2;
  const ReferenceResult r = PathTracer(scene).estimate(probes, o);
  SolverOptions so;
  so.eps = 1e-3;
  Solver solver(scene, so);
  (void)solver.run();
  const std::vector<Rgb> e = solver.probe_irradiance(probes);
  double sum = 0;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    EXPECT_TRUE(r.probes[i].converged) << i;
    for (int c = 0; c < 3; ++c) {
      const double ref = r.probes[i].irradiance[c];
      EXPECT_NEAR(e[i][c], ref, 0.10 * ref) << "probe " << i << " channel " << c;
      sum += std::abs(e[i][c] - ref) / ref;
    }
  }
  EXPECT_LT(sum / (3.0 * static_cast<double>(probes.size())), 0.06);
}

// Same seed: bit-identical, whatever the thread count; another seed: different.
TEST(PathTracer, DeterministicAndThreadIndependent) {
  const Scene scene = make_builtin("builtin:cornell");
  const std::vector<Probe> probes = cornell_probes();
  const PathTracer pt(scene);
  PathTracerOptions o = quick(3e-2);
  const ReferenceResult a = pt.estimate(probes, o);
  o.threads = 2;
  const ReferenceResult b = pt.estimate(probes, o);
  o.seed = 2;
  const ReferenceResult c = pt.estimate(probes, o);
  for (std::size_t i = 0; i < probes.size(); ++i) {
    EXPECT_EQ(a.probes[i].samples, b.probes[i].samples);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.probes[i].irradiance[k], b.probes[i].irradiance[k]);
      EXPECT_EQ(a.probes[i].std_error[k], b.probes[i].std_error[k]);
    }
    EXPECT_NE(a.probes[i].irradiance[0], c.probes[i].irradiance[0]);
  }
  EXPECT_EQ(pt.batch_mean(probes[0], 7, 3, 11, 8)[0], pt.batch_mean(probes[0], 7, 3, 11, 8)[0]);
}

// The standard error falls like 1/sqrt(N) (16x the paths: 4x smaller, within 20% on
// the average over 24 independent copies of a probe) and is honest: about 95% of the
// copies lie within 2 SE of the exact value (at least 80% required).
TEST(PathTracer, StandardErrorShrinksAsOneOverSqrtN) {
  const double a = 1, h = 1.5;
  const Scene scene =
      lone_emitter({Vec3(-a, -a, h), Vec3(-a, a, h), Vec3(a, a, h), Vec3(a, -a, h)}, 1.0);
  const double want = 4 * corner_rectangle_ff(a, a, h);
  const PathTracer pt(scene);
  const std::vector<Probe> copies(24, Probe{Vec3::Zero(), Vec3::UnitZ()});
  const double exact = want;
  double se_small = 0, se_large = 0;
  int within = 0;
  for (const std::uint64_t n : {1024u, 16384u}) {
    const ReferenceResult r = pt.estimate(copies, quick(1e-9, n));
    for (const ProbeEstimate& e : r.probes) {
      EXPECT_EQ(e.samples, n);
      EXPECT_FALSE(e.converged);
      (n == 1024 ? se_small : se_large) += e.std_error[0];
      if (n == 16384 && std::abs(e.irradiance[0] - exact) <= 2 * e.std_error[0]) ++within;
    }
  }
  EXPECT_NEAR(se_small / se_large, 4.0, 0.8);
  EXPECT_GE(within, 19);  // of 24
}

TEST(PathTracer, RejectsBadOptions) {
  const Scene scene = make_builtin("builtin:furnace");
  const PathTracer pt(scene);
  const Probe p{Vec3(0.5, 0.1, 0.5), Vec3::UnitY()};
  PathTracerOptions o;
  o.rel_error = 0;
  EXPECT_THROW((void)pt.estimate(std::span(&p, 1), o), std::invalid_argument);
  o = PathTracerOptions{};
  o.max_samples = 10;
  EXPECT_THROW((void)pt.estimate(std::span(&p, 1), o), std::invalid_argument);
}

}  // namespace
}  // namespace hrad
