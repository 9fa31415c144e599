// builtin:cabin — an aircraft cabin after the paper's AIRCRAFT scene (184,456
// polygons): a fuselage tube with a floor, end bulkheads, overhead bins and rows of
// seats, everything tessellated into small triangles; light comes from strips under
// the bins and along the ceiling.
//
// | name          | type | default | meaning                                          |
// |---------------|------|---------|--------------------------------------------------|
// | rows          | int  | 34      | seat rows (pitch 0.82 m)                         |
// | seats_per_row | int  | 6       | seats per row, in two blocks beside the aisle    |
// | segments      | int  | 64      | fuselage segments around the arc (cylinders of   |
// |               |      |         | the seats get segments / 8, at least 6)          |
// | light         | real | 1       | strip exitance scale: 40 x light W/m²            |
//
// Triangles: about 186,000 by default: ~690 per seat (cushion, backrest, headrest,
// legs), ~84 per armrest (seats + 2 per row), 2 x segments x length / 0.3 m for the
// fuselage, plus floor, bins, strips and bulkheads (~10,000). Grows linearly with
// rows and seats_per_row.
//
// Layout (metres, y up): the cabin runs along z from 0 (front bulkhead) to
// L = 4 + 0.82 rows; the floor is y = 0; the fuselage is a circle of radius R about
// (0, 0.3 R) with R >= 2 chosen so the widest seat block fits. Seats face -z; the
// camera stands in the aisle at the rear looking forward.
#include "core/scene/builtin/shapes.h"
#include "core/scene/builtin_scenes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hrad::builtin {

namespace {

constexpr double kPitch = 0.82, kGalley = 2.0;  // row pitch, free length at each end
constexpr double kSeatW = 0.5, kAisle = 0.5;    // seat pitch across, aisle width
constexpr double kCell = 0.3;                   // tessellation along the cabin
constexpr double kStripExitance = 40.0;         // W/m² for light = 1

struct Palette {
  std::uint32_t fuselage, floor, bulkhead, bin, fabric, trim, metal, emitter;
};

struct Tube {
  double R, yc, L;
  int segments;
  /// Point of the fuselage circle at angle phi from straight down, at depth z.
  [[nodiscard]] Vec3 at(double phi, double z) const {
    return {R * std::sin(phi), yc - R * std::cos(phi), z};
  }
  [[nodiscard]] double phi0() const { return std::acos(yc / R); }  // the floor line
  /// Polygon-safe half width at height y: the circle less the tessellation's sagitta.
  [[nodiscard]] double half_width(double y) const {
    const double dphi = 2 * (std::numbers::pi - phi0()) / segments;
    return std::sqrt(R * R - (y - yc) * (y - yc)) - R * (1 - std::cos(dphi / 2));
  }
};

void add_fuselage(Shapes& s, const Tube& t, const Palette& p) {
  const Frame world;
  const int nz = cells_for(t.L, kCell);
  const double a0 = t.phi0(), a1 = 2 * std::numbers::pi - a0;
  auto arc = [&](int j, double z) { return t.at(a0 + (a1 - a0) * j / t.segments, z); };
  // i along z, j along the arc: d/dz x d/dphi points to the axis (inward).
  s.surface(
      world, nz, t.segments, [&](int i, int j) { return arc(j, t.L * i / nz); }, p.fuselage);
  const double wf = std::sqrt(t.R * t.R - t.yc * t.yc);
  s.grid(world, Vec3(-wf, 0, 0), Vec3(0, 0, t.L), Vec3(2 * wf, 0, 0), nz, cells_for(2 * wf, kCell),
         p.floor);
  // Bulkheads: rings of trapezoids around (0, yc) out to the arc and the floor chord;
  // the arc runs counter-clockwise seen from +z, so (centre, a_j, a_j+1) faces +z.
  const int rings = cells_for(t.R, kCell);
  for (const bool front : {true, false}) {
    const double z = front ? 0.0 : t.L;
    const Vec3 c(0, t.yc, z);
    for (int j = 0; j <= t.segments; ++j) {
      const Vec3 a = arc(j, z), b = j < t.segments ? arc(j + 1, z) : arc(0, z);
      auto ring = [&](const Vec3& q, int k) { return Vec3(c + (q - c) * (double(k) / rings)); };
      for (int k = 0; k < rings; ++k) {
        const Vec3 a0p = ring(a, k), b0p = ring(b, k), a1p = ring(a, k + 1), b1p = ring(b, k + 1);
        if (k == 0 && front) {
          s.tri(world, c, a1p, b1p, p.bulkhead);
        } else if (k == 0) {
          s.tri(world, c, b1p, a1p, p.bulkhead);
        } else if (front) {
          s.quad(world, a0p, a1p, b1p, b0p, p.bulkhead);
        } else {
          s.quad(world, b0p, b1p, a1p, a0p, p.bulkhead);
        }
      }
    }
  }
}

/// Overhead bins on both sides, with a light strip under each and one on the ceiling.
void add_bins_and_strips(Shapes& s, const Tube& t, const Palette& p) {
  const double yb = t.yc + 0.55 * t.R, yt = t.yc + 0.75 * t.R, xi = 0.45 * t.R;
  const double z0 = 1.5, z1 = t.L - 1.5, gap = 0.02;
  const int nz = cells_for(z1 - z0, kCell);
  const Frame world;
  for (const double side : {1.0, -1.0}) {
    std::array<Eigen::Vector2d, 4> prof = {
        Eigen::Vector2d(side * xi, yb), Eigen::Vector2d(side * (t.half_width(yb) - gap), yb),
        Eigen::Vector2d(side * (t.half_width(yt) - gap), yt), Eigen::Vector2d(side * xi, yt)};
    if (side < 0) std::reverse(prof.begin(), prof.end());  // keep it counter-clockwise
    s.prism(world, prof, z0, z1, nz, 3, p.bin);
    // Strip 1 cm under the bin's inner edge, facing down (x x z = -y).
    const double x0 = side > 0 ? xi + 0.03 : -xi - 0.23;
    s.grid(world, Vec3(x0, yb - 0.01, z0), Vec3(0.2, 0, 0), Vec3(0, 0, z1 - z0), 1, nz, p.emitter);
  }
  s.grid(world, Vec3(-0.25, t.yc + t.R - 0.12, z0), Vec3(0.5, 0, 0), Vec3(0, 0, z1 - z0), 2, nz,
         p.emitter);
}

/// A seat centred on the frame's origin on the floor; the passenger faces -z.
void add_seat(Shapes& s, const Frame& f, int cyl, const Palette& p) {
  s.box(f, Vec3(-0.22, 0.40, -0.24), Vec3(0.22, 0.52, 0.22), p.fabric, kAllFaces, Facing::Outward,
        Eigen::Vector3i(6, 2, 6));
  s.box(f, Vec3(-0.22, 0.52, 0.22), Vec3(0.22, 1.15, 0.32), p.fabric, kAllFaces, Facing::Outward,
        Eigen::Vector3i(6, 9, 2));
  s.box(f, Vec3(-0.2, 1.15, 0.23), Vec3(0.2, 1.3, 0.32), p.trim, kAllFaces & ~kYNeg,
        Facing::Outward, Eigen::Vector3i(4, 2, 1));
  for (const double x : {-0.17, 0.17})
    for (const double z : {-0.17, 0.17})
      s.cylinder(f * Frame::at(Vec3(x, 0, z)), 0.02, 0.0, 0.40, cyl, 1, p.metal, 0);
}

/// An armrest at x on a post beside the cushions.
void add_armrest(Shapes& s, const Frame& f, int cyl, const Palette& p) {
  s.cylinder(f * Frame::along(Vec3(0, 0.65, -0.2), Vec3(0, 0.65, 0.2)), 0.035, 0.0, 0.4, cyl, 3,
             p.trim);
  s.box(f, Vec3(-0.015, 0.40, -0.1), Vec3(0.015, 0.615, -0.07), p.metal, kAllFaces, Facing::Outward,
        Eigen::Vector3i(1, 2, 1));
}

}  // namespace

