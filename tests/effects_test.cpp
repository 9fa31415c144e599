// Effects follow the scene (core/config/effects.h, core/transport/shaft.h): every shortcut gives
// the same radiosity as the full computation (`effects = all`) to 1e-9 relative,
// and its counter shows the work it saved.
#include "core/config/effects.h"
#include "core/config/options_io.h"
#include "core/hierarchy/hierarchy.h"
#include "core/output/stats_json.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/builtin_scenes.h"
#include "core/solver/propagation.h"
#include "core/solver/solver.h"
#include "core/transport/shaft.h"
#include "core/transport/transport.h"
#include "tests/solver_test_util.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace hrad {
namespace {

struct Solved {
  RunStats stats;
  std::vector<Solver::Leaf> leaves;
};

SolverOptions small_options() {
  SolverOptions o;
  o.eps = 1e-3;
  o.min_area = 1e-3;
  return o;
}

Solved solve(const Scene& scene, SolverOptions o, const char* effects) {
  apply_option_value(o, "effects", effects, "test");
  Solver s(scene, o);
  Solved r;
  r.stats = s.run();
  r.leaves = s.leaves();
  return r;
}

// Same leaves (the same mesh) with the same radiosity to 1e-9 relative.
void expect_same_radiosity(const Solved& a, const Solved& b) {
  ASSERT_EQ(a.leaves.size(), b.leaves.size());
  ASSERT_FALSE(a.leaves.empty());
  for (std::size_t i = 0; i < a.leaves.size(); ++i) {
    ASSERT_EQ(a.leaves[i].id, b.leaves[i].id);
    for (int c = 0; c < 3; ++c) {
      const double x = a.leaves[i].radiosity[c], y = b.leaves[i].radiosity[c];
      ASSERT_LE(std::abs(x - y), 1e-9 * std::max(std::abs(x), std::abs(y)))
          << "leaf " << i << " channel " << c << ": " << x << " vs " << y;
    }
  }
}

std::uint64_t sweeps(const RunStats& s) {
  std::uint64_t n = 0;
  for (const IterationStats& it : s.iterations) n += static_cast<std::uint64_t>(it.gather_sweeps);
  return n;
}

/// A closed room [0,1]^3 (faces inward, 2 x 2 quads each), optionally with a closed
/// box inside (faces outward), every face of material m.
Scene room(const Material& m, bool object) {
  SceneBuilder b("room", "test");
  const auto id = b.add_material(m, {"t", 0});
  test::add_room(b, Vec3(0, 0, 0), Vec3(1, 1, 1), id, 2, true);
  if (object) test::add_room(b, Vec3(0.3, 0.2, 0.35), Vec3(0.6, 0.5, 0.7), id, 1, false);
  return b.finish("t");
}

Material coloured(const Rgb& rho, const Rgb& e) {
  Material m;
  m.name = "coloured";
  m.reflectance = rho;
  m.emission = e;
  return m;
}

// --- the scene analysis -------------------------------------------------------------

TEST(EffectsAnalysis, ConvexEnclosureKnownAnswers) {
  const Material m = test::material(0.5, 1);
  EXPECT_TRUE(is_convex_enclosure(room(m, false)));
  EXPECT_TRUE(is_convex_enclosure(make_builtin("builtin:furnace?objects=0")));
  std::string why;
  EXPECT_FALSE(is_convex_enclosure(room(m, true), &why));
  EXPECT_NE(why.find("behind the plane of polygon"), std::string::npos) << why;
  // A box seen from outside: every face has the opposite face's vertices behind it.
  SceneBuilder b("outside", "test");
  test::add_room(b, Vec3(0, 0, 0), Vec3(1, 1, 1), b.add_material(m, {"t", 0}), 1, false);
  EXPECT_FALSE(is_convex_enclosure(b.finish("t")));
  // The Cornell box's light hangs below the ceiling: not convex even without blocks.
  EXPECT_FALSE(is_convex_enclosure(make_builtin("builtin:cornell?blocks=0")));
  EXPECT_FALSE(is_convex_enclosure(make_builtin("builtin:cornell")));
}

TEST(EffectsAnalysis, DecidesEachEffectWithAReason) {
  SolverOptions o;
  const Effects cornell = analyse_effects(make_builtin("builtin:cornell"), o);
  EXPECT_TRUE(cornell.visibility.on);
  EXPECT_TRUE(cornell.interreflection.on);
  EXPECT_TRUE(cornell.colour.on);  // red and green walls
  EXPECT_TRUE(cornell.emission.on);
  EXPECT_FALSE(cornell.visibility.reason.empty());

  const Effects furnace = analyse_effects(make_builtin("builtin:furnace?objects=0"), o);
  EXPECT_FALSE(furnace.visibility.on);
  EXPECT_NE(furnace.visibility.reason.find("convex enclosure"), std::string::npos);
  EXPECT_FALSE(furnace.colour.on);
  EXPECT_TRUE(furnace.interreflection.on);

  const Effects black = analyse_effects(room(test::material(0, 1), true), o);
  EXPECT_FALSE(black.interreflection.on);
  EXPECT_FALSE(black.visibility.on);  // V would only weight light nobody reflects

  const Effects dark = analyse_effects(room(test::material(0.5, 0), false), o);
  EXPECT_FALSE(dark.emission.on);
  EXPECT_EQ(dark.emission.reason.rfind("scene has no emitter", 0), 0u) << dark.emission.reason;

  o.effects = EffectsMode::All;
  const Effects forced = analyse_effects(room(test::material(0, 0), false), o);
  for (const auto& [name, e] : forced.table()) EXPECT_TRUE(e->on) << name << ": " << e->reason;
}

TEST(EffectsAnalysis, OptionsAreChecked) {
  SolverOptions o;
  apply_option_assignment(o, "effects=all");
  apply_option_assignment(o, "shaft-culling=on");
  EXPECT_EQ(o.effects, EffectsMode::All);
  EXPECT_EQ(o.shaft_culling, ShaftCulling::On);
  EXPECT_NO_THROW(validate_options(o));
  // Values outside the tables are refused where they are read.
  EXPECT_THROW(apply_option_assignment(o, "effects=some"), std::invalid_argument);
  EXPECT_THROW(apply_option_assignment(o, "shaft_culling=yes"), std::invalid_argument);
  EXPECT_EQ(o.effects, EffectsMode::All);  // unchanged by the refused values
  EXPECT_EQ(o.shaft_culling, ShaftCulling::On);
}

TEST(EffectsAnalysis, StatsJsonReportsEveryEffect) {
  RunStats s;
  s.effects.visibility = {false, "convex"};
  s.totals.iterations_run = 2;
  const nlohmann::json j = stats_to_json(s);
  EXPECT_EQ(j["effects"]["visibility"]["on"], false);
  EXPECT_EQ(j["effects"]["visibility"]["reason"], "convex");
  ASSERT_EQ(j["effects"].size(), s.effects.table().size());
  for (const auto& [name, e] : s.effects.table()) {
    ASSERT_TRUE(j["effects"].contains(name)) << name;
    EXPECT_EQ(j["effects"][name]["on"], e->on) << name;
  }
  for (const char* k : {"interreflection", "colour", "emission", "iterations"})
    EXPECT_EQ(j["effects"][k]["on"], true) << k;
  EXPECT_EQ(j["totals"]["iterations_run"], 2);
}

// --- each shortcut: same result, and the saving shows -------------------------------

TEST(EffectsShortcut, ConvexEnclosureCastsNoRays) {
  // A coloured furnace without objects: convex, so only visibility is turned off.
  // With normalized row sums the exact answer is B = E / (1 - rho) per channel.
  const Rgb rho(0.7, 0.5, 0.3), e(1, 0.8, 0.6);
  const Scene scene = room(coloured(rho, e), false);
  SolverOptions o = small_options();
  o.row_sums = RowSumMode::Normalize;
  o.gather_tolerance = 1e-10;
  // The links settle after iteration 3, where the fast run would stop (its answer is
  // then that of a 3-iteration run) and the full one go on; a 4th iteration's push
  // weights come from other radiosities (core/solver/push_weights.h), so the two would differ
  // by 1e-7. Both run 3 here.
  o.iterations = 3;
  const Solved fast = solve(scene, o, "auto");
  const Solved full = solve(scene, o, "all");
  EXPECT_FALSE(fast.stats.effects.visibility.on);
  EXPECT_TRUE(fast.stats.effects.interreflection.on);
  EXPECT_TRUE(fast.stats.effects.colour.on);
  // No visibility ray at all (the escape rays of normalize are not visibility rays).
  std::uint64_t escape = 0;
  for (const IterationStats& it : fast.stats.iterations) escape += it.rays_cast;
  EXPECT_EQ(fast.stats.totals.rays_cast, escape);
  EXPECT_GT(fast.stats.totals.rays_skipped, full.stats.totals.rays_skipped);
  // Every visibility ray the full run cast was skipped (same links, same pairs). The
  // full run also looks for closed-in parts (core/transport/open_fraction.h), which a convex
  // enclosure cannot have: the fast run casts no such ray.
  std::uint64_t open_rays = 0;
  for (const IterationStats& it : full.stats.iterations)
    open_rays += it.open_rays + it.exposure_rays;
  for (const IterationStats& it : fast.stats.iterations) {
    EXPECT_EQ(it.open_rays, 0u);
    EXPECT_EQ(it.exposure_rays, 0u);
  }
  EXPECT_GT(open_rays, 0u);
  EXPECT_EQ(fast.stats.totals.rays_skipped - full.stats.totals.rays_skipped,
            full.stats.totals.rays_cast - fast.stats.totals.rays_cast - open_rays);
  // Both runs meet the closed form to the propagation tolerance and float link
  // storage (1e-7), and each other to 1e-9 (in fact exactly: every ray is clear).
  ASSERT_EQ(fast.leaves.size(), full.leaves.size());
  for (std::size_t i = 0; i < fast.leaves.size(); ++i) {
    ASSERT_EQ(fast.leaves[i].id, full.leaves[i].id);
    for (int c = 0; c < 3; ++c) {
      const double exact = e[c] / (1 - rho[c]);
      const double x = fast.leaves[i].radiosity[c], y = full.leaves[i].radiosity[c];
      ASSERT_NEAR(x, y, 1e-9 * exact) << "leaf " << i << " channel " << c;
      ASSERT_NEAR(x, exact, 1e-7 * exact) << "leaf " << i << " channel " << c;
    }
  }
  // With the default row sums too, the full run gives the same radiosity to 1e-9:
  // its visibility rays ignore the polygons their end points lie on, so none that
  // grazes a wall is reported blocked by it (before, 277 of 222,910 element pairs in
  // this box were, costing up to 6e-5 of some leaves' radiosity).
  // Two iterations: the second is the last, so the iterations shortcut (a run whose
  // links settled stops there, with what its last propagation gives) does not make the
  // runs differ here; it has its own test.
  SolverOptions d = small_options();
  d.gather_tolerance = 1e-10;
  d.iterations = 2;
  expect_same_radiosity(solve(scene, d, "auto"), solve(scene, d, "all"));
}

TEST(EffectsShortcut, NonConvexScenesKeepVisibility) {
  for (const char* spec : {"builtin:cornell", "builtin:cornell?blocks=0"}) {
    SolverOptions o = small_options();
    o.iterations = 1;
    const Solved r = solve(make_builtin(spec), o, "auto");
    EXPECT_TRUE(r.stats.effects.visibility.on) << spec;
    EXPECT_GT(r.stats.totals.rays_cast, 0u) << spec;
  }
}

TEST(EffectsShortcut, BlackRoomGathersOnceAndStopsEarly) {
  // Every reflectance 0: B = E exactly, one sweep per iteration, no rays, and the
  // second iteration changes nothing, so the last two are not run.
  const Scene scene = room(test::material(0, 2), true);
  const Solved fast = solve(scene, small_options(), "auto");
  const Solved full = solve(scene, small_options(), "all");
  EXPECT_FALSE(fast.stats.effects.interreflection.on);
  for (const IterationStats& it : fast.stats.iterations) EXPECT_EQ(it.gather_sweeps, 1);
  // The full run needs one sweep per iteration too (B starts at E and does not
  // change), but four iterations of it.
  EXPECT_LT(sweeps(fast.stats), sweeps(full.stats));
  EXPECT_EQ(fast.stats.totals.rays_cast, 0u);
  EXPECT_GT(full.stats.totals.rays_cast, 0u);
  EXPECT_EQ(fast.stats.totals.iterations_run, 2);
  EXPECT_EQ(full.stats.totals.iterations_run, 4);
  EXPECT_FALSE(fast.stats.effects.iterations.on);
  EXPECT_NE(fast.stats.effects.iterations.reason.find("stopped after iteration 2 of 4"),
            std::string::npos);
  expect_same_radiosity(fast, full);
  for (const auto& l : fast.leaves) EXPECT_EQ(l.radiosity[0], 2.0);
}

TEST(EffectsShortcut, GreySceneSolvesOneChannel) {
  // The furnace with objects: grey and not convex, so only colour is turned off.
  const Scene scene = make_builtin("builtin:furnace?rho=0.8");
  SolverOptions o = small_options();
  o.iterations = 2;
  const Solved fast = solve(scene, o, "auto");
  const Solved full = solve(scene, o, "all");
  EXPECT_FALSE(fast.stats.effects.colour.on);
  EXPECT_TRUE(fast.stats.effects.visibility.on);
  EXPECT_TRUE(fast.stats.effects.interreflection.on);
  EXPECT_EQ(fast.stats.totals.rays_cast, full.stats.totals.rays_cast);
  expect_same_radiosity(fast, full);
}

TEST(EffectsShortcut, GreyGatherReadsOneChannel) {
  // The saving itself: a grey sweep gathers channel 0 only and copies it, so a
  // source whose channels differ (impossible in a grey scene) shows it.
  SceneBuilder b("pair", "test");
  const auto m = b.add_material(test::material(0, 0), {"t", 0});
  const std::vector<Vec3> lo = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  const std::vector<Vec3> hi = {Vec3(0, 0, 1), Vec3(0, 1, 1), Vec3(1, 1, 1), Vec3(1, 0, 1)};
  b.add_polygon(lo, m, {"t", 1});
  b.add_polygon(hi, m, {"t", 2});
  const Scene scene = b.finish("t");
  for (bool grey : {false, true}) {
    Hierarchy h(scene, 1);
    std::vector<Element*> els = h.elements();
    Element* r = nullptr;
    Element* s = nullptr;
    for (Element* e : els)
      if (!e->is_cluster()) (e->face == 0 ? r : s) = e;
    ASSERT_TRUE(r && s);
    const Link l{s, 0.5f, 1.0f};
    h.store_links(*r, {&l, 1}, 0);
    s->B = Rgb(1, 2, 3);
    propagation_sweep(els, 1, ClusterReceiver::Isotropic, grey);
    EXPECT_EQ(r->gathered[0], 0.5);
    EXPECT_EQ(r->gathered[2], grey ? 0.5 : 1.5);
  }
}

TEST(EffectsShortcut, NoEmitterGivesZeroAtOnce) {
  const Scene scene = room(test::material(0.5, 0), true);
  SolverOptions o = small_options();
  o.min_area = 0.02;  // the full run refines everything down to min_area (eps x 0 power)
  o.iterations = 2;
  const Solved fast = solve(scene, o, "auto");
  const Solved full = solve(scene, o, "all");
  EXPECT_FALSE(fast.stats.effects.emission.on);
  EXPECT_TRUE(fast.stats.iterations.empty());
  EXPECT_EQ(fast.stats.totals.iterations_run, 0);
  EXPECT_EQ(fast.stats.totals.rays_cast, 0u);
  ASSERT_FALSE(fast.stats.warnings.empty());
  EXPECT_EQ(fast.stats.warnings.front().rfind("scene has no emitter", 0), 0u);
  EXPECT_EQ(full.stats.iterations.size(), 2u);
  EXPECT_GT(full.stats.totals.rays_cast, 0u);
  // The meshes differ (the full run refined), the radiosity is zero in both.
  for (const Solved* r : {&fast, &full})
    for (const auto& l : r->leaves) EXPECT_TRUE((l.radiosity == 0).all());
}

// --iterations 1000 re-ran the same links 990 times: once an iteration re-accepts every
// link and creates none, it is propagated to gather_tolerance and the run stops, with
// the answer of a run asked for exactly that many iterations.
TEST(EffectsShortcut, IterationsStopOnceTheLinksSettle) {
  SolverOptions o = small_options();
  o.iterations = 1000;
  const Solved many = solve(make_builtin("builtin:cornell"), o, "auto");
  const int ran = many.stats.totals.iterations_run;
  EXPECT_LT(ran, 20);
  EXPECT_FALSE(many.stats.effects.iterations.on);
  EXPECT_NE(many.stats.effects.iterations.reason.find(
                fmt::format("stopped after iteration {} of 1000", ran)),
            std::string::npos)
      << many.stats.effects.iterations.reason;
  EXPECT_EQ(many.stats.iterations.back().links_created, 0u);
  o.iterations = ran;
  const Solved exact = solve(make_builtin("builtin:cornell"), o, "auto");
  EXPECT_TRUE(exact.stats.effects.iterations.on);
  ASSERT_EQ(many.leaves.size(), exact.leaves.size());
  for (std::size_t i = 0; i < many.leaves.size(); ++i)
    EXPECT_EQ((many.leaves[i].radiosity - exact.leaves[i].radiosity).abs().maxCoeff(), 0.0) << i;
}

TEST(EffectsShortcut, IterationsRunInFullWhenSomethingChanges) {
  SolverOptions o = small_options();
  o.iterations = 3;
  const Solved r = solve(make_builtin("builtin:cornell"), o, "auto");
  EXPECT_TRUE(r.stats.effects.iterations.on);
  EXPECT_EQ(r.stats.totals.iterations_run, 3);
  EXPECT_EQ(r.stats.iterations.size(), 3u);
}

// --- shaft culling ------------------------------------------------------------------

Scene facing_quads(bool blocker_inside) {
  SceneBuilder b("shaft", "test");
  const auto m = b.add_material(test::material(0.5, 1), {"t", 0});
  b.add_polygon(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, m, {"t", 1});
  b.add_polygon(std::vector<Vec3>{{0, 0, 2}, {0, 1, 2}, {1, 1, 2}, {1, 0, 2}}, m, {"t", 2});
  const double x = blocker_inside ? 0.25 : 3.0;
  b.add_polygon(
      std::vector<Vec3>{{x, 0.25, 1}, {x + 0.5, 0.25, 1}, {x + 0.5, 0.75, 1}, {x, 0.75, 1}}, m,
      {"t", 3});
  return b.finish("t");
}

TEST(Shaft, KnownAnswers) {
  for (bool inside : {true, false}) {
    const Scene scene = facing_quads(inside);
    Hierarchy h(scene, 1);
    const Element* a = nullptr;
    const Element* c = nullptr;
    for (const Element* e : h.elements()) {
      if (e->is_cluster()) continue;
      if (e->face == 0) a = e;
      if (e->face == 1) c = e;
    }
    ASSERT_TRUE(a && c);
    const ShaftCuller shafts(h);
    EXPECT_EQ(shafts.clear(*a, *c), !inside) << "blocker inside: " << inside;
    EXPECT_EQ(shafts.clear(*c, *a), !inside);
  }
}

TEST(Shaft, ClearShaftsAreNeverBlocked) {
  // Soundness: on the Cornell box subdivided twice, every pair the culler calls clear
  // is unblocked by 16 rays; and it does call some pairs clear, and some not.
  const Scene scene = make_builtin("builtin:cornell");
  Hierarchy h(scene, 1);
  const RayScene rays = RayScene::from_scene(scene);
  const Transport t(h, rays, 16, 7);
  LockPool locks(2, 1);
  std::vector<Element*> surfaces;
  for (Element* e : h.elements())
    if (!e->is_cluster())
      for (Element& k : h.subdivide(*e, 0, locks))
        for (Element& g : h.subdivide(k, 0, locks)) surfaces.push_back(&g);
  const ShaftCuller shafts(h);
  int clear = 0, not_clear = 0;
  std::uint64_t cast = 0;
  for (std::size_t i = 0; i < surfaces.size(); i += 3) {
    for (std::size_t j = 1; j < surfaces.size(); j += 5) {
      const Element& r = *surfaces[i];
      const Element& s = *surfaces[j];
      if (t.classify(r, s) != PairClass::Regular) continue;
      if (shafts.clear(r, s)) {
        ++clear;
        ASSERT_EQ(t.visibility(r, s, cast), 1.0) << "faces " << r.face << " " << s.face;
      } else {
        ++not_clear;
      }
    }
  }
  EXPECT_GT(clear, 100);
  EXPECT_GT(not_clear, 100);
}

TEST(Shaft, CullingGivesTheSameRadiosityWithFewerRays) {
  const Scene scene = make_builtin("builtin:cornell");
  SolverOptions o = small_options();
  o.iterations = 2;
  const Solved off = solve(scene, o, "auto");
  o.shaft_culling = ShaftCulling::On;
  const Solved on = solve(scene, o, "auto");
  const Solved forced = solve(scene, o, "all");  // effects = all turns shaft culling off too
  EXPECT_LT(on.stats.totals.rays_cast, off.stats.totals.rays_cast);
  EXPECT_EQ(on.stats.totals.rays_cast + on.stats.totals.rays_skipped,
            off.stats.totals.rays_cast + off.stats.totals.rays_skipped);
  EXPECT_EQ(forced.stats.totals.rays_cast, off.stats.totals.rays_cast);
  expect_same_radiosity(on, off);
}

}  // namespace
}  // namespace hrad
