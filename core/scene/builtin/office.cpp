// builtin:office — an open-plan office: rows of desks (drawer pedestal, monitor,
// keyboard, mouse, tower PC, papers, mug) with swivel chairs, bookshelves full of
// books along the back wall, a door, a whiteboard and ceiling luminaires. Sized like
// the paper's OFFICE scene (5,260 polygons).
//
// | name   | type | default | meaning                                                |
// |--------|------|---------|--------------------------------------------------------|
// | desks  | int  | 19      | workstations (desk + chair), in a near-square grid     |
// | lights | int  | 12      | ceiling luminaires (1.2 x 0.3 m, exitance 60 W/m²)    |
// | seed   | int  | 1       | seed of the layout jitter (chair poses, books, clutter) |
//
// Polygons: about 5,100 by default (~200 per desk, ~225 per bookshelf, one shelf per
// desk column, ~110 for the room, 5 per luminaire); the count grows linearly with
// `desks` and `lights`.
//
// Layout (metres, y up): room [0, W] x [0, 2.8] x [0, D] with W = 2.4 + 2 * columns,
// D = 1.95 + 2.8 * rows. Desks face -z (toward the shelves on the z = 0 wall); the
// camera stands in the corner (W, D) at eye height. Walls, floor and ceiling are cut
// into ~2 m quads; everything else is boxes and prisms whose faces that touch another
// surface are left out.
#include "core/scene/builtin/shapes.h"
#include "core/scene/builtin_scenes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hrad::builtin {

