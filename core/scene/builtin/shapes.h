// Shape helpers for the procedural scenes: boxes, grids, cylinders, spheres and
// prisms emitted as quads (planar, convex) or triangles into a SceneBuilder.
//
// Orientation invariant: every helper emits polygons whose normal (Newell, right-hand
// rule over the vertex order) points to the side that receives light. Solids are
// closed surfaces with outward normals unless Facing::Inward is asked for (rooms).
// Omitted faces (masks, caps) are the caller's statement that the face touches
// another surface and can receive no light; a fully masked-in solid is closed, which
// the tests check (edges pair up with opposite directions, signed volume > 0).
//
// Only triangles and quads are emitted, never larger polygons: the element
// quadtree below each polygon knows how to split those two.
//
// Units: metres, y up (the builtin scenes' convention; the helpers don't care).
#pragma once

#include "core/scene/scene_builder.h"

#include <array>
#include <cstdint>
#include <random>
#include <span>
#include <string>

namespace hrad::builtin {

/// A rigid placement: world = origin + rotation * local.
struct Frame {
  Vec3 origin = Vec3::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();

  static Frame at(const Vec3& origin) { return Frame{origin, Eigen::Matrix3d::Identity()}; }
  /// Rotation by `yaw` radians about +y (counter-clockwise seen from above), then
  /// translation to `origin`.
  static Frame yawed(const Vec3& origin, double yaw);
  /// The frame whose local +y runs from `a` to `b` (origin at `a`).
  static Frame along(const Vec3& a, const Vec3& b);
  /// This frame applied after `child`: world = this(child(local)).
  [[nodiscard]] Frame operator*(const Frame& child) const {
    return Frame{origin + rotation * child.origin, rotation * child.rotation};
  }
  [[nodiscard]] Vec3 operator()(const Vec3& p) const { return origin + rotation * p; }
};

enum class Facing { Outward, Inward };

/// Box faces, for masks: the face on the low (Neg) or high (Pos) side of each axis.
enum BoxFace : unsigned {
  kXNeg = 1u,
  kXPos = 2u,
  kYNeg = 4u,  // bottom
  kYPos = 8u,  // top
  kZNeg = 16u,
  kZPos = 32u,
  kAllFaces = 63u,
  kNoBottom = 63u & ~4u,
};

/// Per-face materials of a box, indexed like the BoxFace bits: x-, x+, y-, y+, z-, z+.
using BoxMaterials = std::array<std::uint32_t, 6>;

/// Cells per axis for a length: round(length / cell), at least 1.
int cells_for(double length, double cell);

/// Deterministic uniform numbers from a fixed seed, identical on every platform
/// (std::mt19937's output is specified; the distributions of <random> are not).
class Rng {
 public:
  explicit Rng(std::uint32_t seed) : gen_(seed) {}
  /// Uniform in [a, b).
  double uniform(double a, double b) { return a + (b - a) * (gen_() * 0x1p-32); }
  /// Uniform integer in [0, n), n >= 1.
  int below(int n) { return static_cast<int>(gen_() % static_cast<std::uint32_t>(n)); }

 private:
  std::mt19937 gen_;
};

class Shapes {
 public:
  /// `spec` names the input in error messages (the builtin spec string).
  Shapes(SceneBuilder& builder, std::string spec) : b_(builder), at_{std::move(spec), 0} {}

  std::uint32_t material(std::string name, const Rgb& reflectance,
                         const Rgb& emission = Rgb::Zero());
  /// When on, every quad is emitted as two triangles (for "tessellated" scenes).
  void set_triangles(bool on) { triangles_ = on; }
  [[nodiscard]] const SourceLoc& at() const { return at_; }

