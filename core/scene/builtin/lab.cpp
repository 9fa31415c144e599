// builtin:lab — a two-floor computer lab after the paper's VRLAB (30,449 polygons):
// a ground floor and an upper floor on a concrete slab with a stair void, mostly
// overhead lighting, large walls and slabs beside many tiny patches (keyboards with
// individual keys, desktop computers with drive bays and LEDs, CRT monitors, chairs
// with spherical casters, server racks).
//
// | name         | type | default | meaning                                           |
// |--------------|------|---------|---------------------------------------------------|
// | workstations | int  | 41      | desks with computer and chair, split over floors  |
// | lights       | int  | 24      | luminaires (exitance 80 W/m²), half per floor     |
// | seed         | int  | 1       | seed of the layout jitter (chair poses)           |
//
// Polygons: about 30,000 by default (~700 per workstation, of which 330 are keyboard
// keys; ~155 per rack, one rack per 8 workstations; ~450 for room, slab, stair and
// railing; 5 per luminaire); the count grows linearly with the parameters.
//
// Layout (metres, y up): footprint [0, W] x [0, D]; ground floor y in [0, 3.2], slab
// y in [3.2, 3.5], upper floor y in [3.5, 6.5]. The slab has a 1.6 x 6 m void at
// x in [vx0, vx0 + 1.6], z in [2, 8] holding an open-riser stair that climbs toward
// +z; a railing guards its three other edges on the upper floor. Workstations fill
// x < vx0 - 0.5 on both floors and face the racks along the z = 0 wall. Walls, floor,
// roof and slab are cut into ~3 m quads. The camera stands on the ground floor in the
// corner (W, D).
#include "core/scene/builtin/shapes.h"
#include "core/scene/builtin_scenes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hrad::builtin {

