// Microbenchmarks of scene-side costs that unit tests used to bound by the clock
// (moved here so that a busy machine cannot fail a test):
//  RayOcclusion:  one thread's occlusion rays per second (items/s) on 10k random
//                 triangles (size ~0.05 in the unit cube), for long segments (across
//                 the cube, nearly all blocked; Arg 0) and short ones (length <= 0.2,
//                 mostly free; Arg 1). Was tests/ray_scene_test.cpp's
//                 ThroughputOfOcclusionRays (bound: 1e5 rays/s).
//  RaySceneBuild: building the Embree scene of those 10k triangles.
//  PolygonsNearAFan: RayScene::polygon_boxes() searched round 1,000 points of a disc of N
//                 corners (one polygon, a fan of N - 2 slivers; Arg N) beside a square,
//                 each search stopping at the first polygon but the disc, as the face
//                 crossings' searches stop (items/s: searches). Embree's point query went
//                 on through every sliver box holding the point: time grew with N.
//  CabinGeneration: make_builtin("builtin:cabin"); was tests/builtin_scenes_test.cpp's
//                 CabinGeneratesQuickly (bound: 10 s; well under 1 s in Release).
//  Crossings:     the face crossings' test on every polygon of builtin:lab (Arg 0, 30,400
//                 polygons) and builtin:cabin (Arg 1, 186,680), whole (items/s:
//                 polygons). Candidates found round each polygon's bounding box instead
//                 of a sphere round it: lab 96 -> 75 ms, cabin 610 -> 408 ms (medians of
//                 3, one machine, one session).
//  SelfOverlapStar: the self-crossing check of one star polygon of N thin spikes (Arg N),
//                 whose slanted edges each cover dozens of the check's grid cells: a
//                 sweep over the edges (the grid tested every pair in every shared cell:
//                 50,000 corners took seconds, 200,000 over a minute).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/base/box_tree.h"
#include "core/raycast/face_crossings.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/builtin_scenes.h"
#include "core/scene/self_overlap.h"

namespace {

using namespace hrad;

struct Soup {
  std::vector<Vec3> vertices;
  std::vector<std::uint32_t> indices;
  std::vector<PolygonRange> polys;
};

Soup random_triangles(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0), off(-0.05, 0.05);
  Soup s;
  for (int i = 0; i < n; ++i) {
    const Vec3 c(uni(rng), uni(rng), uni(rng));
    s.polys.push_back({static_cast<std::uint32_t>(s.indices.size()), 3});
    for (int k = 0; k < 3; ++k) {
      s.indices.push_back(static_cast<std::uint32_t>(s.vertices.size()));
      s.vertices.push_back(c + Vec3(off(rng), off(rng), off(rng)));
    }
  }
  return s;
}

const Soup& soup() {
  static const Soup s = random_triangles(10000, 1);
  return s;
}

void BM_RaySceneBuild(benchmark::State& state) {
  for (auto _ : state) {
    const RayScene rs(soup().vertices, soup().indices, soup().polys);
    benchmark::DoNotOptimize(&rs);
  }
}
BENCHMARK(BM_RaySceneBuild)->Unit(benchmark::kMillisecond);

