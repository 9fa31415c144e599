// builtin:cornell — the classic Cornell box (after the published measurements of the
// Cornell Program of Computer Graphics, millimetres scaled to metres), open at the
// front; the camera looks in through the opening from z = -8 m.
//
// | name   | type | default | meaning                                                 |
// |--------|------|---------|---------------------------------------------------------|
// | light  | real | 1       | emission scale: the light's exitance is 15 x light W/m² |
// | blocks | int  | 1       | 1 = short and tall block inside, 0 = empty box          |
//
// Polygons: 16 by default (5 walls, 1 light, 2 blocks of 5 faces: their bottoms
// touch the floor and are left out), 6 with blocks=0.
//
// Layout (metres, y up): x in [0, 5.56] (x = 0 is the green right wall, x = 5.56 the
// red left wall, seen from the camera), y in [0, 5.488], z in [0, 5.592] (z = 5.592
// is the back wall; z = 0 is open). The light, 1.30 x 1.05 m, hangs 1 cm below the
// ceiling and faces down. The blocks' corners are the published ones, so they are
// rotated as in the classic box.
#include "core/scene/builtin/shapes.h"
#include "core/scene/builtin_scenes.h"

#include <array>

namespace hrad::builtin {

namespace {
constexpr double kW = 5.56, kH = 5.488, kD = 5.592;
constexpr double kLightExitance = 15.0;  // W/m² for light = 1

/// A block standing on the floor: its four floor corners (x, z) and its height.
struct Block {
  std::array<Eigen::Vector2d, 4> corners;
  double height;
};

void add_block(Shapes& s, const Block& b, std::uint32_t m) {
  std::array<Vec3, 4> bot, top;
  for (int i = 0; i < 4; ++i) {
    bot[i] = Vec3(b.corners[i].x(), 0, b.corners[i].y());
    top[i] = Vec3(b.corners[i].x(), b.height, b.corners[i].y());
  }
  // Order the corners so that the top faces up; then each side (i, i+1) faces out.
  if (vector_area(top).y() < 0) {
    std::swap(bot[1], bot[3]);
    std::swap(top[1], top[3]);
  }
  const Frame world;
  s.quad(world, top[0], top[1], top[2], top[3], m);
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    s.quad(world, bot[i], bot[j], top[j], top[i], m);
  }
}
}  // namespace

BuiltinInfo cornell_info() {
  return {"cornell",
          "the classic Cornell box (5.56 m, open front, red left / green right wall, "
          "ceiling light, two rotated blocks)",
          {{"light", 1, 0, 1e6, "emission scale: light exitance is 15 x light W/m²", false},
           {"blocks", 1, 0, 1, "1 = short and tall block inside, 0 = empty box", true}}};
}

Scene make_cornell(const Args& args) {
  SceneBuilder builder("cornell", args.spec());
  Shapes s(builder, args.spec());
  // Common RGB reflectances for the box's measured paint spectra.
  const auto white = s.material("white", Rgb(0.73, 0.73, 0.73));
  const auto red = s.material("red", Rgb(0.63, 0.065, 0.05));
  const auto green = s.material("green", Rgb(0.14, 0.45, 0.091));
  const auto light =
      s.material("light", Rgb::Constant(0.78), Rgb::Constant(kLightExitance * args.get("light")));

  // The room: a box facing inward, front face (z = 0) left open.
  const BoxMaterials walls{green, red, white, white, white, white};
  s.box(Frame{}, Vec3(0, 0, 0), Vec3(kW, kH, kD), walls, kAllFaces & ~kZNeg, Facing::Inward);

  const double y = kH - 0.01;
  s.quad(Frame{}, Vec3(2.13, y, 2.27), Vec3(3.43, y, 2.27), Vec3(3.43, y, 3.32),
         Vec3(2.13, y, 3.32), light);

  if (args.get_int("blocks") == 1) {
    const Block short_block{{{{1.30, 0.65}, {0.82, 2.25}, {2.40, 2.72}, {2.90, 1.14}}}, 1.65};
    const Block tall_block{{{{4.23, 2.47}, {2.65, 2.96}, {3.14, 4.56}, {4.72, 4.06}}}, 3.30};
    add_block(s, short_block, white);
    add_block(s, tall_block, white);
  }

  Camera cam;
  cam.eye = Vec3(2.78, 2.73, -8.0);
  cam.target = Vec3(2.78, 2.73, 0.0);
  cam.up = Vec3(0, 1, 0);
  cam.fov_y_deg = 39.3;
  builder.set_camera(cam);
  return builder.finish(args.spec());
}

}  // namespace hrad::builtin