namespace {

constexpr double kGround = 3.2, kSlabTop = 3.5, kRoof = 6.5;  // heights
constexpr double kPitchX = 2.2, kPitchZ = 2.6;                // workstation grid
constexpr double kAreaX = 1.5, kAreaZ = 2.0;                  // where the grid starts (x, z)
constexpr double kVoidW = 1.6, kVoidZ0 = 2.0, kVoidZ1 = 8.0;
constexpr double kLightExitance = 80.0;  // W/m²
constexpr double kCell = 3.0;            // room subdivision

struct Palette {
  std::uint32_t wall, floor, ceiling, concrete, desk, metal, beige, dark, screen, key, fabric, led,
      rack, housing, emitter, projection;
};

Palette make_palette(Shapes& s) {
  Palette p{};
  p.wall = s.material("wall", Rgb(0.7, 0.7, 0.68));
  p.floor = s.material("floor", Rgb(0.3, 0.3, 0.32));
  p.ceiling = s.material("ceiling", Rgb(0.75, 0.75, 0.75));
  p.concrete = s.material("concrete", Rgb(0.5, 0.5, 0.48));
  p.desk = s.material("desk", Rgb(0.6, 0.6, 0.55));
  p.metal = s.material("metal", Rgb(0.45, 0.45, 0.5));
  p.beige = s.material("beige plastic", Rgb(0.72, 0.68, 0.58));
  p.dark = s.material("dark plastic", Rgb(0.1, 0.1, 0.1));
  p.screen = s.material("screen", Rgb(0.05, 0.07, 0.07));
  p.key = s.material("key", Rgb(0.8, 0.78, 0.7));
  p.fabric = s.material("fabric", Rgb(0.45, 0.1, 0.1));
  p.led = s.material("led", Rgb(0.2, 0.7, 0.2));
  p.rack = s.material("rack", Rgb(0.15, 0.15, 0.18));
  p.housing = s.material("housing", Rgb(0.8, 0.8, 0.8));
  p.emitter = s.material("emitter", Rgb::Constant(0.8), Rgb::Constant(kLightExitance));
  p.projection = s.material("projection screen", Rgb(0.85, 0.85, 0.85));
  return p;
}

constexpr unsigned kNoBack = kAllFaces & ~kZNeg;  // for parts stuck on a +z-facing front

/// Swivel chair with spherical casters, centred on the frame; the sitter faces -z.
void add_chair(Shapes& s, const Frame& f, const Palette& p) {
  s.box(f, Vec3(-0.05, 0.06, -0.05), Vec3(0.05, 0.12, 0.05), p.metal);
  for (int k = 0; k < 5; ++k) {
    const Frame arm = f * Frame::yawed(Vec3::Zero(), 2 * std::numbers::pi * k / 5);
    s.box(arm, Vec3(0.0, 0.065, -0.02), Vec3(0.33, 0.095, 0.02), p.metal, kAllFaces & ~kXNeg);
    s.sphere(arm, Vec3(0.3, 0.03, 0), 0.03, 8, 4, p.dark);
  }
  s.cylinder(f, 0.025, 0.12, 0.40, 8, 1, p.metal, 0);
  s.box(f, Vec3(-0.24, 0.40, -0.23), Vec3(0.24, 0.48, 0.23), p.fabric, kAllFaces, Facing::Outward,
        Eigen::Vector3i(3, 1, 3));
  s.box(f, Vec3(-0.025, 0.44, 0.235), Vec3(0.025, 0.56, 0.265), p.metal, kAllFaces & ~kYPos);
  s.box(f, Vec3(-0.23, 0.56, 0.23), Vec3(0.23, 1.0, 0.29), p.fabric, kAllFaces, Facing::Outward,
        Eigen::Vector3i(3, 3, 1));
  for (const double side : {-1.0, 1.0}) {
    const double x = side * 0.22;
    s.box(f, Vec3(x - 0.015, 0.48, -0.015), Vec3(x + 0.015, 0.68, 0.015), p.metal,
          kAllFaces & ~kYNeg & ~kYPos);
    s.box(f, Vec3(x - 0.025, 0.68, -0.15), Vec3(x + 0.025, 0.71, 0.12), p.dark);
  }
}

/// Keyboard on a surface at height y, centred at (0, zc): a base and 65 keys.
void add_keyboard(Shapes& s, const Frame& f, double y, double zc, const Palette& p) {
  constexpr double pitch = 0.019, key = 0.016, x0 = -(13 * pitch + key) / 2;  // 14 columns
  s.box(f, Vec3(-0.16, y, zc - 0.085), Vec3(0.16, y + 0.03, zc + 0.085), p.beige, kNoBottom);
  const double ky = y + 0.03;
  auto key_at = [&](double xa, double xb, int row) {
    const double z = zc - 0.07 + row * pitch;
    s.box(f, Vec3(xa, ky, z), Vec3(xb, ky + 0.015, z + key), p.key, kNoBottom);
  };
  for (int row = 0; row < 4; ++row)
    for (int c = 0; c < 14; ++c) key_at(x0 + c * pitch, x0 + c * pitch + key, row);
  // Bottom row: four keys, the space bar, four keys.
  for (int c = 0; c < 14; ++c) {
    if (c == 4) key_at(x0 + 4 * pitch, x0 + 9 * pitch + key, 4);
    if (c >= 4 && c <= 9) continue;
    key_at(x0 + c * pitch, x0 + c * pitch + key, 4);
  }
}

/// Desk with a desktop computer, CRT monitor, keyboard and mouse; user side +z.
void add_workstation(Shapes& s, const Frame& f, const Palette& p) {
  constexpr double top = 0.72;
  s.table(f, 1.4, 0.75, top, 0.03, 0.04, 0.03, p.desk, p.metal);
  // Desktop case with drive bays, a power button and two LEDs on its front (z = 0.05).
  constexpr double case_top = top + 0.12;
  s.box(f, Vec3(-0.21, top, -0.35), Vec3(0.21, case_top, 0.05), p.beige, kNoBottom);
  for (int b = 0; b < 2; ++b) {
    const double y0 = top + 0.03 + 0.04 * b;
    s.box(f, Vec3(0.02, y0, 0.05), Vec3(0.17, y0 + 0.03, 0.055), p.beige, kNoBack);
  }
  s.box(f, Vec3(-0.17, top + 0.05, 0.05), Vec3(-0.15, top + 0.07, 0.06), p.dark, kNoBack);
  for (int l = 0; l < 2; ++l) {
    const double x0 = -0.12 + 0.02 * l;
    s.box(f, Vec3(x0, top + 0.055, 0.05), Vec3(x0 + 0.01, top + 0.065, 0.055), p.led, kNoBack);
  }
  // CRT: foot, bezel (screen toward +z), tapered tube behind, three buttons.
  s.box(f, Vec3(-0.1, case_top, -0.25), Vec3(0.1, case_top + 0.03, -0.05), p.beige, kNoBottom);
  const double y0 = case_top + 0.03, y1 = y0 + 0.36;
  const BoxMaterials bezel{p.beige, p.beige, p.beige, p.beige, p.beige, p.screen};
  s.box(f, Vec3(-0.2, y0, -0.05), Vec3(0.2, y1, 0.03), bezel);
  std::array<Vec3, 8> tube;
  for (int i = 0; i < 8; ++i) {
    const bool hx = i & 1, hy = i & 2, back = i & 4;  // back = low z
    const double hw = back ? 0.1 : 0.17, yl = back ? y0 + 0.08 : y0 + 0.02,
                 yh = back ? y1 - 0.08 : y1 - 0.02;
    tube[i] = Vec3(hx ? hw : -hw, hy ? yh : yl, back ? -0.35 : -0.05);
  }
  // Corner bit 2 must mean "high z": swap the halves so that index bit 4 = front.
  std::array<Vec3, 8> hex;
  for (int i = 0; i < 8; ++i) hex[i] = tube[i ^ 4];
  s.hexahedron(f, hex, p.beige, kAllFaces & ~kZPos);
  for (int b = 0; b < 3; ++b) {
    const double x0 = 0.08 + 0.03 * b;
    s.box(f, Vec3(x0, y0 + 0.005, 0.03), Vec3(x0 + 0.02, y0 + 0.015, 0.04), p.dark, kNoBack);
  }
  add_keyboard(s, f, top, 0.2, p);
  s.box(f, Vec3(0.28, top, 0.05), Vec3(0.48, top + 0.003, 0.25), p.dark, kNoBottom);
  s.box(f, Vec3(0.35, top + 0.003, 0.1), Vec3(0.41, top + 0.03, 0.2), p.beige, kNoBottom);
}

/// A server rack against the z = 0 wall at (x, y): ten units with two LEDs each.
void add_rack(Shapes& s, double x, double y, const Palette& p) {
  const Frame f = Frame::at(Vec3(x, y, 0));
  s.box(f, Vec3(-0.3, 0, 0), Vec3(0.3, 2.0, 1.0), p.rack, kAllFaces & ~kYNeg & ~kZNeg);
  for (int u = 0; u < 10; ++u) {
    const double y0 = 0.1 + 0.18 * u;
    s.box(f, Vec3(-0.28, y0, 1.0), Vec3(0.28, y0 + 0.16, 1.02), p.dark, kNoBack);
    for (int l = 0; l < 2; ++l) {
      const double lx = 0.2 + 0.03 * l;
      s.box(f, Vec3(lx, y0 + 0.07, 1.02), Vec3(lx + 0.01, y0 + 0.08, 1.03), p.led, kNoBack);
    }
  }
}

/// Slab between the floors, with the void [vx0, vx1] x [kVoidZ0, kVoidZ1].
void add_slab(Shapes& s, double W, double D, double vx0, double vx1, const Palette& p) {
  const double xs[4] = {0, vx0, vx1, W}, zs[4] = {0, kVoidZ0, kVoidZ1, D};
  const Frame world;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (i == 1 && j == 1) continue;  // the void
      const double dx = xs[i + 1] - xs[i], dz = zs[j + 1] - zs[j];
      const int nx = cells_for(dx, kCell), nz = cells_for(dz, kCell);
      // Top faces up (z x x = +y), bottom faces down (x x z = -y).
      s.grid(world, Vec3(xs[i], kSlabTop, zs[j]), Vec3(0, 0, dz), Vec3(dx, 0, 0), nz, nx, p.floor);
      s.grid(world, Vec3(xs[i], kGround, zs[j]), Vec3(dx, 0, 0), Vec3(0, 0, dz), nx, nz, p.ceiling);
    }
  // The void's four edges, facing into the void.
  const Vec3 up(0, kSlabTop - kGround, 0), along_z(0, 0, kVoidZ1 - kVoidZ0),
      along_x(vx1 - vx0, 0, 0);
  s.quad(world, Vec3(vx0, kGround, kVoidZ0), Vec3(vx0, kGround, kVoidZ0) + up,
         Vec3(vx0, kGround, kVoidZ0) + up + along_z, Vec3(vx0, kGround, kVoidZ0) + along_z,
         p.concrete);
  s.grid(world, Vec3(vx1, kGround, kVoidZ0), along_z, up, 1, 1, p.concrete);
  s.grid(world, Vec3(vx0, kGround, kVoidZ0), along_x, up, 1, 1, p.concrete);
  s.grid(world, Vec3(vx0, kGround, kVoidZ1), up, along_x, 1, 1, p.concrete);
}

