// Small scenes built in code for solver tests.
#pragma once

#include "core/scene/scene_builder.h"

namespace hrad::test {

/// A closed axis-aligned box [lo,hi] with faces looking inward, each face split
/// into n x n quads, all with reflectance rho and emission e (exitance).
inline void add_room(SceneBuilder& b, const Vec3& lo, const Vec3& hi, std::uint32_t material,
                     int n = 1, bool inward = true) {
  const SourceLoc at{"test-room", 0};
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          auto pt = [&](double a, double c) {
            Vec3 p;
            p[axis] = side ? hi[axis] : lo[axis];
            p[u] = lo[u] + (hi[u] - lo[u]) * a / n;
            p[v] = lo[v] + (hi[v] - lo[v]) * c / n;
            return p;
          };
          std::vector<Vec3> q = {pt(i, j), pt(i + 1, j), pt(i + 1, j + 1), pt(i, j + 1)};
          // (u, v) order gives a normal along +axis; the low side of an inward room
          // must face +axis, the high side -axis.
          const bool plus = (side == 0) == inward;
          if (!plus) std::swap(q[1], q[3]);
          b.add_polygon(q, material, at);
        }
      }
    }
  }
}

inline Material material(double rho, double emission) {
  Material m;
  m.name = "uniform";
  m.reflectance = Rgb::Constant(rho);
  m.emission = Rgb::Constant(emission);
  return m;
}

}  // namespace hrad::test
