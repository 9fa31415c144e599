// Export of a solution as a PLY mesh that MeshLab, Blender or ParaView open directly.
//
// Format: binary little-endian PLY 1.0.
//   element vertex: float x, y, z (scene units); float radiosity_r, radiosity_g,
//                   radiosity_b (W per unit area, linear); uchar red, green, blue
//                   (display colour: radiance B/pi tone-mapped to sRGB with the
//                   ToneMap rules of render.h, automatic exposure over all vertices)
//   element face:   list uchar int vertex_indices (triangles as 3, quads as 4)
// Reflectance is not exported. A vertex record is 27 bytes, a face 1 + 4k bytes.
#pragma once

#include "core/output/render.h"
#include "core/scene/render_mesh.h"

#include <filesystem>
#include <string>

namespace hrad {

/// The complete file contents (header and binary body).
[[nodiscard]] std::string encode_ply(const RenderMesh& mesh, const ToneMap& tm = {});

/// encode_ply written atomically. Throws std::invalid_argument for a bad mesh,
/// std::runtime_error when the file cannot be written.
void write_ply(const RenderMesh& mesh, const std::filesystem::path& path, const ToneMap& tm = {});

}  // namespace hrad