/// Open-riser stair in the void, climbing toward +z, and the railing around the void.
void add_stair(Shapes& s, double vx0, double vx1, const Palette& p) {
  constexpr int kSteps = 18;
  const double rise = kSlabTop / kSteps;
  const double run = (kVoidZ1 - kVoidZ0 - 0.05) / (kSteps - 1);  // last tread clears the slab
  for (int k = 1; k < kSteps; ++k)
    s.box(Frame{}, Vec3(vx0 + 0.1, k * rise - 0.04, kVoidZ0 + (k - 1) * run),
          Vec3(vx1 - 0.1, k * rise, kVoidZ0 + k * run), p.desk);
  // Railing on the slab: posts every ~1 m, a top rail, along x = vx0, x = vx1, z = z0.
  constexpr double h = 1.0, rail = 0.05, inset = 0.04, post = 0.04;
  const double y0 = kSlabTop, y1 = kSlabTop + h;
  const unsigned post_faces = kAllFaces & ~kYNeg & ~kYPos;
  s.box(Frame{}, Vec3(vx0 - inset - 0.06, y1, kVoidZ0 - inset - 0.06),
        Vec3(vx1 + inset + 0.06, y1 + rail, kVoidZ0 - inset), p.metal);
  for (const double side : {-1.0, 1.0}) {
    const double xe = side < 0 ? vx0 - inset - 0.06 : vx1 + inset;  // rail's low x
    s.box(Frame{}, Vec3(xe, y1, kVoidZ0 - inset), Vec3(xe + 0.06, y1 + rail, kVoidZ1), p.metal,
          kAllFaces & ~kZNeg);
    const int n = cells_for(kVoidZ1 - kVoidZ0, 1.0);
    for (int i = 0; i <= n; ++i) {
      const double z = kVoidZ0 + (kVoidZ1 - kVoidZ0 - post) * i / n, x = xe + 0.01;
      s.box(Frame{}, Vec3(x, y0, z), Vec3(x + post, y1, z + post), p.metal, post_faces);
    }
  }
  const int n = cells_for(vx1 - vx0, 1.0);
  for (int i = 0; i <= n; ++i) {
    const double x = vx0 + (vx1 - vx0 - post) * i / n, z = kVoidZ0 - inset - 0.05;
    s.box(Frame{}, Vec3(x, y0, z), Vec3(x + post, y1, z + post), p.metal, post_faces);
  }
}

