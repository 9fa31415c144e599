#include "core/scene/back_faces.h"

#include "core/scene/polygon_key.h"

#include <fmt/format.h>

#include <stdexcept>
#include <unordered_set>

namespace hrad {

void add_back_faces(Scene& scene, Sides mode) {
  scene.sides = enum_name(mode);
  scene.back_faces = 0;
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
  for (std::size_t f = 0; f < n; ++f) cycles.insert(cycle_key(scene.face_vertices(f)));
  for (std::size_t f = 0; f < n; ++f) {
    if (!wanted(f)) continue;
    if (cycles.count(cycle_key(scene.face_vertices(f), /*reversed=*/true))) {
      ++scene.back_faces_present;
      continue;
    }
    const Face front = scene.faces[f];
    Face back = front;
    back.first = static_cast<std::uint32_t>(scene.indices.size());
    scene.indices.push_back(scene.indices[front.first]);
    for (std::uint32_t k = front.count - 1; k >= 1; --k)
      scene.indices.push_back(scene.indices[front.first + k]);
    scene.faces.push_back(back);
    ++scene.back_faces;
  }
}

}  // namespace hrad
