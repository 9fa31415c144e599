// A polygon soup built up in tests: vertices, indices and ranges as RayScene and the
// face tables (core/raycast/face_twins.h, core/raycast/face_contacts.h) take them.
#pragma once

#include "core/raycast/ray_scene.h"

#include <cstdint>
#include <initializer_list>
#include <span>
#include <vector>

namespace hrad::test {

struct Soup {
  std::vector<Vec3> vertices;
  std::vector<std::uint32_t> indices;
  std::vector<PolygonRange> polys;

  /// Appends a polygon with its own copies of `corners`; returns its index.
  std::uint32_t add(std::span<const Vec3> corners) {
    PolygonRange r{static_cast<std::uint32_t>(indices.size()),
                   static_cast<std::uint32_t>(corners.size())};
    for (const Vec3& c : corners) {
      indices.push_back(static_cast<std::uint32_t>(vertices.size()));
      vertices.push_back(c);
    }
    polys.push_back(r);
    return static_cast<std::uint32_t>(polys.size() - 1);
  }
  std::uint32_t add(std::initializer_list<Vec3> corners) {
    return add(std::span<const Vec3>(corners.begin(), corners.size()));
  }
  /// The same soup under p -> s * p + shift.
  [[nodiscard]] Soup transformed(double s, const Vec3& shift) const {
    Soup t = *this;
    for (Vec3& v : t.vertices) v = s * v + shift;
    return t;
  }
  [[nodiscard]] RayScene build() const { return RayScene(vertices, indices, polys); }
};

}  // namespace hrad::test