void add_lights(Shapes& s, int n, double x1, double D, double ceiling, const Palette& p) {
  if (n <= 0) return;
  const int lz = std::clamp(static_cast<int>(std::lround(std::sqrt(n * D / x1))), 1, n);
  const int lx = (n + lz - 1) / lz;
  const double lw = std::min(1.2, 0.7 * x1 / lx), ld = std::min(0.3, 0.7 * D / lz);
  for (int i = 0; i < n; ++i) {
    const Vec3 c(x1 * (i % lx + 0.5) / lx, ceiling, D * (i / lx + 0.5) / lz);
    s.luminaire(c, lw, 0.08, ld, p.housing, p.emitter);
  }
}

}  // namespace

BuiltinInfo lab_info() {
  return {
      "lab",
      "two-floor computer lab with a stair void, overhead lights, many tiny patches "
      "(~30,000 polygons, like the paper's VRLAB)",
      {{"workstations", 41, 1, 2000, "desks with computer and chair, split over 2 floors", true},
       {"lights", 24, 2, 800, "luminaires (exitance 80 W/m²), half per floor", true},
       {"seed", 1, 0, 2147483647, "seed of the layout jitter", true}}};
}

Scene make_lab(const Args& args) {
  SceneBuilder builder("lab", args.spec());
  Shapes s(builder, args.spec());
  const Palette p = make_palette(s);
  Rng rng(static_cast<std::uint32_t>(args.get_int("seed")));

  const int ws = args.get_int("workstations");
  const int per_floor[2] = {(ws + 1) / 2, ws / 2};
  const int cols = static_cast<int>(std::ceil(std::sqrt(per_floor[0] * 1.3)));
  const int rows = (per_floor[0] + cols - 1) / cols;
  const double vx0 = kAreaX + kPitchX * cols + 0.5, vx1 = vx0 + kVoidW;
  const double W = vx1 + 1.5, D = std::max(kAreaZ + kPitchZ * rows + 1.0, kVoidZ1 + 1.5);

  // Ground-floor walls and floor; upper-floor walls and roof; the slab in between.
  const BoxMaterials room{p.wall, p.wall, p.floor, p.ceiling, p.wall, p.wall};
  const int nx = cells_for(W, kCell), nz = cells_for(D, kCell);
  s.box(Frame{}, Vec3::Zero(), Vec3(W, kGround, D), room, kAllFaces & ~kYPos, Facing::Inward,
        Eigen::Vector3i(nx, 1, nz));
  s.box(Frame{}, Vec3(0, kSlabTop, 0), Vec3(W, kRoof, D), room, kAllFaces & ~kYNeg, Facing::Inward,
        Eigen::Vector3i(nx, 1, nz));
  add_slab(s, W, D, vx0, vx1, p);
  add_stair(s, vx0, vx1, p);
  s.box(Frame{}, Vec3(1.5, 0.8, D - 0.05), Vec3(5.5, 3.0, D), p.projection, kAllFaces & ~kZPos);

  const int racks = (ws + 7) / 8;
  for (int r = 0; r < racks; ++r) {
    const int floor = r % 2, i = r / 2;
    add_rack(s, 1.0 + 0.8 * i, floor == 0 ? 0.0 : kSlabTop, p);
  }
  for (int floor = 0; floor < 2; ++floor) {
    const double y = floor == 0 ? 0.0 : kSlabTop;
    for (int i = 0; i < per_floor[floor]; ++i) {
      const double x = kAreaX + kPitchX * (i % cols + 0.5);
      const double z = kAreaZ + 0.375 + kPitchZ * (i / cols);
      add_workstation(s, Frame::at(Vec3(x, y, z)), p);
      const Vec3 chair(x + rng.uniform(-0.15, 0.15), y, z + 0.75 + rng.uniform(0, 0.15));
      add_chair(s, Frame::yawed(chair, rng.uniform(-0.35, 0.35)), p);
    }
  }
  const int lights = args.get_int("lights");
  add_lights(s, (lights + 1) / 2, vx0 - 0.3, D, kGround, p);  // under the slab, not the void
  add_lights(s, lights / 2, W, D, kRoof, p);

  Camera cam;
  cam.eye = Vec3(W - 0.7, 1.7, D - 0.7);
  cam.target = Vec3(0.4 * W, 2.0, 1.0);
  cam.up = Vec3(0, 1, 0);
  cam.fov_y_deg = 65;
  builder.set_camera(cam);
  return builder.finish(args.spec());
}

}  // namespace hrad::builtin
