#include "core/scene/back_faces.h"

#include "core/base/interrupt.h"
#include "core/scene/polygon_key.h"

#include <fmt/format.h>

#include <stdexcept>
#include <unordered_set>

namespace hrad {

void add_back_faces(Scene& scene, Sides mode, EmitterSides emitters) {
  scene.sides = enum_name(mode);
  scene.emitter_sides = enum_name(emitters);
  scene.back_faces = 0;
  scene.dark_back_faces = 0;
  scene.back_faces_present = 0;
  if (mode == Sides::One) return;
  const std::size_t n = scene.faces.size();
  auto wanted = [&](std::size_t f) {
    return mode == Sides::Two || scene.face_material(f).two_sided;
  };
  bool any = false;
  for (std::size_t f = 0; f < n && !any; ++f) any = wanted(f);
  if (!any) return;
  // The scene's cycles, to find faces whose back is already there.
  std::unordered_set<std::vector<double>, PositionsHash> cycles;
  cycles.reserve(n);
  for (std::size_t f = 0; f < n; ++f) {
    poll_interrupt(f);  // a million faces take seconds here and below
    cycles.insert(cycle_key(scene.face_vertices(f)));
  }
  // Per material, the material of its back faces: itself, or (an emitter, with
  // emitters = front) a copy without emission, made when first needed.
  std::vector<std::uint32_t> back_material(scene.materials.size());
  for (std::size_t m = 0; m < back_material.size(); ++m)
    back_material[m] = static_cast<std::uint32_t>(m);
  const auto back_of = [&](std::uint32_t m) {
    if (emitters == EmitterSides::Both || !scene.materials[m].emits()) return m;
    if (back_material[m] == m) {  // its dark copy is not made yet
      Material dark = scene.materials[m];
      dark.name += " (back)";
      dark.emission = Rgb::Zero();
      back_material[m] = static_cast<std::uint32_t>(scene.materials.size());
      scene.materials.push_back(std::move(dark));
    }
    return back_material[m];
  };
  for (std::size_t f = 0; f < n; ++f) {
    poll_interrupt(f);
    if (!wanted(f)) continue;
    if (cycles.count(cycle_key(scene.face_vertices(f), /*reversed=*/true))) {
      ++scene.back_faces_present;
      continue;
    }
    const Face front = scene.faces[f];
    Face back = front;
    back.material = back_of(front.material);
    if (back.material != front.material) ++scene.dark_back_faces;
    back.first = static_cast<std::uint32_t>(scene.indices.size());
    scene.indices.push_back(scene.indices[front.first]);
    for (std::uint32_t k = front.count - 1; k >= 1; --k)
      scene.indices.push_back(scene.indices[front.first + k]);
    scene.faces.push_back(back);
    ++scene.back_faces;
  }
  if (scene.dark_back_faces > 0)
    scene.warnings.push_back(fmt::format(
        "{} two-sided emitter face(s) emit from the front only (emitter_sides = front, as "
        "RenderPark and Radiance read MGF); --emitter-sides both makes their back faces emit "
        "too",
        scene.dark_back_faces));
}

}  // namespace hrad