namespace {

constexpr double kHeight = 2.8;
constexpr double kPitchX = 2.0, kPitchZ = 2.8;  // desk grid
constexpr double kMarginX = 1.2;                // room wall to the first desk column
constexpr double kFirstRowZ = 1.95;             // back wall to the first desk's centre
constexpr double kLightExitance = 60.0;         // W/m²

struct Palette {
  std::uint32_t wall, floor, ceiling, wood, metal, fabric, plastic, screen, paper, ceramic, housing,
      emitter, door, board;
  std::uint32_t books[6];
};

Palette make_palette(Shapes& s) {
  Palette p{};
  p.wall = s.material("wall", Rgb(0.75, 0.73, 0.68));
  p.floor = s.material("floor", Rgb(0.25, 0.28, 0.35));
  p.ceiling = s.material("ceiling", Rgb(0.8, 0.8, 0.8));
  p.wood = s.material("wood", Rgb(0.55, 0.4, 0.25));
  p.metal = s.material("metal", Rgb(0.5, 0.5, 0.52));
  p.fabric = s.material("fabric", Rgb(0.15, 0.2, 0.45));
  p.plastic = s.material("plastic", Rgb(0.12, 0.12, 0.12));
  p.screen = s.material("screen", Rgb(0.05, 0.06, 0.08));
  p.paper = s.material("paper", Rgb(0.85, 0.85, 0.82));
  p.ceramic = s.material("ceramic", Rgb(0.7, 0.2, 0.15));
  p.housing = s.material("housing", Rgb(0.8, 0.8, 0.8));
  p.emitter = s.material("emitter", Rgb::Constant(0.8), Rgb::Constant(kLightExitance));
  p.door = s.material("door", Rgb(0.45, 0.3, 0.2));
  p.board = s.material("whiteboard", Rgb(0.85, 0.85, 0.85));
  const Rgb book_colours[6] = {{0.6, 0.1, 0.1},   {0.1, 0.3, 0.6}, {0.1, 0.45, 0.2},
                               {0.75, 0.65, 0.3}, {0.3, 0.2, 0.4}, {0.8, 0.8, 0.75}};
  for (int i = 0; i < 6; ++i) p.books[i] = s.material("book" + std::to_string(i), book_colours[i]);
  return p;
}

/// A swivel chair centred on the frame's origin; the sitter faces local -z.
void add_chair(Shapes& s, const Frame& f, const Palette& p) {
  s.box(f, Vec3(-0.05, 0.06, -0.05), Vec3(0.05, 0.12, 0.05), p.metal);  // hub
  for (int k = 0; k < 5; ++k) {
    const Frame arm = f * Frame::yawed(Vec3::Zero(), 2 * std::numbers::pi * k / 5);
    s.box(arm, Vec3(0.0, 0.07, -0.02), Vec3(0.33, 0.10, 0.02), p.metal, kAllFaces & ~kXNeg);
    // Caster under the arm's end, inside the arm's footprint (its top is covered).
    s.box(arm, Vec3(0.285, 0.0, -0.018), Vec3(0.325, 0.07, 0.018), p.plastic,
          kAllFaces & ~kYNeg & ~kYPos);
  }
  s.cylinder(f, 0.025, 0.12, 0.40, 8, 1, p.metal, 0);                    // gas column
  s.box(f, Vec3(-0.24, 0.40, -0.23), Vec3(0.24, 0.48, 0.23), p.fabric);  // seat
  s.box(f, Vec3(-0.025, 0.44, 0.235), Vec3(0.025, 0.56, 0.265), p.metal, kAllFaces & ~kYPos);
  s.box(f, Vec3(-0.23, 0.56, 0.23), Vec3(0.23, 1.02, 0.29), p.fabric);  // backrest
  for (const double side : {-1.0, 1.0}) {
    const double x = side * 0.22;
    s.box(f, Vec3(x - 0.015, 0.48, -0.015), Vec3(x + 0.015, 0.68, 0.015), p.metal,
          kAllFaces & ~kYNeg & ~kYPos);
    s.box(f, Vec3(x - 0.025, 0.68, -0.15), Vec3(x + 0.025, 0.71, 0.12), p.plastic);
  }
}

/// A desk centred on the frame's origin, the user's side at local +z.
void add_desk(Shapes& s, const Frame& f, const Palette& p, Rng& rng) {
  constexpr double top = 0.74;
  s.table(f, 1.6, 0.8, top, 0.03, 0.05, 0.03, p.wood, p.metal);
  s.box(f, Vec3(-0.7, 0.3, -0.38), Vec3(0.7, top - 0.03, -0.36), p.wood, kAllFaces & ~kYPos);
  // Drawer pedestal with three drawer fronts and handles facing the user.
  s.box(f, Vec3(0.25, 0, -0.30), Vec3(0.65, 0.60, 0.33), p.wood, kNoBottom);
  for (int d = 0; d < 3; ++d) {
    const double y0 = 0.03 + 0.19 * d, y1 = y0 + 0.17, ym = 0.5 * (y0 + y1);
    s.box(f, Vec3(0.27, y0, 0.33), Vec3(0.63, y1, 0.35), p.wood, kAllFaces & ~kZNeg);
    s.box(f, Vec3(0.39, ym - 0.01, 0.35), Vec3(0.51, ym + 0.01, 0.37), p.metal, kAllFaces & ~kZNeg);
  }
  s.box(f, Vec3(-0.6, 0, -0.30), Vec3(-0.4, 0.45, 0.15), p.plastic, kNoBottom);  // tower PC
  // Monitor: base, neck (5 mm behind the panel), panel with the screen toward +z.
  s.box(f, Vec3(-0.11, top, -0.36), Vec3(0.11, top + 0.015, -0.18), p.plastic, kNoBottom);
  s.box(f, Vec3(-0.02, top + 0.015, -0.29), Vec3(0.02, 1.05, -0.255), p.plastic, kNoBottom);
  const BoxMaterials panel{p.plastic, p.plastic, p.plastic, p.plastic, p.plastic, p.screen};
  s.box(f, Vec3(-0.28, 0.86, -0.25), Vec3(0.28, 1.20, -0.21), panel);
  s.box(f, Vec3(-0.22, top, 0.05), Vec3(0.22, top + 0.025, 0.20), p.plastic, kNoBottom);
  s.box(f, Vec3(0.32, top, 0.08), Vec3(0.38, top + 0.03, 0.18), p.plastic, kNoBottom);
  if (rng.uniform(0, 1) < 0.7)
    s.box(f, Vec3(-0.70, top, -0.05), Vec3(-0.49, top + 0.01, 0.25), p.paper, kNoBottom);
  if (rng.uniform(0, 1) < 0.6) {
    const Frame mug = f * Frame::at(Vec3(0.55, 0, rng.uniform(-0.2, 0.0)));
    s.cylinder(mug, 0.04, top, top + 0.1, 8, 1, p.ceramic, kYPos);
  }
}

/// A bookshelf against the z = 0 wall, centred at x, with rows of books.
void add_bookshelf(Shapes& s, double x, const Palette& p, Rng& rng) {
  constexpr double w = 0.9, d = 0.35, h = 2.0, t = 0.02, plinth = 0.08, pitch = 0.38;
  const Frame f = Frame::at(Vec3(x, 0, 0));
  const unsigned side_faces = kAllFaces & ~kYNeg & ~kZNeg;  // on the floor, against the wall
  s.box(f, Vec3(-w / 2, 0, 0), Vec3(-w / 2 + t, h, d), p.wood, side_faces);
  s.box(f, Vec3(w / 2 - t, 0, 0), Vec3(w / 2, h, d), p.wood, side_faces);
  const double xi0 = -w / 2 + t, xi1 = w / 2 - t;  // inner width
  const unsigned board_faces = kYNeg | kYPos | kZPos;
  s.box(f, Vec3(xi0, 0, 0), Vec3(xi1, plinth, d), p.wood, kYPos | kZPos);
  s.box(f, Vec3(xi0, h - t, 0), Vec3(xi1, h, d), p.wood, board_faces);
  for (int k = 0; k <= 4; ++k) {
    const double base = plinth + k * pitch;  // the level's surface
    if (k > 0) s.box(f, Vec3(xi0, base - t, 0), Vec3(xi1, base, d), p.wood, board_faces);
    // Books stand on the level, backs against the wall, with 3 mm gaps.
    const double end = xi0 + (xi1 - xi0) * rng.uniform(0.3, 0.8);
    for (double bx = xi0 + 0.003; bx < end;) {
      const double bw = rng.uniform(0.03, 0.06);
      const double bh = rng.uniform(0.18, 0.30), bd = rng.uniform(0.20, 0.26);
      const std::uint32_t m = p.books[rng.below(6)];
      s.box(f, Vec3(bx, base, 0), Vec3(bx + bw, base + bh, bd), m, kAllFaces & ~kYNeg & ~kZNeg);
      bx += bw + 0.003;
    }
  }
}

}  // namespace

