// Microbenchmark of the form-factor estimators (core/transport/form_factor.h): cost per call of
// each function on typical solver inputs (a triangle or quad source, a quadrature order
// of 1-3 for polygon-to-polygon). Google Benchmark; links hrad_lib.
#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <vector>

#include "core/transport/form_factor.h"

namespace {

using hrad::Vec3;

// A pool of receiver points/normals in front of the sources, varied so the branch
// predictor does not memorise one configuration.
struct Points {
  std::vector<Vec3> x, n;
  explicit Points(double z_lo, double z_hi, double tilt) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> U(0, 1);
    for (int i = 0; i < 1024; ++i) {
      x.emplace_back(-0.5 + 2 * U(rng), -0.5 + 2 * U(rng), z_lo + (z_hi - z_lo) * U(rng));
      n.push_back(Vec3(tilt * (U(rng) - 0.5), tilt * (U(rng) - 0.5), -1).normalized());
    }
  }
};

// Sources in the plane z = 0, facing +z (towards the points above).
const std::array<Vec3, 4> kQuad = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
const std::array<Vec3, 3> kTri = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.3, 0.9, 0)};

template <std::size_t K>
void point_to_polygon(benchmark::State& state, const std::array<Vec3, K>& poly, double tilt) {
  // tilt = 0: receivers parallel to the source (no clipping); tilt = 4: strongly tilted
  // receivers whose horizon often cuts the source (clipping path).
  const Points pts(0.05, 1.5, tilt);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(hrad::point_to_polygon_ff(pts.x[i], pts.n[i], poly));
    i = (i + 1) & 1023;
  }
}

void BM_PointToTriangle(benchmark::State& s) { point_to_polygon(s, kTri, 0.0); }
void BM_PointToQuad(benchmark::State& s) { point_to_polygon(s, kQuad, 0.0); }
void BM_PointToQuadTilted(benchmark::State& s) { point_to_polygon(s, kQuad, 4.0); }
BENCHMARK(BM_PointToTriangle);
BENCHMARK(BM_PointToQuad);
BENCHMARK(BM_PointToQuadTilted);

void BM_Disk(benchmark::State& state) {
  const Points pts(0.05, 1.5, 1.0);
  const Vec3 y(0.5, 0.5, 0), ny(0, 0, 1);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(hrad::disk_ff(pts.x[i], pts.n[i], y, ny, 1.0));
    i = (i + 1) & 1023;
  }
}
BENCHMARK(BM_Disk);

// Quad receiver over the unit quad source, facing it, at varying heights; n = range(0).
void BM_QuadToQuad(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<std::array<Vec3, 4>> recv;
  for (int i = 0; i < 256; ++i) {
    const Vec3 o(U(rng), U(rng), 0.2 + U(rng));
    // Facing -z: clockwise seen from above.
    recv.push_back({o, o + Vec3(0, 0.3, 0.05), o + Vec3(0.3, 0.3, 0.1), o + Vec3(0.3, 0, 0.05)});
  }
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(hrad::polygon_to_polygon_ff(recv[i], kQuad, n));
    i = (i + 1) & 255;
  }
}
BENCHMARK(BM_QuadToQuad)->Arg(1)->Arg(2)->Arg(3)->Arg(8);

void BM_TriangleToQuad(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const std::array<Vec3, 3> recv = {Vec3(0.2, 0.2, 0.7), Vec3(0.3, 0.8, 0.8), Vec3(0.9, 0.4, 0.6)};
  for (auto _ : state) benchmark::DoNotOptimize(hrad::polygon_to_polygon_ff(recv, kQuad, n));
}
BENCHMARK(BM_TriangleToQuad)->Arg(1)->Arg(2)->Arg(3);

}  // namespace
