// The scene as every reader produces it and every solver consumes it: a polygon
// soup with diffuse materials. Readers go through SceneBuilder, which enforces the
// invariants listed on Scene.
#pragma once

#include "core/base/geometry.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace hrad {

struct Material {
  std::string name;
  Rgb reflectance = Rgb::Constant(0.5);  ///< diffuse reflectance rho, each channel in [0,1]
  Rgb emission = Rgb::Zero();            ///< emitted exitance E (power per unit area)
  /// Both sides of its faces reflect (MGF `sides 2`): core/scene/back_faces.h gives each
  /// such face a back face, unless the `sides` option says `one`; the back face of an
  /// emitter emits only with the `emitter_sides` option `both`.
  bool two_sided = false;
  [[nodiscard]] bool emits() const { return (emission > 0).any(); }
};

/// A planar polygon: 3 vertices, or 4 and more when planar and strictly convex.
struct Face {
  std::uint32_t first = 0;  ///< index into Scene::indices
  std::uint32_t count = 0;  ///< number of vertices (>= 3)
  std::uint32_t material = 0;
};

struct Camera {
  Vec3 eye = Vec3::Zero();
  Vec3 target = Vec3(0, 0, -1);
  Vec3 up = Vec3(0, 1, 0);
  double fov_y_deg = 45.0;
};

/// Invariants (checked by SceneBuilder): every coordinate finite; every face has
/// positive area, is planar to 1e-3 of its size and convex; every reflectance in
/// [0,1], every emission finite and >= 0; every face's material exists.
struct Scene {
  std::string name;    ///< short name used for output folders ("office", "CornellBox-Original")
  std::string source;  ///< what was loaded: a path or a builtin spec
  std::vector<Vec3> vertices;
  std::vector<std::uint32_t> indices;
  std::vector<Face> faces;
  std::vector<Material> materials;
  std::optional<Camera> camera;
  std::vector<std::string> warnings;  ///< for the user; each already counts what it is about
  /// What add_back_faces (core/scene/back_faces.h) did: the `sides` mode it applied ("" when
  /// it did not run), the back faces it appended (the last `back_faces` faces), and the
  /// two-sided faces whose back face the input already had.
  std::string sides;
  /// The `emitter_sides` mode applied, and how many of the back faces got a copy of
  /// their emitting material without the emission.
  std::string emitter_sides;
  std::size_t dark_back_faces = 0;
  std::size_t back_faces = 0;
  std::size_t back_faces_present = 0;

  [[nodiscard]] std::size_t polygon_count() const { return faces.size(); }
  [[nodiscard]] std::vector<Vec3> face_vertices(std::size_t f) const;
  [[nodiscard]] Vec3 face_normal(std::size_t f) const;
  [[nodiscard]] double face_area(std::size_t f) const;
  [[nodiscard]] const Material& face_material(std::size_t f) const {
    return materials[faces[f].material];
  }
  [[nodiscard]] Aabb bounds() const;
  /// Where the bulk of the area lies: per axis, the quantiles (1 - share) / 2 and
  /// (1 + share) / 2 of the faces' corners, each weighted by its face's area / corners.
  /// Far smaller than bounds() when a little geometry lies far away (a small triangle
  /// 30,000 units from a room), which the tolerances relative to bounds() do not suit.
  [[nodiscard]] Aabb bulk_bounds(double share = 0.98) const;
  [[nodiscard]] double total_area() const;
  [[nodiscard]] std::size_t emitter_count() const;
  /// Per channel, the sum over faces of emission x area (stats.json's emitted_power).
  [[nodiscard]] Rgb emitted_power() const;
  /// The sum over faces of area x the face's largest emission channel: the power
  /// scale that the oracle threshold eps is relative to (core/solver/solver.cpp).
  [[nodiscard]] double max_channel_emitted_power() const;
  /// True when every reflectance and emission has equal channels.
  [[nodiscard]] bool is_grey() const;
  /// The up axis a user declared (`--camera up=0,0,1`), or -1: found from the faces.
  int declared_up = -1;
  /// declared_up when set; else for an MGF scene (z up, as RenderPark and Radiance
  /// draw them) 2 unless clearly more face area faces along y than along z (1.5 times),
  /// and for any other 1 (y up, the OBJ convention) unless clearly more faces along z.
  [[nodiscard]] int up_axis() const;
  /// A camera looking horizontally into the scene from outside its bounding box
  /// through the side with the least wall facing inwards, when that side is open (its
  /// inward-facing area is under 5% of the side: the Cornell box's missing front
  /// wall, or any side of a single object); nullopt when every side is walled.
  [[nodiscard]] std::optional<Camera> open_side_camera() const;
  /// open_side_camera(), else a view from 2% inside the least-walled side. Blind to
  /// wall thickness: in a closed room whose walls are thicker than that, the eye is
  /// inside a wall. core/output/auto_camera.h chooses better cameras with rays.
  [[nodiscard]] Camera default_camera() const;
};

}  // namespace hrad
