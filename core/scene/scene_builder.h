// SceneBuilder: the one place where scene invariants are enforced. Every reader
// (OBJ, MGF, builtin) feeds it vertices, materials and polygons with their source
// location; it rejects bad input with an InputError naming file and line, and
// repairs what can be repaired (degenerate faces dropped, non-planar or concave
// polygons triangulated, missing materials defaulted) with counted warnings.
#pragma once

#include "core/base/input_error.h"
#include "core/scene/polygon_key.h"
#include "core/scene/scene.h"

#include <span>
#include <string>
#include <unordered_set>
#include <vector>

namespace hrad {

/// Where a piece of input came from, for error messages.
struct SourceLoc {
  std::string file;
  int line = 0;
};

/// Largest exitance (emission, W per unit area) a material may have: results are
/// written as 32-bit floats (at most 3.4e38), and interreflection multiplies the
/// emission by up to 1 / (1 - rho); 1e30 leaves room for both. (Ke 1e40 solved with
/// exit 0 and wrote inf into solution.ply.)
inline constexpr double kMaxExitance = 1e30;
/// Smallest non-zero exitance (largest channel) a material may have: below it the
/// results would leave what 32-bit floats hold (Ke 1e-300 wrote a mesh of zeros) and
/// the refinement threshold, eps x emitted power, underflowed (Ke 1e-310 refined
/// without bound). The solution scales with the emission: give it in larger units.
inline constexpr double kMinExitance = 1e-20;
/// Coplanar faces facing the same way that share more than this share of the scene's
/// area are reported (core/scene/coplanar_overlap.h).
inline constexpr double kCoplanarOverlapShare = 1e-3;

/// A polygon whose area is below this share of the sum of its squared edge lengths is a
/// sliver (a long face 1e-10 wide): its normal cannot be trusted, and the builder drops
/// it (so does the coplanar cut with such a piece, core/scene/coplanar_overlap.h).
inline constexpr double kSliverAreaRatio = 1e-12;

/// Most corners one input polygon may have (1,048,576), refused with its file, line and
/// count before any work on it: the checks and the triangulation of a polygon at the
/// bound take seconds (docs/bad-input.md), and one polygon gives the solver as many
/// slivers.
inline constexpr std::size_t kMaxPolygonVertices = std::size_t{1} << 20;
/// The scene builder's warning for a scene without emitters. A solve does not print it:
/// the solver says the same, with what it skipped ("scene has no emitter: ...").
inline constexpr const char* kNoEmitterWarning =
    "no face emits light: the solution is zero everywhere";

class SceneBuilder {
 public:
  SceneBuilder(std::string name, std::string source);

  /// Throws InputError when a coordinate is NaN, infinite or beyond +-1e30.
  std::uint32_t add_vertex(const Vec3& p, const SourceLoc& at);
  /// Throws InputError when a reflectance is outside [0,1] or an emission is negative
  /// or not finite.
  std::uint32_t add_material(Material m, const SourceLoc& at);
  /// The grey (0.5) material used for faces that name none; created on first use
  /// and counted in a warning.
  std::uint32_t default_material();
  /// A polygon by indices into the vertices added so far. Throws on an index out of
  /// range, fewer than 3 vertices or more than kMaxPolygonVertices; drops zero-area faces (counted) and copies of an
  /// earlier polygon (the same vertex positions in the same cyclic order, counted:
  /// a coincident copy would reflect and emit its light twice); triangulates
  /// non-planar or non-convex polygons (counted).
  void add_polygon(std::span<const std::uint32_t> idx, std::uint32_t material, const SourceLoc& at);
  /// Convenience for generated geometry: adds the vertices, then the polygon.
  void add_polygon(std::span<const Vec3> pts, std::uint32_t material, const SourceLoc& at);
  void set_camera(const Camera& c) { scene_.camera = c; }
  void warn(std::string message) { scene_.warnings.push_back(std::move(message)); }
  [[nodiscard]] std::size_t vertex_count() const { return scene_.vertices.size(); }
  [[nodiscard]] std::size_t material_count() const { return scene_.materials.size(); }

  /// Finishes the scene. Throws InputError (naming `file`) when it has no polygon;
  /// warns when nothing emits.
  Scene finish(const std::string& file);

 private:
  void emit_face(std::span<const std::uint32_t> idx, std::uint32_t material);
  void triangulate(std::span<const std::uint32_t> idx, std::uint32_t material);

  Scene scene_;
  std::uint32_t default_material_ = UINT32_MAX;
  std::size_t defaulted_faces_ = 0;
  std::size_t degenerate_faces_ = 0;
  std::size_t sliver_faces_ = 0;
  std::size_t triangulated_faces_ = 0;
  std::size_t duplicate_faces_ = 0;
  std::size_t self_overlapping_faces_ = 0;
  std::uint32_t polygons_ = 0;         ///< input polygons kept so far
  std::vector<std::uint32_t> source_;  ///< per face, its input polygon (coplanar test)
  std::string first_self_overlap_;     ///< "file:line: what", of the first one dropped
  /// Each polygon's vertex positions, rotated to start at the smallest (x, y, z), in
  /// its own cyclic order: the key of the duplicate test.
  std::unordered_set<std::vector<double>, PositionsHash> seen_;
};

}  // namespace hrad
