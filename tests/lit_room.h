// A unit room [0, 1]^3 with its faces inward, lit by a 0.2 x 0.2 lamp 1 cm under the
// ceiling's centre (exitance 10, facing down), for tests that add objects to it.
#pragma once

#include "core/scene/scene_builder.h"

#include <cstdint>
#include <span>
#include <vector>

namespace hrad::test {

struct LitRoom {
  SceneBuilder builder{"room", "test"};
  SourceLoc at{"t", 0};
  std::uint32_t white = 0, light = 0;

  /// The room (faces 0-5: floor, ceiling, x-, x+, z-, z+ walls) and the lamp (face 6),
  /// every face of reflectance `rho`.
  explicit LitRoom(double rho) {
    Material w;
    w.name = "white";
    w.reflectance = Rgb::Constant(rho);
    Material l = w;
    l.name = "light";
    l.emission = Rgb::Constant(10);
    white = builder.add_material(w, at);
    light = builder.add_material(l, at);
    quad({0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, white);                              // floor
    quad({0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}, white);                              // ceiling
    quad({0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}, white);                              // x-
    quad({1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}, white);                              // x+
    quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, white);                              // z-
    quad({0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}, white);                              // z+
    quad({0.4, 0.99, 0.4}, {0.6, 0.99, 0.4}, {0.6, 0.99, 0.6}, {0.4, 0.99, 0.6}, light);  // lamp
  }
  /// A quad a b c d (counter-clockwise seen from its front) of material m.
  void quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, std::uint32_t m) {
    const std::vector<Vec3> q = {a, b, c, d};
    builder.add_polygon(std::span<const Vec3>(q), m, at);
  }
  Scene finish() { return builder.finish("t"); }
};

}  // namespace hrad::test
