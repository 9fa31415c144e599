#include "core/output/auto_camera.h"

#include "core/base/clock.h"
#include "core/base/hash.h"
#include "core/output/render.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/camera_spec.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace hrad {
namespace {

constexpr int kGrid = 5;         // candidates per axis
constexpr int kSphereRays = 48;  // free-space test per candidate
constexpr int kKeep = 16;        // candidates whose views are scored
constexpr int kAzimuths = 8;     // horizontal view directions
constexpr double kPitchesDeg[] = {0.0, -20.0};
constexpr int kFrustumX = 8, kFrustumY = 6;  // score rays per view (4:3, as render.png)
constexpr double kMaxBackShare = 0.25;       // of the hits; more: inside a solid
constexpr double kMinClearance = 0.005;      // of the diagonal
constexpr double kEnclosedEscape = 0.04;     // of the rays; at most this: enclosed
constexpr std::uint64_t kSeed = 0x5eed0fca3e7aULL;

/// kSphereRays unit directions spread evenly over the sphere (a Fibonacci lattice).
std::vector<Vec3> sphere_directions() {
  std::vector<Vec3> d;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < kSphereRays; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / kSphereRays, r = std::sqrt(1.0 - z * z);
    d.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return d;
}

struct Candidate {
  Vec3 eye;
  int hits = 0, back = 0, escaped = 0;
  // In scene diagonals:
  double nearest = std::numeric_limits<double>::infinity();
  double farthest = 0;  // the longest sight line that hits something
  [[nodiscard]] bool free() const {
    return hits > 0 && back <= kMaxBackShare * hits && nearest >= kMinClearance;
  }
  [[nodiscard]] double escape_share() const { return static_cast<double>(escaped) / kSphereRays; }
};

/// One of 26 directions (axes, edge and corner diagonals) nearest the unit normal n.
int orientation_class(const Vec3& n) {
  int code = 0;
  for (int c = 2; c >= 0; --c) code = 3 * code + (n[c] > 0.38 ? 2 : n[c] < -0.38 ? 0 : 1);
  return code;
}

struct View {
  Camera camera;
  double score = -1;
};

/// The view from `eye` along `dir`, and its score (rule 4 of auto_camera.h).
View score_view(const RayScene& rays, const Vec3& eye, const Vec3& dir, const Vec3& up,
                double diagonal) {
  View v;
  v.camera.eye = eye;
  v.camera.up = up;
  v.camera.fov_y_deg = kDefaultFovDeg;
  v.camera.target = eye + diagonal * dir;  // + dir alone may round to eye (huge scenes)
  double depth = 0;
  std::array<bool, 27> seen{};
  int classes = 0;
  for (int y = 0; y < kFrustumY; ++y) {
    for (int x = 0; x < kFrustumX; ++x) {
      const Vec3 d = camera_ray(v.camera, kFrustumX, kFrustumY, x + 0.5, y + 0.5).normalized();
      const auto hit = rays.intersect(eye, diagonal * d);  // t in diagonals
      if (!hit || d.dot(rays.normal(hit->prim)) >= 0) continue;
      depth += std::min(hit->t, 0.5);
      const int k = orientation_class(rays.normal(hit->prim));
      if (!seen[k]) {
        seen[k] = true;
        ++classes;
      }
    }
  }
  v.score = depth / (kFrustumX * kFrustumY) * std::min(classes, 6);
  const auto centre = rays.intersect(eye, diagonal * dir);
  v.camera.target = eye + dir * (diagonal * (centre ? centre->t : 0.5));
  return v;
}

Camera best_interior_view(const RayScene& rays, std::vector<Candidate> pool, int up_axis,
                          double diagonal) {
  std::stable_sort(pool.begin(), pool.end(),
                   [](const Candidate& a, const Candidate& b) { return a.farthest > b.farthest; });
  pool.resize(std::min<std::size_t>(pool.size(), kKeep));
  const Vec3 up = Vec3::Unit(up_axis);
  const int h1 = (up_axis + 1) % 3, h2 = (up_axis + 2) % 3;  // horizontal axes
  constexpr int kPerEye = kAzimuths * static_cast<int>(std::size(kPitchesDeg));
  std::vector<View> views(pool.size() * kPerEye);
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < static_cast<int>(views.size()); ++i) {
    const double azimuth = 2 * std::numbers::pi * (i % kAzimuths + 0.5) / kAzimuths;
    const double pitch =
        kPitchesDeg[(i / kAzimuths) % std::size(kPitchesDeg)] * std::numbers::pi / 180;
    Vec3 dir = std::sin(pitch) * up;
    dir[h1] = std::cos(pitch) * std::cos(azimuth);
    dir[h2] = std::cos(pitch) * std::sin(azimuth);
    views[i] = score_view(rays, pool[i / kPerEye].eye, dir, up, diagonal);
  }
  const auto best = std::max_element(
      views.begin(), views.end(), [](const View& a, const View& b) { return a.score < b.score; });
  return best->camera;
}

