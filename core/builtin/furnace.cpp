// builtin:furnace — the "white furnace" test scene: a closed cubic room (faces
// inward) holding closed objects (faces outward), every face with the same
// reflectance and the same exitance. The exact radiosity is B = E / (1 - rho) on
// every face, whatever the geometry, because every point sees a closed enclosure.
//
// | name     | type | default | meaning                                            |
// |----------|------|---------|----------------------------------------------------|
// | rho      | real | 0.5     | reflectance of every face, in [0, 1]               |
// | emission | real | 1       | exitance of every face, W/m² (>= 0)                |
// | size     | real | 1       | room edge in metres                                |
// | objects  | int  | 1       | 1 = a cube and an octahedron float inside, 0 = none |
//
// Polygons: 20 by default (6 walls, 6 cube faces, 8 octahedron triangles), 6 with
// objects=0.
//
// Closure invariant (tested): every edge of every face is shared with exactly one
// other face running the opposite way (bit-identical vertex coordinates), so the
// room and each object are watertight, consistently oriented surfaces. Objects keep a
// clearance of at least 0.14 x size from every wall and 0.05 x size from each other.
#include "core/builtin/shapes.h"
#include "core/builtin_scenes.h"

namespace hrad::builtin {

BuiltinInfo furnace_info() {
  return {"furnace",
          "closed room with closed objects, one material everywhere: B = E / (1 - rho)",
          {{"rho", 0.5, 0, 1, "reflectance of every face", false},
           {"emission", 1, 0, 1e6, "exitance of every face, W/m²", false},
           {"size", 1, 1e-3, 1e4, "room edge in metres", false},
           {"objects", 1, 0, 1, "1 = a cube and an octahedron float inside, 0 = empty", true}}};
}

Scene make_furnace(const Args& args) {
  SceneBuilder builder("furnace", args.spec());
  Shapes s(builder, args.spec());
  const double size = args.get("size");
  const auto m = s.material("furnace", Rgb::Constant(args.get("rho")),
                            Rgb::Constant(args.get("emission")));
  const Frame world;
  s.box(world, Vec3::Zero(), Vec3::Constant(size), m, kAllFaces, Facing::Inward);

  if (args.get_int("objects") == 1) {
    s.box(world, Vec3::Constant(0.2 * size), Vec3::Constant(0.45 * size), m);
    // Octahedron |x - c|_1 <= r: spans [0.5, 0.86] x [0.44, 0.8] x [0.44, 0.8] * size,
    // clear of the cube ([0.2, 0.45]^3) and of the walls.
    const Vec3 c = Vec3(0.68, 0.62, 0.62) * size;
    const double r = 0.18 * size;
    for (int sx = -1; sx <= 1; sx += 2)
      for (int sy = -1; sy <= 1; sy += 2)
        for (int sz = -1; sz <= 1; sz += 2) {
          const Vec3 a = c + Vec3(sx * r, 0, 0), b = c + Vec3(0, sy * r, 0),
                     d = c + Vec3(0, 0, sz * r);
          // (a, b, d) faces away from c when the octant has an even number of
          // negative signs; otherwise reverse it.
          if (sx * sy * sz > 0)
            s.tri(world, a, b, d, m);
          else
            s.tri(world, a, d, b, m);
        }
  }

  Camera cam;
  cam.eye = Vec3(0.5, 0.5, 0.95) * size;
  cam.target = Vec3(0.5, 0.45, 0.0) * size;
  cam.up = Vec3(0, 1, 0);
  cam.fov_y_deg = 70;
  builder.set_camera(cam);
  return builder.finish(args.spec());
}

}  // namespace hrad::builtin
