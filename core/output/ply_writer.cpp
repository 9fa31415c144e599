#include "core/output/ply_writer.h"

#include "core/base/atomic_file.h"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace hrad {
namespace {

/// Appends the little-endian bytes of a 4-byte value.
template <typename T>
void put_le(std::string& out, T value) {
  static_assert(sizeof(T) == 4);
  std::uint32_t bits;
  std::memcpy(&bits, &value, 4);
  const char b[4] = {static_cast<char>(bits & 0xff), static_cast<char>((bits >> 8) & 0xff),
                     static_cast<char>((bits >> 16) & 0xff),
                     static_cast<char>((bits >> 24) & 0xff)};
  out.append(b, 4);
}

}  // namespace

std::string encode_ply(const RenderMesh& mesh, const ToneMap& tm) {
  check_render_mesh(mesh);
  if (mesh.positions.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw std::invalid_argument("encode_ply: too many vertices for int indices");

  std::vector<Rgb> radiance;
  radiance.reserve(mesh.radiosity.size());
  for (const Rgb& b : mesh.radiosity) radiance.push_back(b / std::numbers::pi);
  const double exposure = choose_exposure(radiance, tm);

  std::string out = fmt::format(
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment hrad radiosity solution\n"
      "comment radiosity_*: W per unit area (linear); red/green/blue: tone-mapped sRGB\n"
      "element vertex {}\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float radiosity_r\nproperty float radiosity_g\nproperty float radiosity_b\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element face {}\n"
      "property list uchar int vertex_indices\n"
      "end_header\n",
      mesh.positions.size(), mesh.polys.size());
  out.reserve(out.size() + 27 * mesh.positions.size() + 17 * mesh.polys.size());

  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    for (int c = 0; c < 3; ++c) put_le(out, static_cast<float>(mesh.positions[i][c]));
    for (int c = 0; c < 3; ++c) put_le(out, static_cast<float>(mesh.radiosity[i][c]));
    const auto rgb = tone_map(radiance[i], exposure, tm);
    out.append(reinterpret_cast<const char*>(rgb.data()), 3);
  }
  for (const auto& q : mesh.polys) {
    const int k = RenderMesh::is_triangle(q) ? 3 : 4;
    out.push_back(static_cast<char>(k));
    for (int c = 0; c < k; ++c) put_le(out, static_cast<std::int32_t>(q[c]));
  }
  return out;
}

void write_ply(const RenderMesh& mesh, const std::filesystem::path& path, const ToneMap& tm) {
  write_file_atomically(path, encode_ply(mesh, tm));
}

}  // namespace hrad
