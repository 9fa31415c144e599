// What a solution looks like to the outside world: the leaf elements as a polygon
// mesh with per-vertex values. The renderer (render.h) and the PLY writer
// (ply_writer.h) read only this, so they do not depend on the solver's data structures.
#pragma once

#include "core/base/geometry.h"

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace hrad {

struct Scene;

/// Invariants (check_render_mesh): positions, radiosity and reflectance have one entry
/// per vertex; every polygon is a triangle or a planar convex quad whose indices are
/// below positions.size(); every value finite, radiosity >= 0.
struct RenderMesh {
  static constexpr std::uint32_t kNoVertex = std::numeric_limits<std::uint32_t>::max();

  std::vector<Vec3> positions;  ///< vertices, possibly shared by several polygons
  /// Radiosity B per vertex, in W per unit area (scene units). A solver writes values
  /// smoothed over the leaves that share the vertex.
  std::vector<Rgb> radiosity;
  std::vector<Rgb> reflectance;  ///< diffuse reflectance per vertex (surface colour)
  /// Corners in order; a triangle has polys[i][3] == kNoVertex.
  std::vector<std::array<std::uint32_t, 4>> polys;

  [[nodiscard]] static bool is_triangle(const std::array<std::uint32_t, 4>& p) {
    return p[3] == kNoVertex;
  }
};

/// Throws std::invalid_argument naming the first violated invariant.
void check_render_mesh(const RenderMesh& mesh);

/// The scene before any light transport: radiosity = each face's emission, so only
/// emitters are lit. Every face gets its own vertices (no sharing, hence no smoothing
/// across faces); faces with more than 4 vertices are fan-triangulated.
RenderMesh render_mesh_from_emission(const Scene& scene);

}  // namespace hrad