BuiltinInfo cabin_info() {
  return {"cabin",
          "aircraft cabin: fuselage tube, bins, rows of seats, all small triangles "
          "(~186,000, like the paper's AIRCRAFT)",
          {{"rows", 34, 1, 400, "seat rows (pitch 0.82 m)", true},
           {"seats_per_row", 6, 2, 10, "seats per row in two blocks beside the aisle", true},
           {"segments", 64, 8, 1024, "fuselage segments around the arc", true},
           {"light", 1, 0, 1e6, "strip exitance scale: 40 x light W/m²", false}}};
}

Scene make_cabin(const Args& args) {
  SceneBuilder builder("cabin", args.spec());
  Shapes s(builder, args.spec());
  s.set_triangles(true);
  Palette p{};
  p.fuselage = s.material("fuselage", Rgb(0.8, 0.8, 0.78));
  p.floor = s.material("floor", Rgb(0.2, 0.22, 0.3));
  p.bulkhead = s.material("bulkhead", Rgb(0.7, 0.68, 0.62));
  p.bin = s.material("bin", Rgb(0.85, 0.85, 0.85));
  p.fabric = s.material("fabric", Rgb(0.15, 0.18, 0.4));
  p.trim = s.material("trim", Rgb(0.3, 0.3, 0.32));
  p.metal = s.material("metal", Rgb(0.55, 0.55, 0.58));
  p.emitter =
      s.material("emitter", Rgb::Constant(0.8), Rgb::Constant(kStripExitance * args.get("light")));

  const int rows = args.get_int("rows"), n = args.get_int("seats_per_row");
  const int block[2] = {(n + 1) / 2, n / 2};  // right (x > 0), left
  const int segments = args.get_int("segments"), cyl = std::max(6, segments / 8);
  Tube t{};
  t.R = std::max(2.0, (kAisle / 2 + block[0] * kSeatW + 0.15) / 0.9);
  t.yc = 0.3 * t.R;
  t.L = 2 * kGalley + kPitch * rows;
  t.segments = segments;

  add_fuselage(s, t, p);
  add_bins_and_strips(s, t, p);
  for (int r = 0; r < rows; ++r) {
    const double z = kGalley + 0.3 + kPitch * r;
    for (int b = 0; b < 2; ++b) {
      const double side = b == 0 ? 1.0 : -1.0;
      for (int i = 0; i < block[b]; ++i)
        add_seat(s, Frame::at(Vec3(side * (kAisle / 2 + kSeatW * (i + 0.5)), 0, z)), cyl, p);
      for (int i = 0; i <= block[b] && block[b] > 0; ++i)
        add_armrest(s, Frame::at(Vec3(side * (kAisle / 2 + kSeatW * i), 0, z)), cyl, p);
    }
  }

  Camera cam;
  cam.eye = Vec3(0, 1.6, t.L - 0.8);
  cam.target = Vec3(0, 1.3, 0);
  cam.up = Vec3(0, 1, 0);
  cam.fov_y_deg = 60;
  builder.set_camera(cam);
  return builder.finish(args.spec());
}

}  // namespace hrad::builtin
