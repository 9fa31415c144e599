// Interrupts (core/base/interrupt.h): signals that arrive together are one request, and
// every long phase stops at its next poll. Each phase's test fails if that phase does
// not poll: with the flag already raised it would run to its end and return normally.
#include "core/base/interrupt.h"
#include "core/hierarchy/hierarchy.h"
#include "core/output/render.h"
#include "core/raycast/face_twins.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/back_faces.h"
#include "core/scene/builtin_scenes.h"
#include "core/scene/coplanar_overlap.h"
#include "core/scene/render_mesh.h"
#include "core/scene/scene_builder.h"
#include "core/scene/self_overlap.h"
#include "core/solver/solver.h"
#include "core/transport/open_fraction.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <string>
#include <thread>
#include <vector>

namespace hrad {
namespace {

// Clears the flag however the test ends.
struct ClearsInterrupt {
  ~ClearsInterrupt() { simulate_interrupt(0); }
};

// `timeout` sends SIGTERM to the process and then to its group, and Ctrl-C reaches
// every process of the foreground group: two signals at once. Taken as "a second
// signal", that pair ended the process by the signal's default action, with no cleanup.
TEST(Interrupt, SignalsThatArriveTogetherAreOneRequest) {
  ClearsInterrupt clear;
  install_interrupt_handlers();
  ASSERT_EQ(std::raise(SIGTERM), 0);
  ASSERT_EQ(std::raise(SIGTERM), 0);  // the default action would end the test here
  ASSERT_EQ(std::raise(SIGINT), 0);
  EXPECT_TRUE(interrupted());
  EXPECT_EQ(interrupt_signal(), SIGTERM);  // the first one is the request
  EXPECT_THROW(throw_if_interrupted(), Interrupted);
}

// A comb of many teeth, most of its corners reflex.
std::vector<Vec3> comb(int teeth) {
  std::vector<Vec3> p = {{0, 0, 0}, {2.0 * teeth, 0, 0}};
  for (int t = teeth - 1; t >= 0; --t) {
    const double x = 2.0 * t;
    p.insert(p.end(), {{x + 1.5, 1, 0}, {x + 1.5, 3, 0}, {x + 0.5, 3, 0}, {x + 0.5, 1, 0}});
  }
  return p;
}

// A huge polygon took minutes to load and ignored SIGTERM throughout. The flag is
// raised from another thread while the polygon is checked and triangulated.
TEST(Interrupt, AHugePolygonsLoadStops) {
  ClearsInterrupt clear;
  const std::vector<Vec3> p = comb(150000);  // 600,002 corners
  SceneBuilder b("t", "t");
  Material m;
  m.name = "m";
  m.reflectance = Rgb::Constant(0.5);
  const auto mat = b.add_material(m, SourceLoc{"t.obj", 1});
  std::thread late([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    simulate_interrupt(SIGTERM);
  });
  EXPECT_THROW(b.add_polygon(p, mat, SourceLoc{"t.obj", 2}), Interrupted);
  late.join();
}

TEST(Interrupt, TheOverlapChecksStop) {
  ClearsInterrupt clear;
  const std::vector<Vec3> p = comb(100);
  const Scene scene = make_builtin("builtin:office");
  simulate_interrupt(SIGINT);
  EXPECT_THROW((void)find_self_overlap(p), Interrupted);
  Scene copy = scene;
  std::vector<std::uint32_t> source;
  EXPECT_THROW((void)remove_coplanar_overlaps(copy, source), Interrupted);
}

TEST(Interrupt, OpenFractionsStop) {
  ClearsInterrupt clear;
  const Scene scene = make_builtin("builtin:furnace?objects=2");
  Hierarchy h(scene, 1);
  const RayScene rays = RayScene::from_scene(scene);
  std::vector<Element*> all = h.elements();
  simulate_interrupt(SIGINT);
  EXPECT_THROW((void)update_open_fractions(all, h, rays, 1, 2, true), Interrupted);
}

// Preparing a large scene (a cabin of a million polygons) went on for about 15 s after
// a signal: the face twins, contacts, the ray scene's loops, the hierarchy's build, the
// back faces and the bulk's bounds never asked. Each now stops at once when the flag is
// up (Embree's own build is the one part that cannot).
TEST(Interrupt, PreparingAScenesStructuresStops) {
  ClearsInterrupt clear;
  Scene scene = make_builtin("builtin:office");
  simulate_interrupt(SIGTERM);
  EXPECT_THROW((void)find_twins(scene), Interrupted);
  EXPECT_THROW((void)scene.bulk_bounds(), Interrupted);
  EXPECT_THROW((void)RayScene::from_scene(scene), Interrupted);
  EXPECT_THROW((void)Hierarchy(scene, 1), Interrupted);
  EXPECT_THROW(add_back_faces(scene, Sides::Two, EmitterSides::Front), Interrupted);
  EXPECT_THROW((void)Solver(scene, SolverOptions{}), Interrupted);
  simulate_interrupt(0);
  EXPECT_NO_THROW((void)Hierarchy(scene, 1));  // nothing left behind by the stopped build
}

// A phase's memory was checked only at its end: a cabin of four million polygons took
// 2.5 GB while loading under a limit of 0.3 GB. While a MemoryBudget lives, the
// interrupt polls compare the process's growth with it.
TEST(Interrupt, AMemoryBudgetStopsAPhaseThatGrowsPastIt) {
  std::vector<char> held;
  {
    const MemoryBudget budget(8'000'000, "the test's phase");
    EXPECT_NO_THROW(throw_if_interrupted());
    held.assign(64'000'000, 1);  // touched: resident
    try {
      throw_if_interrupted();
      FAIL() << "not stopped";
    } catch (const MemoryExceeded& e) {
      EXPECT_NE(std::string(e.what()).find("the test's phase took more than the limit of 0.008 GB"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_NO_THROW(throw_if_interrupted());  // no budget: no check
  const MemoryBudget none(0, "unbounded");
  EXPECT_NO_THROW(throw_if_interrupted());
}

// The solve, stopped in each phase of its iteration as the progress line names it:
// the flag is raised when the phase starts, and the run must not finish.
TEST(Interrupt, EveryPhaseOfASolveStops) {
  ClearsInterrupt clear;
  const Scene scene = make_builtin("builtin:office");
  for (const std::string phase : {"refine", "open fractions", "propagate"}) {
    SolverOptions o;
    o.threads = 2;
    o.iterations = 2;
    bool raised = false;
    Solver s(scene, o, [&](const std::string& line, double) {
      if (!raised && line.find("iteration 2/2: " + phase) != std::string::npos) {
        raised = true;
        simulate_interrupt(SIGTERM);
      }
    });
    EXPECT_THROW((void)s.run(), Interrupted) << phase;
    EXPECT_TRUE(raised) << phase;
    simulate_interrupt(0);
  }
}

// A million probes took 15 minutes and ignored SIGTERM; rendering a large image too.
TEST(Interrupt, ProbesAndRenderingStop) {
  ClearsInterrupt clear;
  const Scene scene = make_builtin("builtin:cornell");
  SolverOptions o;
  o.iterations = 1;
  Solver s(scene, o);
  (void)s.run();
  std::vector<Probe> probes(1000, Probe{Vec3(2.78, 0.01, 2.8), Vec3(0, 1, 0)});
  std::vector<std::string> lines;
  const auto seen =
      s.probe_irradiance(std::span<const Probe>(probes.data(), 10),
                         [&](const std::string& line, double) { lines.push_back(line); });
  ASSERT_EQ(seen.size(), 10u);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.front().rfind("probes: ", 0), 0u) << lines.front();
  const RenderMesh mesh = s.render_mesh(o.shading);
  simulate_interrupt(SIGINT);
  EXPECT_THROW((void)s.probe_irradiance(probes), Interrupted);
  Camera cam;
  cam.eye = Vec3(2.78, 2.73, -8);
  cam.target = Vec3(2.78, 2.73, 0);
  EXPECT_THROW((void)render_radiance(mesh, cam, 64, 48), Interrupted);
}

}  // namespace
}  // namespace hrad