  void tri(const Frame& f, const Vec3& a, const Vec3& b, const Vec3& c, std::uint32_t m);
  /// A planar convex quad, vertices counter-clockwise seen from the lit side.
  void quad(const Frame& f, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
            std::uint32_t m);
  /// A rectangle corner + s*u + t*v (s, t in [0,1]) cut into nu x nv quads; its normal
  /// is u x v.
  void grid(const Frame& f, const Vec3& corner, const Vec3& u, const Vec3& v, int nu, int nv,
            std::uint32_t m);
  /// A quad mesh over the points p(i, j), i in [0, nu], j in [0, nv]; each cell's normal
  /// is dp/di x dp/dj. Cells must be planar (e.g. rectangles, trapezoids).
  template <class Point>
  void surface(const Frame& f, int nu, int nv, Point p, std::uint32_t m) {
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) quad(f, p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1), m);
  }

  /// Axis-aligned box [lo, hi] in the frame, each face cut into a grid of
  /// cells.(axis) cells along each of its two axes; `faces` selects the faces.
  void box(const Frame& f, const Vec3& lo, const Vec3& hi, const BoxMaterials& m,
           unsigned faces = kAllFaces, Facing facing = Facing::Outward,
           const Eigen::Vector3i& cells = Eigen::Vector3i::Ones());
  void box(const Frame& f, const Vec3& lo, const Vec3& hi, std::uint32_t m,
           unsigned faces = kAllFaces, Facing facing = Facing::Outward,
           const Eigen::Vector3i& cells = Eigen::Vector3i::Ones()) {
    box(f, lo, hi, BoxMaterials{m, m, m, m, m, m}, faces, facing, cells);
  }
  /// A convex hexahedron with planar faces, corners indexed like a box's:
  /// c[x + 2y + 4z] with each bit 0 = low side, 1 = high side (e.g. a frustum).
  /// Faces as in box(), outward, one polygon each.
  void hexahedron(const Frame& f, const std::array<Vec3, 8>& c, std::uint32_t m,
                  unsigned faces = kAllFaces);
  /// A box whose faces are cut into cells of about `cell` metres.
  void box_cells(const Frame& f, const Vec3& lo, const Vec3& hi, std::uint32_t m, double cell,
                 unsigned faces = kAllFaces, Facing facing = Facing::Outward);

  /// Cylinder around the local y axis from y0 to y1, `segments` sides, `rings`
  /// bands along the axis; caps (kYNeg / kYPos bits of `caps`) as triangle fans.
  void cylinder(const Frame& f, double radius, double y0, double y1, int segments, int rings,
                std::uint32_t m, unsigned caps = kYNeg | kYPos);
  /// Cylinder between two points (caps as above: kYNeg at `a`, kYPos at `b`).
  void rod(const Vec3& a, const Vec3& b, double radius, int segments, std::uint32_t m,
           unsigned caps = kYNeg | kYPos);
  /// Latitude-longitude sphere: quads (planar trapezoids) between latitudes,
  /// triangles at the poles.
  void sphere(const Frame& f, const Vec3& center, double radius, int slices, int stacks,
              std::uint32_t m);
  /// A closed convex profile (x, y) given counter-clockwise, extruded along local z
  /// from z0 to z1 in `nz` bands; each profile edge is cut into `per_edge` pieces.
  /// Caps (kZNeg / kZPos bits) are fans around the profile's centroid.
  void prism(const Frame& f, std::span<const Eigen::Vector2d> profile, double z0, double z1, int nz,
             int per_edge, std::uint32_t m, unsigned caps = kZNeg | kZPos);
  /// A table: top [-w/2, w/2] x [h - t, h] x [-d/2, d/2] (all faces), four square legs
  /// of side `leg` inset by `inset`, touching the floor and the top (those faces omitted).
  void table(const Frame& f, double w, double d, double h, double t, double leg, double inset,
             std::uint32_t top, std::uint32_t legs);
  /// A luminaire: a housing of size (w, h, d) hanging centred below the ceiling
  /// point `center_at_ceiling`; its top touches the ceiling (omitted) and its bottom
  /// face is the emitter, facing down (world axes, y up).
  void luminaire(const Vec3& center_at_ceiling, double w, double h, double d, std::uint32_t housing,
                 std::uint32_t emitter);

 private:
  void emit(std::span<const Vec3> world, std::uint32_t m);

  SceneBuilder& b_;
  SourceLoc at_;
  bool triangles_ = false;
};

}  // namespace hrad::builtin