BuiltinInfo office_info() {
  return {"office",
          "open-plan office: desks with chairs and monitors, bookshelves, ceiling "
          "luminaires (~5,000 polygons, like the paper's OFFICE)",
          {{"desks", 19, 1, 2000, "workstations (desk + chair) in a near-square grid", true},
           {"lights", 12, 1, 400, "ceiling luminaires (exitance 60 W/m²)", true},
           {"seed", 1, 0, 2147483647, "seed of the layout jitter", true}}};
}

Scene make_office(const Args& args) {
  SceneBuilder builder("office", args.spec());
  Shapes s(builder, args.spec());
  const Palette p = make_palette(s);
  Rng rng(static_cast<std::uint32_t>(args.get_int("seed")));

  const int desks = args.get_int("desks");
  const int cols = static_cast<int>(std::ceil(std::sqrt(desks * 1.2)));
  const int rows = (desks + cols - 1) / cols;
  const double W = 2 * kMarginX + kPitchX * cols, D = kFirstRowZ + kPitchZ * rows;

  const BoxMaterials room{p.wall, p.wall, p.floor, p.ceiling, p.wall, p.wall};
  s.box(Frame{}, Vec3::Zero(), Vec3(W, kHeight, D), room, kAllFaces, Facing::Inward,
        Eigen::Vector3i(cells_for(W, 2), cells_for(kHeight, 2), cells_for(D, 2)));
  // Door on the x = 0 wall near the camera's end, whiteboard on the x = W wall.
  s.box(Frame{}, Vec3(0, 0, D - 2.0), Vec3(0.04, 2.1, D - 1.0), p.door,
        kAllFaces & ~kXNeg & ~kYNeg);
  s.box(Frame{}, Vec3(W - 0.02, 0.9, D / 2 - 1), Vec3(W, 2.1, D / 2 + 1), p.board,
        kAllFaces & ~kXPos);

  for (int i = 0; i < desks; ++i) {
    const double x = kMarginX + kPitchX * (i % cols + 0.5), z = kFirstRowZ + kPitchZ * (i / cols);
    add_desk(s, Frame::at(Vec3(x, 0, z)), p, rng);
    const Vec3 chair(x + rng.uniform(-0.15, 0.15), 0, z + 0.75 + rng.uniform(0, 0.15));
    add_chair(s, Frame::yawed(chair, rng.uniform(-0.35, 0.35)), p);
  }
  for (int c = 0; c < cols; ++c) add_bookshelf(s, kMarginX + kPitchX * (c + 0.5), p, rng);

  // Luminaires in a grid of about the room's aspect ratio, filled row by row.
  const int lights = args.get_int("lights");
  const int lz = std::clamp(static_cast<int>(std::lround(std::sqrt(lights * D / W))), 1, lights);
  const int lx = (lights + lz - 1) / lz;
  const double lw = std::min(1.2, 0.7 * W / lx), ld = std::min(0.3, 0.7 * D / lz);
  for (int i = 0; i < lights; ++i) {
    const Vec3 c(W * (i % lx + 0.5) / lx, kHeight, D * (i / lx + 0.5) / lz);
    s.luminaire(c, lw, 0.06, ld, p.housing, p.emitter);
  }

  Camera cam;
  cam.eye = Vec3(W - 0.6, 1.7, D - 0.6);
  cam.target = Vec3(0.35 * W, 0.9, 1.0);
  cam.up = Vec3(0, 1, 0);
  cam.fov_y_deg = 60;
  builder.set_camera(cam);
  return builder.finish(args.spec());
}

}  // namespace hrad::builtin