AutoCamera choose(const Scene& scene, const RayScene& rays) {
  AutoCamera out;
  const Aabb box = scene.bounds();
  if (box.empty() || !(box.diagonal() > 0)) {
    out.camera = scene.default_camera();
    out.view = "default";
    return out;
  }
  const std::uint64_t rays_before = rays.rays_cast();
  const double diagonal = box.diagonal();
  const Vec3 extent = box.extent();

  // 1. Candidates, one per grid cell, jittered within the central 70% of the cell.
  std::vector<Candidate> candidates;
  std::uint64_t draw = 0;  // the next of hashed_uniform's stream kSeed
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j)
      for (int k = 0; k < kGrid; ++k) {
        Candidate c;
        const int cell[3] = {i, j, k};
        for (int a = 0; a < 3; ++a)
          c.eye[a] = box.lo[a] +
                     extent[a] * (cell[a] + 0.15 + 0.7 * hashed_uniform(kSeed, draw++)) / kGrid;
        candidates.push_back(c);
      }

  // 2. The free-space test.
  const std::vector<Vec3> sphere = sphere_directions();
#pragma omp parallel for schedule(dynamic, 4)
  for (int n = 0; n < static_cast<int>(candidates.size()); ++n) {
    Candidate& c = candidates[n];
    for (const Vec3& d : sphere) {
      // Directions one diagonal long, whatever the scene's size (t is in diagonals).
      const auto hit = rays.intersect(c.eye, diagonal * d);
      if (!hit) {
        ++c.escaped;
        continue;
      }
      ++c.hits;
      c.back += d.dot(rays.normal(hit->prim)) >= 0;
      c.nearest = std::min(c.nearest, hit->t);
      c.farthest = std::max(c.farthest, hit->t);
    }
  }

  // 3. Which view. Free candidates with less than half their rays escaping are inside
  // something; the scene is closed when at least half of those are enclosed.
  std::vector<Candidate> inside, enclosed;
  for (const Candidate& c : candidates) {
    if (!c.free() || c.escape_share() >= 0.5) continue;
    inside.push_back(c);
    if (c.escape_share() <= kEnclosedEscape) enclosed.push_back(c);
  }
  const int up = scene.up_axis();
  if (!enclosed.empty() && 2 * enclosed.size() >= inside.size()) {
    out.camera = best_interior_view(rays, enclosed, up, diagonal);
    out.view = "interior";
  } else if (const auto side = scene.open_side_camera()) {
    out.camera = *side;
    out.view = "open side";
  } else if (!inside.empty()) {
    out.camera = best_interior_view(rays, inside, up, diagonal);
    out.view = "interior";
  } else {
    out.camera = scene.default_camera();
    out.view = "default";
  }
  out.rays = rays.rays_cast() - rays_before;
  return out;
}

}  // namespace

AutoCamera automatic_camera(const Scene& scene, const RayScene& rays) {
  if (rays.polygon_count() != scene.faces.size())
    throw std::invalid_argument(
        fmt::format("automatic_camera: the ray scene holds {} polygons, the scene {} faces",
                    rays.polygon_count(), scene.faces.size()));
  const auto start = Clock::now();
  AutoCamera out = choose(scene, rays);
  out.seconds = seconds_since(start);
  return out;
}

AutoCamera automatic_camera(const Scene& scene) {
  const auto start = Clock::now();
  AutoCamera out = automatic_camera(scene, RayScene::from_scene(scene, RayScene::Build::Fast));
  out.seconds = seconds_since(start);
  return out;
}

}  // namespace hrad
