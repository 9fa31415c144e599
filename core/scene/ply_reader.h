// Reading back the solution.ply files that core/output/ply_writer.h writes, so that two
// solutions can be compared after the fact (core/reference/error_metrics.h).
//
// Accepted: exactly the writer's layout — binary_little_endian 1.0, element vertex with
// float x, y, z, radiosity_r, radiosity_g, radiosity_b and uchar red, green, blue, then
// element face with list uchar int vertex_indices (3 or 4 indices); comment lines are
// skipped. Anything else is an InputError naming the file (and the header line).
#pragma once

#include "core/scene/render_mesh.h"

#include <filesystem>
#include <string>

namespace hrad {

/// Decodes the bytes of a PLY file; `file` names it in errors. Reflectance is not in
/// the file and is set to zero.
[[nodiscard]] RenderMesh decode_ply(const std::string& bytes, const std::string& file);

/// Reads and decodes `path`. Throws InputError when it cannot be read or is malformed.
[[nodiscard]] RenderMesh read_ply(const std::filesystem::path& path);

}  // namespace hrad
