// A closed room whose walls are solid slabs (six boxes with outward faces), for the
// camera tests: the room is [0, 10]^3, each wall kWall = 1 thick (10% of the size), so
// the free interior is [1, 9]^3. Everything is white; a block stands on the floor and
// an emitting quad hangs under the ceiling, facing down.
#pragma once

#include <array>
#include <string>
#include <utility>

namespace hrad::test {

inline constexpr double kRoom = 10, kWall = 1;

/// The OBJ text (it names "thick.mtl") and the MTL text.
inline std::pair<std::string, std::string> thick_box_obj() {
  std::string obj = "mtllib thick.mtl\n", faces;
  int vertices = 0;
  auto box = [&](std::array<double, 3> lo, std::array<double, 3> hi, const char* material) {
    for (int i = 0; i < 8; ++i)
      obj += "v " + std::to_string(i & 1 ? hi[0] : lo[0]) + " " +
             std::to_string(i & 2 ? hi[1] : lo[1]) + " " + std::to_string(i & 4 ? hi[2] : lo[2]) +
             "\n";
    // Corners c[x + 2y + 4z]; faces x-, x+, y-, y+, z-, z+, counter-clockwise seen from
    // outside.
    constexpr int kFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    faces += std::string("usemtl ") + material + "\n";
    for (const auto& f : kFaces) {
      faces += "f";
      for (int c : f) faces += " " + std::to_string(vertices + c + 1);
      faces += "\n";
    }
    vertices += 8;
  };
  const double s = kRoom, t = kWall;
  box({0, 0, 0}, {t, s, s}, "white");
  box({s - t, 0, 0}, {s, s, s}, "white");
  box({0, 0, 0}, {s, t, s}, "white");
  box({0, s - t, 0}, {s, s, s}, "white");
  box({0, 0, 0}, {s, s, t}, "white");
  box({0, 0, s - t}, {s, s, s}, "white");
  box({4, t, 4}, {6, 3, 6}, "white");
  const double y = s - t - 0.01;
  obj += "v 4 " + std::to_string(y) + " 4\nv 6 " + std::to_string(y) + " 4\nv 6 " +
         std::to_string(y) + " 6\nv 4 " + std::to_string(y) + " 6\n";
  faces += "usemtl light\nf " + std::to_string(vertices + 1) + " " + std::to_string(vertices + 2) +
           " " + std::to_string(vertices + 3) + " " + std::to_string(vertices + 4) + "\n";
  const std::string mtl = "newmtl white\nKd 0.7 0.7 0.7\nnewmtl light\nKd 0 0 0\nKe 10 10 10\n";
  return {obj + faces, mtl};
}

}  // namespace hrad::test
