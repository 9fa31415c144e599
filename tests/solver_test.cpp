// End-to-end tests of the hierarchical solver on scenes with known answers.
#include "core/solver/solver.h"
#include "core/base/interrupt.h"
#include "core/scene/builtin_scenes.h"
#include "core/scene/probes.h"
#include "core/solver/propagation.h"
#include "schedulers/scheduler.h"
#include "tests/read_text.h"
#include "tests/solver_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <sstream>
#include <string>

namespace hrad {
namespace {

Scene furnace(double rho, double e, bool object) {
  SceneBuilder b("furnace", "test");
  const auto m = b.add_material(test::material(rho, e), {"t", 0});
  test::add_room(b, Vec3(0, 0, 0), Vec3(1, 1, 1), m, 2, true);
  if (object) test::add_room(b, Vec3(0.3, 0.2, 0.35), Vec3(0.6, 0.5, 0.7), m, 1, false);
  return b.finish("t");
}

double area_mean(const std::vector<Solver::Leaf>& leaves, int channel = 0) {
  double sum = 0, area = 0;
  for (const auto& l : leaves) {
    sum += l.area * l.radiosity[channel];
    area += l.area;
  }
  return sum / area;
}

void expect_finite_nonnegative(const std::vector<Solver::Leaf>& leaves) {
  for (const auto& l : leaves) {
    ASSERT_TRUE(l.radiosity.isFinite().all()) << "leaf " << l.id;
    ASSERT_TRUE((l.radiosity >= 0).all()) << "leaf " << l.id;
  }
}

// The furnace: a closed room (and closed objects) where every face emits E and
// reflects rho has B = E / (1 - rho) everywhere.
//
// With row_sums = normalize every leaf gathers exactly 1 - escape = 1 of the
// surrounding radiosity (no ray escapes a closed scene, so the correction has no
// noise), and the solution must be the closed form to 1e-3 at every leaf, even at
// rho = 0.99 where plain Jacobi sweeps would need hundreds of sweeps (0.99^k) and the
// accelerated propagation (core/solver/propagation.h) needs under a hundred.
TEST(SolverFurnace, NormalizedRowSumsGiveClosedFormEverywhere) {
  for (const char* spec : {"builtin:furnace?objects=0", "builtin:furnace"}) {
    for (double rho : {0.5, 0.9, 0.99}) {
      const Scene scene = make_builtin(
          std::string(spec) + (std::string(spec).find('?') == std::string::npos ? "?" : "&") +
          "rho=" + std::to_string(rho));
      SolverOptions o;
      o.iterations = 2;
      o.row_sums = RowSumMode::Normalize;
      Solver s(scene, o);
      const RunStats st = s.run();
      const double e = scene.materials[0].emission[0];
      const double expected = e / (1 - rho);
      const auto leaves = s.leaves();
      expect_finite_nonnegative(leaves);
      for (const auto& l : leaves) {
        ASSERT_NEAR(l.radiosity[0], expected, 1e-3 * expected) << spec << " rho " << rho;
      }
      if (rho == 0.99) {
        EXPECT_GT(st.iterations.front().gather_sweeps, 20);
        EXPECT_LT(st.iterations.front().gather_sweeps, 100);
      }
    }
  }
}

// Without correction the hierarchical estimate conserves energy globally (the
// area-weighted mean row sum is 1 up to quadrature error) but redistributes it:
// leaves in corners gather up to ~30% too much from coarse ancestors' links. The
// raw area-weighted mean therefore matches only to a few percent at rho = 0.5.
TEST(SolverFurnace, RawTransportConservesEnergyOnAverage) {
  const Scene scene = furnace(0.5, 1.0, true);
  SolverOptions o;
  o.iterations = 2;
  o.row_sums = RowSumMode::Keep;
  Solver s(scene, o);
  const RunStats st = s.run();
  EXPECT_NEAR(st.iterations.back().row_sum_mean, 1.0, 0.01);
  EXPECT_GT(st.iterations.back().row_sum_max, 1.0) << "the known local overshoot vanished?";
  EXPECT_NEAR(area_mean(s.leaves()), 2.0, 0.03 * 2.0);
}

// At default settings (no row-sum rescale) the furnace of builtin:furnace at rho 0.9,
// a closed room with a cube and an octahedron floating in it, and the same room
// empty: the mean leaf row sum is 1 to 1e-3 and the area-weighted mean radiosity is
// within 1 % of E / (1 - rho) = 10 (measured -0.5 % and -0.2 %). Before push weights
// (core/solver/push_weights.h) the leaves' row sums spread over 0.83-1.44 (a corner leaf
// inherited its ancestors' mean form factor to the nearby walls), which 1 / (1 - rho S)
// turned into a surplus of 4.3 % (room with objects) and 4.7 % (empty room); with push
// weights from an element's own links only, +1.0 % and +1.4 %.
TEST(SolverFurnace, DefaultSettingsConserveEnergy) {
  for (const char* spec : {"builtin:furnace?rho=0.9", "builtin:furnace?rho=0.9&objects=0"}) {
    const Scene scene = make_builtin(spec);
    Solver s(scene, SolverOptions{});
    const RunStats st = s.run();
    EXPECT_NEAR(st.iterations.back().row_sum_mean, 1.0, 1e-3) << spec;
    const auto leaves = s.leaves();
    expect_finite_nonnegative(leaves);
    EXPECT_NEAR(area_mean(leaves), 10.0, 0.01 * 10.0) << spec;
    std::printf("%s: area-mean radiosity %.4f (exact 10), row sums %.3f-%.3f\n", spec,
                area_mean(leaves), st.iterations.back().row_sum_min,
                st.iterations.back().row_sum_max);
  }
}

// Issue 13's row-sum distribution: in a closed room every open leaf sees geometry over
// its whole hemisphere, so its row sum (own and inherited links) should be 1. At the
// defaults, the share of the open area within 0.97-1.03: the empty furnace room at
// least 99 % (measured 100 %, every leaf within 0.982-1.016), the room with a floating
// cube and octahedron at least 98 % (measured 98.9 %). With push weights from an
// element's own links only these were 80 % and 79 % (corner and edge leaves 2-14 %
// high, their neighbours a few percent low).
TEST(SolverFurnace, RowSumsOfAClosedRoomAreOneAtTheDefaults) {
  {
    const Scene scene = make_builtin("builtin:furnace?rho=0.9&objects=0");
    Solver s(scene, SolverOptions{});
    const IterationStats it = s.run().iterations.back();
    EXPECT_GE(it.row_sum_within_band, 0.99);
    EXPECT_GT(it.row_sum_min, 0.97);
    EXPECT_LT(it.row_sum_max, 1.03);
  }
  {
    const Scene scene = make_builtin("builtin:furnace?rho=0.9");
    Solver s(scene, SolverOptions{});
    EXPECT_GE(s.run().iterations.back().row_sum_within_band, 0.98);
  }
}

// The cluttered furnace (builtin:furnace?objects=2: 22 boxes and plates floating,
// stacked, standing on the floor, against walls, in a 5 cm gap) at default settings.
// Every open point has irradiance E / (1 - rho) = 2 (rho 0.5) or 10 (rho 0.9).
// Probes on open faces (room walls away from the boxes, tops and sides of floating
// and standing boxes, both faces of a floating plate, the cube in the gap): their mean
// within 1.5 % (measured -0.25 % at rho 0.5, -1.1 % at rho 0.9), each within 3 % / 5 %
// (the worst: +2.1 % and -3.1 %; with push weights from an element's own links only
// the mean was -0.5 % / -0.9 % and the worst -3.6 % / -7.7 %). Before faces in contact
// were kept out of the energy books and straddling pairs refined, random probes were
// 2.7 % and 13.6 % low on average; before push weights and occluded cluster links
// weighed, these probes' mean was -1.9 % and -2.2 % and the worst -10 %. Issue 13's
// target, 1 % each, is not met.
TEST(SolverFurnace, ClutteredFurnaceAtDefaults) {
  const std::vector<Probe> probes = {
      {{0.2, 0.8, 1e-4}, {0, 0, 1}},           {{0.5, 0.5, 1 - 1e-4}, {0, 0, -1}},  // z walls
      {{1e-4, 0.3, 0.2}, {1, 0, 0}},           {{1 - 1e-4, 0.7, 0.7}, {-1, 0, 0}},  // x walls
      {{0.3, 1 - 1e-4, 0.3}, {0, -1, 0}},      {{0.15, 1e-4, 0.4}, {0, 1, 0}},  // ceiling, floor
      {{0.16, 0.52 + 1e-4, 0.16}, {0, 1, 0}},   // top of a floating box
      {{0.16, 0.40 - 1e-4, 0.16}, {0, -1, 0}},  // its underside
      {{0.40, 0.33 + 1e-4, 0.40}, {0, 1, 0}},   // top of the stack
      {{0.30 - 1e-4, 0.07, 0.40}, {-1, 0, 0}},  // side of the stack's bottom box
      {{0.25, 0.755 + 1e-4, 0.30}, {0, 1, 0}},  // a floating plate, top ...
      {{0.25, 0.75 - 1e-4, 0.30}, {0, -1, 0}},  // ... and bottom
      {{0.225, 0.14 + 1e-4, 0.75}, {0, 1, 0}},  // the cube in the 5 cm gap
      {{0.90, 0.25 + 1e-4, 0.90}, {0, 1, 0}},   // box in the floor's corner, top
  };
  for (const double rho : {0.5, 0.9}) {
    const Scene scene = make_builtin("builtin:furnace?objects=2&rho=" + std::to_string(rho));
    Solver s(scene, SolverOptions{});
    s.run();
    const double exact = 1 / (1 - rho);
    const std::vector<Rgb> e = s.probe_irradiance(probes);
    double mean = 0, worst = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
      EXPECT_NEAR(e[i][0], exact, (rho < 0.7 ? 0.03 : 0.05) * exact)
          << "probe " << i << " rho " << rho;
      mean += e[i][0] / static_cast<double>(e.size());
      if (std::abs(e[i][0] / exact - 1) > std::abs(worst)) worst = e[i][0] / exact - 1;
    }
    EXPECT_NEAR(mean, exact, 0.015 * exact) << "rho " << rho;
    std::printf(
        "cluttered furnace rho %.1f: mean probe irradiance %.4f (exact %.4f), worst %+.2f %%\n",
        rho, mean, exact, 100 * worst);
  }
}

// decision_rays = independent draws an accepted link's visibility again where the
// oracle's decision depended on it. The decisions read the first rays in both modes,
// so the first iteration's link set is the same; only the estimates (and so the
// solution) differ, at the cost of more rays.
TEST(SolverDecisionRays, IndependentEstimatesKeepTheLinkSet) {
  const Scene scene = make_builtin("builtin:furnace?objects=2&rho=0.5");
  SolverOptions o;
  o.iterations = 1;
  Solver shared(scene, o);
  const RunStats a = shared.run();
  o.decision_rays = DecisionRays::Independent;
  Solver independent(scene, o);
  const RunStats b = independent.run();
  ASSERT_GT(a.iterations.at(0).links_created, 1000u);
  EXPECT_EQ(shared.link_ids(), independent.link_ids());
  EXPECT_GT(b.iterations.at(0).rays_cast, a.iterations.at(0).rays_cast);
  const auto la = shared.leaves(), lb = independent.leaves();
  ASSERT_EQ(la.size(), lb.size());
  int changed = 0;
  for (std::size_t i = 0; i < la.size(); ++i) changed += la[i].radiosity[0] != lb[i].radiosity[0];
  EXPECT_GT(changed, 0);
}

// decision_visibility_rays: the rays of the decisions that depend on a visibility
// estimate (an occluded link with a cluster end weighs more in the oracles). 0 means
// visibility_rays, so setting it to visibility_rays changes nothing; 16 finds more
// cluster pairs partly hidden than 4 do, and opens them: more links, other radiosities.
TEST(SolverDecisionRays, DecisionRaysOpenMoreHiddenClusterPairs) {
  const Scene scene = make_builtin("builtin:furnace?objects=2&rho=0.5");
  SolverOptions o;
  o.iterations = 1;
  Solver plain(scene, o);
  const RunStats a = plain.run();
  o.decision_visibility_rays = o.visibility_rays;
  Solver same(scene, o);
  same.run();
  o.decision_visibility_rays = 16;
  Solver more(scene, o);
  const RunStats c = more.run();
  EXPECT_EQ(plain.link_ids(), same.link_ids());
  const auto la = plain.leaves(), lb = same.leaves();
  ASSERT_EQ(la.size(), lb.size());
  for (std::size_t i = 0; i < la.size(); ++i) EXPECT_EQ(la[i].radiosity[0], lb[i].radiosity[0]);
  EXPECT_GT(c.iterations.at(0).links_created, a.iterations.at(0).links_created);
}

// push_visibility = child: each child its own visibility to its parent's partly
// visible links in the push weights. In the cluttered furnace (rho 0.5, exact B = 2)
// leaves beside the boxes stop inheriting light the boxes block, so more of the area
// is within 3 % of the exact value (86 -> 90 % of the leaf area here, 2 iterations;
// asserted: at least 3 points more) and the worst leaf is nearer; the push rays are
// counted; and the result does not depend on the thread count.
TEST(SolverPushVisibility, ChildVisibilityNarrowsTheClutteredFurnace) {
  const Scene scene = make_builtin("builtin:furnace?objects=2&rho=0.5");
  SolverOptions o;
  o.iterations = 2;
  const auto solve = [&](PushVisibility mode, int threads, RunStats* stats) {
    o.push_visibility = mode;
    o.threads = threads;
    Solver s(scene, o);
    *stats = s.run();
    return s.leaves();
  };
  const auto within = [](const std::vector<Solver::Leaf>& leaves, double* worst) {
    double near = 0, total = 0;
    *worst = 0;
    for (const auto& l : leaves) {
      const double d = std::abs(l.radiosity[0] - 2.0) / 2.0;
      if (l.radiosity[0] < 1.5) continue;  // closed in by a contact (B = E there)
      total += l.area;
      if (d <= 0.03) near += l.area;
      *worst = std::max(*worst, d);
    }
    return near / total;
  };
  RunStats link_stats, child_stats, child2_stats;
  const auto by_link = solve(PushVisibility::Link, 1, &link_stats);
  const auto by_child = solve(PushVisibility::Child, 1, &child_stats);
  const auto by_child2 = solve(PushVisibility::Child, 2, &child2_stats);
  double worst_link = 0, worst_child = 0;
  const double near_link = within(by_link, &worst_link),
               near_child = within(by_child, &worst_child);
  std::printf("[ PushVisibility ] area within 3 %%: link %.3f, child %.3f; worst %.3f, %.3f\n",
              near_link, near_child, worst_link, worst_child);
  EXPECT_GT(near_child, near_link + 0.03);
  EXPECT_LT(worst_child, worst_link);
  EXPECT_GT(child_stats.iterations.back().rays_cast, link_stats.iterations.back().rays_cast);
  ASSERT_EQ(by_child.size(), by_child2.size());
  for (std::size_t i = 0; i < by_child.size(); ++i)
    ASSERT_NEAR(by_child[i].radiosity[0], by_child2[i].radiosity[0],
                1e-9 * by_child[i].radiosity[0]);
}

// Clamping row sums at 1 is a physical bound: with uniform E and rho no leaf can
// then exceed E / (1 - rho) (maximum principle), whatever the links.
TEST(SolverFurnace, ClampedRowSumsNeverExceedClosedForm) {
  for (double rho : {0.5, 0.9}) {
    const Scene scene = furnace(rho, 1.0, true);
    SolverOptions o;
    o.iterations = 2;
    o.row_sums = RowSumMode::Clamp;
    Solver s(scene, o);
    const RunStats st = s.run();
    EXPECT_GT(st.iterations.back().row_sum_corrected, 0u);
    for (const auto& l : s.leaves()) ASSERT_LE(l.radiosity[0], (1 + 1e-9) / (1 - rho));
  }
}

// After k Jacobi sweeps from B_0 = E, a furnace with exact (normalized) row sums
// has B_k = E (1 - rho^(k+1)) / (1 - rho) at every leaf: the first kPlainSweeps + 1
// sweeps are plain, whatever comes after. Then the contraction (rho) has settled and
// the sweeps are accelerated: after 20 sweeps B is far nearer the limit E / (1 - rho)
// than the plain series' 20th partial sum (1.09 short of 10): under a hundredth of that.
TEST(SolverFurnace, JacobiSweepsFollowGeometricSeries) {
  const double rho = 0.9;
  const Scene scene = make_builtin("builtin:furnace?rho=0.9&emission=1");
  for (int k : {1, 2, kPlainSweeps + 1, 20}) {
    SolverOptions o;
    o.iterations = 1;
    o.row_sums = RowSumMode::Normalize;
    o.max_gather_sweeps = k;
    Solver s(scene, o);
    const RunStats st = s.run();
    ASSERT_EQ(st.iterations.front().gather_sweeps, k);
    const double plain = (1 - std::pow(rho, k + 1)) / (1 - rho);
    const double limit = 1 / (1 - rho);
    for (const auto& l : s.leaves()) {
      if (k <= kPlainSweeps + 1) {
        ASSERT_NEAR(l.radiosity[0], plain, 1e-6 * plain) << k;
      } else {
        ASSERT_LT(std::abs(l.radiosity[0] - limit), 0.01 * (limit - plain)) << k;
      }
    }
  }
}

TEST(SolverHardCases, NoEmitterGivesZeroSolutionAndWarning) {
  SceneBuilder b("dark", "test");
  const auto m = b.add_material(test::material(0.5, 0.0), {"t", 0});
  test::add_room(b, Vec3(0, 0, 0), Vec3(1, 1, 1), m, 1, true);
  const Scene scene = b.finish("t");
  Solver s(scene, SolverOptions{});
  const RunStats st = s.run();
  EXPECT_TRUE(st.iterations.empty());
  ASSERT_FALSE(st.warnings.empty());
  for (const auto& l : s.leaves()) EXPECT_TRUE((l.radiosity == 0).all());
}

// An emitter very close to a receiver: the bounded estimators keep every value
// finite and the receiver's irradiance below the emitter's exitance.
TEST(SolverHardCases, EmitterCloseToReceiverStaysBounded) {
  for (double gap : {0.01, 0.001}) {
    SceneBuilder b("close", "test");
    const auto floor = b.add_material(test::material(0.0, 0.0), {"t", 0});
    const auto lamp = b.add_material(test::material(0.0, 1.0), {"t", 0});
    const std::vector<Vec3> f = {{0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}};          // faces +y
    const std::vector<Vec3> l = {{0, gap, 0}, {0, gap, -1}, {1, gap, -1}, {1, gap, 0}};  // faces -y
    b.add_polygon(f, floor, {"t", 0});
    b.add_polygon(l, lamp, {"t", 0});
    const Scene scene = b.finish("t");
    SolverOptions o;
    o.iterations = 2;
    Solver s(scene, o);
    s.run();
    // With rho = 0 on the floor, B is 0 there; the probe just above the floor's
    // centre sees the lamp with F -> 0.98 or more (closed form for a point under a
    // unit square: 0.9996 at 0.01, 0.99996 at 0.001).
    const std::vector<Probe> probes = {{Vec3(0.5, 0, -0.5), Vec3(0, 1, 0)}};
    const std::vector<Rgb> e = s.probe_irradiance(probes);
    EXPECT_GT(e[0][0], 0.98) << "gap " << gap;
    EXPECT_LE(e[0][0], 1.0 + 1e-9) << "gap " << gap;
    expect_finite_nonnegative(s.leaves());
  }
}

Scene scaled_cornellish(double scale) {
  SceneBuilder b("scaled", "test");
  const auto white = b.add_material(test::material(0.7, 0.0), {"t", 0});
  const auto lamp = b.add_material(test::material(0.0, 5.0), {"t", 0});
  test::add_room(b, Vec3(0, 0, 0) * scale, Vec3(1, 1, 1) * scale, white, 1, true);
  test::add_room(b, Vec3(0.2, 0.0, 0.2) * scale, Vec3(0.5, 0.4, 0.5) * scale, white, 1, false);
  const std::vector<Vec3> l = {Vec3(0.4, 0.99, 0.4) * scale, Vec3(0.6, 0.99, 0.4) * scale,
                               Vec3(0.6, 0.99, 0.6) * scale, Vec3(0.4, 0.99, 0.6) * scale};
  b.add_polygon(l, lamp, {"t", 0});  // (0.4,0.4)->(0.6,0.4)->(0.6,0.6): normal -y
  return b.finish("t");
}

// Radiosity is power per area and every tolerance is relative to the scene's
// size, so scaling the scene must not change the solution.
TEST(SolverHardCases, ScaleInvariance) {
  SolverOptions o;
  o.iterations = 2;
  std::vector<std::vector<Solver::Leaf>> results;
  for (double scale : {1.0, 1e-3, 1e3}) {
    const Scene scene = scaled_cornellish(scale);
    Solver s(scene, o);
    s.run();
    results.push_back(s.leaves());
  }
  for (std::size_t k = 1; k < results.size(); ++k) {
    ASSERT_EQ(results[k].size(), results[0].size()) << "scale changed the mesh";
    for (std::size_t i = 0; i < results[0].size(); ++i) {
      const Rgb& a = results[0][i].radiosity;
      const Rgb& b = results[k][i].radiosity;
      ASSERT_LE((a - b).abs().maxCoeff(), 1e-4 * std::max(1.0, a.abs().maxCoeff()))
          << "leaf " << i << " scale " << k;
    }
  }
}

// The oracles judge each colour channel against its own light (channel_weights in
// oracles/oracle.h): dimming the red and green of the Cornell box's light by powers of
// two refines the same links as the grey light, and the solution's channels scale by
// those factors (the propagation stops on the largest channel's change relative to the
// brightest radiosity, so a channel dimmed eightfold converges to about eight times
// gather_tolerance of the brightest radiosity). Unweighted, red and green lost their say
// to blue (the red wall reflects 0.63 of a red now an eighth as bright): 39,057 links
// against 47,698.
TEST(SolverColour, DimmingAChannelOfTheLightRefinesTheSameLinks) {
  SolverOptions o;
  o.iterations = 2;
  std::vector<std::vector<std::pair<std::uint64_t, std::uint64_t>>> links;
  std::vector<std::vector<Solver::Leaf>> leaves;
  const Rgb dim(0.125, 0.25, 1);
  for (const bool coloured : {false, true}) {
    Scene scene = make_builtin("builtin:cornell");
    if (coloured)
      for (Material& m : scene.materials)
        if (m.emits()) m.emission *= dim;
    Solver s(scene, o);
    s.run();
    links.push_back(s.link_ids());
    leaves.push_back(s.leaves());
  }
  ASSERT_EQ(links[1].size(), links[0].size());
  ASSERT_TRUE(links[1] == links[0]) << "the same number of links, not the same links";
  ASSERT_EQ(leaves[0].size(), leaves[1].size());
  double brightest = 0;
  for (const Solver::Leaf& l : leaves[0]) brightest = std::max(brightest, l.radiosity.maxCoeff());
  for (std::size_t i = 0; i < leaves[0].size(); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(leaves[1][i].radiosity[c], dim[c] * leaves[0][i].radiosity[c],
                  20 * o.gather_tolerance * brightest)
          << "leaf " << i << " channel " << c;
}

// Two rooms share one floor polygon; a wall stands on it. Only room A has a
// light. Whatever reaches room B leaks through the shared floor element, and
// refinement must make that leak small.
TEST(SolverLightLeak, DarkRoomStaysDark) {
  SceneBuilder b("leak", "test");
  const SourceLoc at{"t", 0};
  const auto white = b.add_material(test::material(0.7, 0.0), at);
  const auto lamp = b.add_material(test::material(0.0, 10.0), at);
  // Floor y = 0 over x in [0,2], z in [0,1], facing +y.
  b.add_polygon(std::vector<Vec3>{{0, 0, 0}, {0, 0, 1}, {2, 0, 1}, {2, 0, 0}}, white, at);
  for (int room = 0; room < 2; ++room) {
    const double x0 = room, x1 = room + 1;
    // Ceiling (facing -y), back and front walls (facing into the room), end wall.
    b.add_polygon(std::vector<Vec3>{{x0, 1, 0}, {x1, 1, 0}, {x1, 1, 1}, {x0, 1, 1}}, white, at);
    b.add_polygon(std::vector<Vec3>{{x0, 0, 0}, {x1, 0, 0}, {x1, 1, 0}, {x0, 1, 0}}, white, at);
    b.add_polygon(std::vector<Vec3>{{x0, 0, 1}, {x0, 1, 1}, {x1, 1, 1}, {x1, 0, 1}}, white, at);
  }
  b.add_polygon(std::vector<Vec3>{{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, white, at);  // +x
  b.add_polygon(std::vector<Vec3>{{2, 0, 0}, {2, 0, 1}, {2, 1, 1}, {2, 1, 0}}, white, at);  // -x
  // The dividing wall at x = 1, one face into each room.
  b.add_polygon(std::vector<Vec3>{{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}}, white, at);  // -x
  b.add_polygon(std::vector<Vec3>{{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, white, at);  // +x
  b.add_polygon(
      std::vector<Vec3>{{0.4, 0.99, 0.4}, {0.6, 0.99, 0.4}, {0.6, 0.99, 0.6}, {0.4, 0.99, 0.6}},
      lamp, at);
  const Scene scene = b.finish("t");
  SolverOptions o;
  Solver s(scene, o);
  s.run();
  double lit = 0, lit_area = 0, dark = 0, dark_area = 0;
  for (const auto& l : s.leaves()) {
    if (l.radiosity.maxCoeff() > 5) continue;  // the lamp
    if (l.center.x() < 0.95) {
      lit += l.area * l.radiosity[0];
      lit_area += l.area;
    } else if (l.center.x() > 1.05) {
      dark += l.area * l.radiosity[0];
      dark_area += l.area;
    }
  }
  ASSERT_GT(lit_area, 0);
  ASSERT_GT(dark_area, 0);
  EXPECT_LT(dark / dark_area, 0.01 * lit / lit_area) << "light leaks into the dark room";
}

}  // namespace
}  // namespace hrad

namespace hrad {
namespace {

// Convergence on the Cornell box: irradiance at interior probes against a fine
// reference (eps = 2e-5) must fall as eps falls.
TEST(SolverConvergence, CornellErrorFallsWithEps) {
  const Scene scene = make_builtin("builtin:cornell");
  const Aabb b = scene.bounds();
  std::vector<Probe> probes;
  for (int i = 1; i <= 3; ++i)
    for (int j = 1; j <= 3; ++j)
      for (const Vec3& n : {Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, -1, 0)}) {
        const Vec3 t(i / 4.0, 0.5, j / 4.0);
        probes.push_back({b.lo + b.extent().cwiseProduct(t), n});
      }
  auto solve = [&](double eps) {
    SolverOptions o;
    o.eps = eps;
    o.min_area = 1e-5;
    Solver s(scene, o);
    s.run();
    return s.probe_irradiance(probes);
  };
  const std::vector<Rgb> ref = solve(2e-5);
  auto error = [&](const std::vector<Rgb>& e) {
    double num = 0, den = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
      num += (e[i] - ref[i]).abs().sum();
      den += ref[i].abs().sum();
    }
    return num / den;
  };
  const double coarse = error(solve(1e-2)), mid = error(solve(1e-3)), fine = error(solve(1e-4));
  EXPECT_LT(mid, coarse);
  EXPECT_LT(fine, mid);
  EXPECT_LT(fine, 0.05) << "relative L1 error at eps 1e-4";
  std::printf("[ Convergence ] relative L1 probe error: eps 1e-2 %.4f, 1e-3 %.4f, 1e-4 %.4f\n",
              coarse, mid, fine);
}

}  // namespace
}  // namespace hrad

namespace hrad {
namespace {

// Per-member cosines at cluster receivers redistribute what a cluster gathers among
// its members but must not change the total: after one sweep from B = E, the
// power gathered by all leaves is the same in both modes, while some leaves differ.
// (A scene without contacts: where part of a member is closed in, what it gathers is
// per unit of open area, core/transport/open_fraction.h, and a leaf's area alone would not
// weigh it.)
TEST(SolverClusterReceiver, CosineRedistributesButConservesGatheredPower) {
  const Scene scene = make_builtin("builtin:furnace?objects=1&rho=0.5");
  auto gathered = [&](ClusterReceiver mode, std::vector<Solver::Leaf>* leaves) {
    SolverOptions o;
    o.iterations = 1;
    o.eps = 1e-2;
    o.max_gather_sweeps = 1;
    o.row_sums = RowSumMode::Keep;
    o.cluster_receiver = mode;
    Solver s(scene, o);
    s.run();
    *leaves = s.leaves();
    double power = 0;
    for (const auto& l : *leaves) {
      const Material& m = scene.materials[scene.faces[l.face].material];
      if (m.reflectance[1] > 0)
        power += l.area * (l.radiosity[1] - m.emission[1]) / m.reflectance[1];
    }
    return power;
  };
  std::vector<Solver::Leaf> iso, cos;
  const double p_iso = gathered(ClusterReceiver::Isotropic, &iso),
               p_cos = gathered(ClusterReceiver::Cosine, &cos);
  EXPECT_GT(p_iso, 0);
  // Equal up to the single precision of the clusters' directional areas (float in
  // the links' form factors, summed in double over the open members by the gather).
  EXPECT_NEAR(p_cos, p_iso, 1e-5 * p_iso);
  ASSERT_EQ(iso.size(), cos.size());
  double moved = 0;
  for (std::size_t i = 0; i < iso.size(); ++i)
    moved = std::max(moved, std::abs(iso[i].radiosity[1] - cos[i].radiosity[1]));
  EXPECT_GT(moved, 0) << "cosine mode changed nothing: no cluster receiver links?";
}

// In a closed furnace every member of a cluster has the same radiosity, so neither the
// cosine split nor weighing the members by their exposure (cluster_members = exposed,
// core/transport/cluster_exposure.h) changes anything: B = E / (1 - rho) everywhere.
TEST(SolverClusterReceiver, CosineFurnaceStillExactWithNormalizedRowSums) {
  const Scene scene = make_builtin("builtin:furnace?rho=0.9");
  for (const ClusterMembers members : {ClusterMembers::Alike, ClusterMembers::Exposed}) {
    SolverOptions o;
    o.iterations = 2;
    o.row_sums = RowSumMode::Normalize;
    o.cluster_receiver = ClusterReceiver::Cosine;
    o.cluster_members = members;
    o.eps = 1e-3;
    Solver s(scene, o);
    const RunStats stats = s.run();
    EXPECT_EQ(stats.iterations.front().exposure_rays > 0, members == ClusterMembers::Exposed);
    const double expected = scene.materials[0].emission[0] / (1 - 0.9);
    for (const auto& l : s.leaves()) {
      ASSERT_NEAR(l.radiosity[0], expected, 1e-3 * expected);
    }
  }
}

}  // namespace
}  // namespace hrad

namespace hrad {
namespace {

// builtin:office at default settings against the path-traced reference stored with
// the accuracy-time figure (docs/figures/accuracy-time/, 18 probes, 0.5 % relative
// standard error each). Before the oracle weighed occluded cluster links
// (oracles/oracle.h) the mean signed error here was -13 %; now it is -1.5 % (median
// 1.0 %). The tolerance, 3.5 %, leaves room for the reference's noise and for small
// changes elsewhere, and fails on the old bias by a wide margin.
TEST(SolverAccuracy, OfficeAtDefaultsIsNotDark) {
  const std::string csv = test::read_text(
      std::string(HRAD_SOURCE_DIR) + "/docs/figures/accuracy-time/reference-builtin_office.csv");
  ASSERT_FALSE(csv.empty());
  std::vector<Probe> probes;
  std::vector<double> ref;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // header: x,y,z,nx,ny,nz,E_r,E_g,E_b,...
  while (std::getline(in, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream f(line);
    double v[9];
    for (double& x : v) f >> x;
    if (!f) continue;
    probes.push_back({Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5]).normalized()});
    ref.push_back(v[6] + v[7] + v[8]);
  }
  ASSERT_EQ(probes.size(), 18u);
  const Scene scene = make_builtin("builtin:office");
  SolverOptions o;
  o.threads = 2;  // the result does not depend on it
  Solver s(scene, o);
  s.run();
  const std::vector<Rgb> got = s.probe_irradiance(probes);
  double bias = 0;
  std::vector<double> abs_err;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const double e = got[i].sum() / ref[i] - 1;
    bias += e / static_cast<double>(probes.size());
    abs_err.push_back(std::abs(e));
  }
  std::sort(abs_err.begin(), abs_err.end());
  const double median = 0.5 * (abs_err[8] + abs_err[9]);
  std::printf("[ Accuracy ] office at defaults: signed mean %+.2f %%, median |error| %.2f %%\n",
              100 * bias, 100 * median);
  EXPECT_LT(std::abs(bias), 0.035) << "signed mean relative error";
  EXPECT_LT(median, 0.04) << "median relative error";
}

// An interrupt (core/base/interrupt.h) unwinds a run at its first safe point, with two
// refiners as with one, and leaves nothing that stops the next run.
TEST(SolverInterrupt, StopsAtTheFirstSafePointAndTheNextRunIsWhole) {
  const Scene scene = make_builtin("builtin:cornell");
  for (int threads : {1, 2}) {
    SolverOptions o;
    o.threads = threads;
    o.iterations = 1;
    Solver stopped(scene, o);
    simulate_interrupt(SIGINT);
    try {
      (void)stopped.run();
      ADD_FAILURE() << "not interrupted";
    } catch (const Interrupted& e) {
      EXPECT_EQ(e.exit_status(), 130);
    }
    simulate_interrupt(0);
    Solver whole(scene, o);
    EXPECT_GT(whole.run().totals.links, 10000u);
  }
}

// max_memory_gb stops a refinement stage (with one refiner or two) and the run fails
// with a message that says what to change. (A limit below what preparing the scene
// takes stops the Solver's construction instead: tests/hostile_input_test.cpp.)
TEST(SolverMemoryCap, StopsARefinementThatOutgrowsIt) {
  const Scene scene = make_builtin("builtin:office");
  for (int threads : {1, 2}) {
    SolverOptions o;
    o.threads = threads;
    o.eps = 1e-30;
    o.max_memory_gb = 0.03;
    Solver s(scene, o);
    try {
      (void)s.run();
      ADD_FAILURE() << "not stopped";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("raise eps or min_area"), std::string::npos) << e.what();
    }
  }
}

// The Solver checks names against the registries, before anything is built, with the
// registries' own message (make_scheduler's and make_oracle's).
TEST(SolverNames, UnknownNamesGiveTheRegistriesMessages) {
  const Scene scene = make_builtin("builtin:cornell");
  const auto message = [](const auto& f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  SolverOptions o;
  o.scheduler = "lifo";
  const std::string registry = message([] { (void)make_scheduler("lifo", SchedulerConfig{}); });
  EXPECT_EQ(message([&] { Solver s(scene, o); }), registry);
  o = SolverOptions{};
  o.oracle = "BF";
  EXPECT_EQ(message([&] { Solver s(scene, o); }), "unknown oracle 'BF' (known: bf, error)");
}

}  // namespace
}  // namespace hrad