void BM_RayOcclusion(benchmark::State& state) {
  const bool short_segments = state.range(0) != 0;
  const RayScene rs(soup().vertices, soup().indices, soup().polys);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> uni(0.0, 1.0), step(-0.1, 0.1);
  std::vector<std::pair<Vec3, Vec3>> queries(200000);
  for (auto& [from, to] : queries) {
    from = Vec3(uni(rng), uni(rng), uni(rng));
    to = short_segments ? Vec3(from + Vec3(step(rng), step(rng), step(rng)))
                        : Vec3(uni(rng), uni(rng), uni(rng));
  }
  std::size_t blocked = 0;
  for (auto _ : state)
    for (const auto& [from, to] : queries) blocked += rs.occluded(from, to) ? 1 : 0;
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(queries.size()));
  state.counters["blocked_share"] =
      static_cast<double>(blocked) /
      (static_cast<double>(state.iterations()) * static_cast<double>(queries.size()));
}
BENCHMARK(BM_RayOcclusion)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_PolygonsNearAFan(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  Soup s;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    s.vertices.emplace_back(std::cos(a), std::sin(a), 0);
    s.indices.push_back(i);
  }
  s.polys.push_back({0, n});
  for (const Vec3& v : {Vec3(2, 2, 0), Vec3(3, 2, 0), Vec3(3, 3, 0), Vec3(2, 3, 0)}) {
    s.indices.push_back(static_cast<std::uint32_t>(s.vertices.size()));
    s.vertices.push_back(v);
  }
  s.polys.push_back({n, 4});
  const RayScene rs(s.vertices, s.indices, s.polys);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-0.7, 0.7);
  std::vector<Vec3> at(1000);
  for (Vec3& p : at) p = Vec3(uni(rng), uni(rng), 0);
  const auto near = [](const Vec3& p) {
    Aabb b;
    b.extend(p - Vec3::Constant(3));
    b.extend(p + Vec3::Constant(3));
    return b;
  };
  std::size_t found = 0;
  for (auto _ : state)
    for (const Vec3& p : at)
      rs.polygon_boxes().for_each_overlapping(near(p), [&](std::uint32_t poly) {
        if (poly == 0) return true;
        ++found;
        return false;
      });
  benchmark::DoNotOptimize(found);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(at.size()));
}
BENCHMARK(BM_PolygonsNearAFan)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

void BM_CabinGeneration(benchmark::State& state) {
  for (auto _ : state) {
    const Scene s = make_builtin("builtin:cabin");
    benchmark::DoNotOptimize(s.polygon_count());
  }
}
BENCHMARK(BM_CabinGeneration)->Unit(benchmark::kMillisecond);

// The open fractions test each new leaf once (core/raycast/face_crossings.h), and the
// cabin's leaves are its polygons.
void BM_Crossings(benchmark::State& state) {
  const Scene s = make_builtin(state.range(0) == 0 ? "builtin:lab" : "builtin:cabin");
  const RayScene rs = RayScene::from_scene(s);
  const double tol = RayScene::kContactReach * rs.scale();
  std::vector<std::vector<Vec3>> corners(s.polygon_count());
  std::vector<Vec3> normals(s.polygon_count());
  for (std::size_t f = 0; f < s.polygon_count(); ++f) {
    corners[f] = s.face_vertices(f);
    normals[f] = rs.normal(static_cast<std::uint32_t>(f));
  }
  std::size_t crossed = 0;
  for (auto _ : state)
    for (std::size_t f = 0; f < corners.size(); ++f)
      crossed +=
          crossed_inside(rs, s, corners[f], normals[f], static_cast<std::uint32_t>(f), tol) ? 1 : 0;
  state.counters["crossed_share"] =
      static_cast<double>(crossed) /
      (static_cast<double>(state.iterations()) * static_cast<double>(corners.size()));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(corners.size()));
}
BENCHMARK(BM_Crossings)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_SelfOverlapStar(benchmark::State& state) {
  const auto corners = static_cast<int>(state.range(0));
  std::vector<Vec3> p;
  for (int i = 0; i < corners; ++i) {
    const double a = 2 * 3.141592653589793 * i / corners, r = i % 2 == 0 ? 1.0 : 0.9;
    p.emplace_back(r * std::cos(a), 0, -r * std::sin(a));
  }
  for (auto _ : state) benchmark::DoNotOptimize(find_self_overlap(p).found);
  state.SetItemsProcessed(state.iterations() * corners);
}
BENCHMARK(BM_SelfOverlapStar)->Arg(50000)->Arg(200000)->Unit(benchmark::kMillisecond);

}  // namespace
