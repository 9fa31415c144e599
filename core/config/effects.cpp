#include "core/config/effects.h"

#include "core/base/interrupt.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace hrad {

namespace {

bool grey(const Rgb& c) { return c[0] == c[1] && c[1] == c[2]; }

/// Materials actually used by some face, in first-use order (unused materials in
/// a file decide nothing).
std::vector<const Material*> used_materials(const Scene& scene) {
  std::vector<char> seen(scene.materials.size(), 0);
  std::vector<const Material*> out;
  for (const Face& f : scene.faces) {
    if (seen[f.material]) continue;
    seen[f.material] = 1;
    out.push_back(&scene.materials[f.material]);
  }
  return out;
}

const char* kForced = "effects = all: computed whatever the scene";

}  // namespace

bool is_convex_enclosure(const Scene& scene, std::string* why) {
  // Vertices referenced by faces (an unreferenced vertex blocks nothing).
  std::vector<std::uint32_t> used(scene.indices.begin(), scene.indices.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  const double tol = kConvexTolerance * scene.bounds().diagonal();
  // Probes: the vertices extreme along 13 axes (and their opposites). The vertex
  // farthest behind a face's plane is the extreme one along -normal, so in most
  // scenes that are not convex some probe lies behind some face, and the full
  // O(faces x vertices) pass below runs only for scenes that look convex.
  std::vector<std::uint32_t> probes;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c) {
        if (a == 0 && b == 0 && c == 0) continue;
        const Vec3 d(a, b, c);
        const auto best = std::max_element(used.begin(), used.end(), [&](auto x, auto y) {
          return d.dot(scene.vertices[x]) < d.dot(scene.vertices[y]);
        });
        if (best != used.end()) probes.push_back(*best);
      }
  std::sort(probes.begin(), probes.end());
  probes.erase(std::unique(probes.begin(), probes.end()), probes.end());
  // Beyond this many vertex-plane tests the scene is not proved convex (it keeps
  // visibility on, which is always exact): a convex enclosure that large is rare.
  constexpr double kBudget = 2e8;
  const bool full_pass =
      static_cast<double>(scene.faces.size()) * static_cast<double>(used.size()) <= kBudget;

  std::vector<std::uint32_t> own;
  for (const std::vector<std::uint32_t>* candidates : {&probes, &used}) {
    if (candidates == &used && !full_pass) {
      if (why)
        *why = fmt::format(
            "no polygon found in front of another by a quick test, and {} "
            "polygons x {} vertices is too many to prove the scene convex",
            scene.faces.size(), used.size());
      return false;
    }
    for (std::size_t f = 0; f < scene.faces.size(); ++f) {
      poll_interrupt(f, 256);  // up to 2e8 tests in all
      const Face& face = scene.faces[f];
      const Vec3 n = scene.face_normal(f);
      // The plane through the centroid: faces may be planar only to 1e-3 of their
      // size, and their own vertices are skipped below.
      Vec3 c = Vec3::Zero();
      own.assign(scene.indices.begin() + face.first,
                 scene.indices.begin() + face.first + face.count);
      for (std::uint32_t v : own) c += scene.vertices[v];
      c /= static_cast<double>(face.count);
      for (std::uint32_t v : *candidates) {
        if (n.dot(scene.vertices[v] - c) >= -tol) continue;
        if (std::find(own.begin(), own.end(), v) != own.end()) continue;
        if (why)
          *why = fmt::format(
              "vertex {} lies behind the plane of polygon {}: polygons may block "
              "each other",
              v, f);
        return false;
      }
    }
  }
  return true;
}

Effects analyse_effects(const Scene& scene, const SolverOptions& options) {
  const bool all = options.effects == EffectsMode::All;
  const std::vector<const Material*> mats = used_materials(scene);
  Effects e;

  const auto reflecting = std::find_if(
      mats.begin(), mats.end(), [](const Material* m) { return (m->reflectance > 0).any(); });
  const bool black = reflecting == mats.end();
  if (options.visibility_rays == 0) {
    e.visibility = {false, "visibility_rays = 0: every pair counts as unblocked"};
  } else if (all) {
    e.visibility = {true, kForced};
  } else if (black) {
    e.visibility = {false,
                    "every reflectance is 0: visibility only weights light that a receiver "
                    "would reflect, so links carry V = 1 without rays"};
  } else if (std::string why; is_convex_enclosure(scene, &why)) {
    e.visibility = {false,
                    "the scene is one convex enclosure (every polygon's plane has all vertices "
                    "on or in front of it): nothing can block a segment between two points "
                    "that see each other, so V = 1 without rays"};
  } else {
    e.visibility = {true, why};
  }

  if (all) {
    e.interreflection = {true, kForced};
  } else if (black) {
    e.interreflection = {false,
                         "every reflectance is 0: nothing is reflected, so one gather sweep per "
                         "iteration gives B = E exactly"};
  } else {
    e.interreflection = {
        true, fmt::format("material '{}' reflects (largest channel {})", (*reflecting)->name,
                          (*reflecting)->reflectance.maxCoeff())};
  }

  const auto coloured = std::find_if(mats.begin(), mats.end(), [](const Material* m) {
    return !grey(m->reflectance) || !grey(m->emission);
  });
  if (all) {
    e.colour = {true, kForced};
  } else if (coloured == mats.end()) {
    e.colour = {false,
                "every reflectance and emission is grey (equal channels): one channel is "
                "gathered and copied to the other two"};
  } else {
    e.colour = {true, fmt::format("material '{}' is not grey", (*coloured)->name)};
  }

  const std::size_t emitters = scene.emitter_count();
  if (all) {
    e.emission = {true, kForced};
  } else if (emitters == 0) {
    e.emission = {false,
                  "scene has no emitter: no polygon emits light, so the solution is zero and "
                  "nothing is refined or propagated"};
  } else {
    e.emission = {true, fmt::format("{} emitting polygon{}", emitters, emitters == 1 ? "" : "s")};
  }

  e.iterations = {true, all ? kForced : "every iteration asked for ran"};
  return e;
}

}  // namespace hrad
