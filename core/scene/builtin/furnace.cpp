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
// | objects  | int  | 1       | 1 = a cube and an octahedron float inside, 0 = none, |
// |          |      |         | 2 = clutter (below)                                  |
//
// Polygons: 20 by default (6 walls, 6 cube faces, 8 octahedron triangles), 6 with
// objects=0.
//
// objects=2, the cluttered furnace: 22 closed boxes in contact and apart, the hard
// cases of clustered transport in one room: boxes floating; a stack of three (each
// standing on the one below); boxes standing on the floor, hanging from the ceiling
// and pushed against a wall and into a corner (faces in contact with the room); two
// thin plates (5 mm of a 1 m room) floating and a third lying on a box; a small cube inside a 5 cm gap between two tall blocks; a row of small cubes
// touching each other. Faces in contact are kept (they still see the furnace: a
// point on them has the touching face at distance 0, so B = E / (1 - rho) holds there
// too).
//
// Closure invariant (tested): every edge of every face is shared with exactly one
// other face running the opposite way (bit-identical vertex coordinates), so the
// room and each object are watertight, consistently oriented surfaces. Objects keep a
// clearance of at least 0.14 x size from every wall and 0.05 x size from each other.
#include "core/scene/builtin/shapes.h"
#include "core/scene/builtin_scenes.h"

namespace hrad::builtin {

BuiltinInfo furnace_info() {
  return {"furnace",
          "closed room with closed objects, one material everywhere: B = E / (1 - rho)",
          {{"rho", 0.5, 0, 1, "reflectance of every face", false},
           {"emission", 1, 0, 1e6, "exitance of every face, W/m²", false},
           {"size", 1, 1e-3, 1e4, "room edge in metres", false},
           {"objects", 1, 0, 2,
            "1 = a cube and an octahedron float inside, 0 = empty, 2 = 22 boxes and plates in "
            "contact and apart",
            true}}};
}

Scene make_furnace(const Args& args) {
  SceneBuilder builder("furnace", args.spec());
  Shapes s(builder, args.spec());
  const double size = args.get("size");
  const auto m =
      s.material("furnace", Rgb::Constant(args.get("rho")), Rgb::Constant(args.get("emission")));
  const Frame world;
  s.box(world, Vec3::Zero(), Vec3::Constant(size), m, kAllFaces, Facing::Inward);

  if (args.get_int("objects") == 2) {
    // Boxes as [lo, hi] in units of the room edge.
    const auto b = [&](double x0, double y0, double z0, double x1, double y1, double z1) {
      s.box(world, Vec3(x0, y0, z0) * size, Vec3(x1, y1, z1) * size, m);
    };
    b(0.10, 0.40, 0.10, 0.22, 0.52, 0.22);    // floating
    b(0.70, 0.55, 0.15, 0.85, 0.62, 0.35);    // floating, flat
    b(0.40, 0.70, 0.60, 0.48, 0.78, 0.68);    // floating, small
    b(0.30, 0.00, 0.30, 0.50, 0.15, 0.50);    // stack on the floor ...
    b(0.33, 0.15, 0.33, 0.47, 0.27, 0.47);    // ... standing on the first
    b(0.36, 0.27, 0.36, 0.44, 0.33, 0.44);    // ... and on the second
    b(0.80, 0.00, 0.80, 1.00, 0.25, 1.00);    // in the floor's corner
    b(0.00, 0.60, 0.45, 0.08, 0.80, 0.60);    // against the x- wall
    b(0.55, 0.85, 0.55, 0.70, 1.00, 0.70);    // hanging from the ceiling
    b(0.60, 0.00, 0.05, 0.75, 0.10, 0.20);    // on the floor
    b(0.62, 0.10, 0.07, 0.73, 0.1050, 0.18);  // a 5 mm plate lying on it
    b(0.15, 0.75, 0.20, 0.35, 0.7550, 0.40);  // a floating 5 mm plate
    b(0.50, 0.30, 0.85, 0.70, 0.50, 0.8550);  // an upright floating 5 mm plate
    b(0.10, 0.00, 0.70, 0.20, 0.35, 0.80);    // two tall blocks 5 cm apart ...
    b(0.25, 0.00, 0.70, 0.35, 0.35, 0.80);
    b(0.205, 0.10, 0.73, 0.245, 0.14, 0.77);  // ... and a cube floating in the gap
    for (int i = 0; i < 4; ++i) {             // a row of cubes, each touching the next
      const double x = 0.55 + 0.06 * i;
      b(x, 0.35, 0.45, x + 0.06, 0.41, 0.51);
    }
    b(0.92, 0.40, 0.40, 1.00, 0.48, 0.48);  // touching the x+ wall
    b(0.45, 0.45, 0.00, 0.55, 0.55, 0.06);  // touching the z- wall
  } else if (args.get_int("objects") == 1) {
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
