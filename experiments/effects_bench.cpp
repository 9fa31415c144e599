// hrad_effects_bench: the time each "effects follow the scene" shortcut saves
// (core/config/effects.h), on a scene where it applies: the same solve with
// `effects = all` (every effect computed) and with `effects = auto`, best wall time
// of N runs each, plus rays, sweeps, iterations and the largest relative radiosity
// difference between the two (when both meshes agree).
//
//   hrad_effects_bench [runs=3]
//
// Scenes: the built-in furnace without objects (a convex enclosure: visibility),
// the office with every reflectance set to 0 (interreflection, and the early stop
// of iterations it allows), the office with every material made grey (its channels'
// mean: colour), the Cornell box without emission (emission), and the office with
// shaft culling on against off (both with effects = auto).
#include "core/base/clock.h"
#include "core/scene/builtin_scenes.h"
#include "core/solver/solver.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

namespace {

using namespace hrad;

struct Measured {
  double wall_s = std::numeric_limits<double>::infinity();
  RunStats stats;
  std::vector<Solver::Leaf> leaves;
};

Measured measure(const Scene& scene, const SolverOptions& o, int runs) {
  Measured m;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = Clock::now();
    Solver s(scene, o);
    RunStats st = s.run();
    const double t = seconds_since(t0);
    if (t < m.wall_s) {
      m.wall_s = t;
      m.stats = std::move(st);
      m.leaves = s.leaves();
    }
  }
  return m;
}

double propagate_s(const RunStats& s) {
  double t = 0;
  for (const IterationStats& it : s.iterations) t += it.propagate_wall_s;
  return t;
}

int sweeps(const RunStats& s) {
  int n = 0;
  for (const IterationStats& it : s.iterations) n += it.gather_sweeps;
  return n;
}

std::string difference(const Measured& a, const Measured& b) {
  if (a.leaves.size() != b.leaves.size()) return "mesh differs";
  double d = 0;
  for (std::size_t i = 0; i < a.leaves.size(); ++i) {
    if (a.leaves[i].id != b.leaves[i].id) return "mesh differs";
    for (int c = 0; c < 3; ++c) {
      const double x = a.leaves[i].radiosity[c], y = b.leaves[i].radiosity[c];
      const double m = std::max(std::abs(x), std::abs(y));
      if (m > 0) d = std::max(d, std::abs(x - y) / m);
    }
  }
  return fmt::format("{:.2g}", d);
}

void row(const char* effect, const char* scene_name, const Scene& scene, SolverOptions full,
         SolverOptions fast, int runs) {
  const Measured a = measure(scene, full, runs);
  const Measured b = measure(scene, fast, runs);
  fmt::print(
      "| {} | {} | {:.3f} | {:.3f} | {:.0f}% | {:.3f} / {:.3f} | {} / {} | {} / {} | {} / {} "
      "| {} |\n",
      effect, scene_name, a.wall_s, b.wall_s, 100 * (1 - b.wall_s / a.wall_s), propagate_s(a.stats),
      propagate_s(b.stats), a.stats.totals.rays_cast, b.stats.totals.rays_cast, sweeps(a.stats),
      sweeps(b.stats), a.stats.totals.iterations_run, b.stats.totals.iterations_run,
      difference(a, b));
}

Scene with_materials(Scene s, const std::function<void(Material&)>& f) {
  for (Material& m : s.materials) f(m);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  SolverOptions all;
  all.effects = EffectsMode::All;
  SolverOptions fast;
  fmt::print(
      "best of {} runs, 1 thread, default options; wall time of Solver construction + run\n\n",
      runs);
  fmt::print(
      "| effect | scene | all (s) | auto (s) | saved | propagate all / auto (s) | rays all / "
      "auto | sweeps all / auto | iterations all / auto | max rel. diff |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n");
  const Scene office = make_builtin("builtin:office");
  {
    SolverOptions a = all, b = fast;
    a.eps = b.eps = 1e-5;
    row("visibility (convex)", "furnace?objects=0, eps 1e-5",
        make_builtin("builtin:furnace?objects=0"), a, b, runs);
  }
  row("interreflection + iterations", "office, every Kd = 0",
      with_materials(office, [](Material& m) { m.reflectance = Rgb::Zero(); }), all, fast, runs);
  row("colour", "office, grey (channel mean)",
      with_materials(office,
                     [](Material& m) {
                       m.reflectance = Rgb::Constant(m.reflectance.mean());
                       m.emission = Rgb::Constant(m.emission.mean());
                     }),
      all, fast, runs);
  {
    SolverOptions a = all, b = fast;
    a.min_area = b.min_area = 1e-2;  // the full run refines everything down to min_area
    a.iterations = b.iterations = 2;
    row("emission", "cornell, no Ke (min_area 1e-2, 2 iterations)",
        with_materials(make_builtin("builtin:cornell"),
                       [](Material& m) { m.emission = Rgb::Zero(); }),
        a, b, runs);
  }
  {
    SolverOptions on = fast;
    on.shaft_culling = ShaftCulling::On;
    row("shaft culling (off vs on)", "office", office, fast, on, runs);
    row("shaft culling (off vs on)", "cornell", make_builtin("builtin:cornell"), fast, on, runs);
  }
  return 0;
}
