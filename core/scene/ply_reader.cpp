// Reader for hrad's own PLY layout: see ply_reader.h.
#include "core/scene/ply_reader.h"

#include "core/base/input_error.h"
#include "core/base/input_file.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace hrad {

namespace {

template <class T>
T get_le(const std::string& b, std::size_t& at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);  // x86 and ARM hosts are little-endian
  at += sizeof v;
  return v;
}

}  // namespace

RenderMesh decode_ply(const std::string& bytes, const std::string& file) {
  // The header, line by line, against the writer's layout.
  const std::vector<std::string> expected = {"ply",
                                             "format binary_little_endian 1.0",
                                             "element vertex *",
                                             "property float x",
                                             "property float y",
                                             "property float z",
                                             "property float radiosity_r",
                                             "property float radiosity_g",
                                             "property float radiosity_b",
                                             "property uchar red",
                                             "property uchar green",
                                             "property uchar blue",
                                             "element face *",
                                             "property list uchar int vertex_indices",
                                             "end_header"};
  std::size_t at = 0, nv = 0, nf = 0;
  int line = 0;
  for (std::size_t k = 0; k < expected.size();) {
    const std::size_t eol = bytes.find('\n', at);
    if (eol == std::string::npos)
      throw InputError(file, line + 1, "unexpected end of the PLY header");
    std::string text = bytes.substr(at, eol - at);
    if (!text.empty() && text.back() == '\r') text.pop_back();
    at = eol + 1;
    ++line;
    if (text.rfind("comment", 0) == 0) continue;
    const std::string& want = expected[k];
    if (want.back() == '*') {
      const std::string prefix = want.substr(0, want.size() - 1);
      std::size_t count = 0;
      char extra = 0;
      if (text.rfind(prefix, 0) != 0 ||
          std::sscanf(text.c_str() + prefix.size(), "%zu%c", &count, &extra) != 1)
        throw InputError(
            file, line,
            fmt::format("expected '{}N', found '{}' (not an hrad solution.ply?)", prefix, text));
      (k == 2 ? nv : nf) = count;
    } else if (text != want) {
      throw InputError(
          file, line,
          fmt::format("expected '{}', found '{}' (not an hrad solution.ply?)", want, text));
    }
    ++k;
  }
  if (bytes.size() - at < 27 * nv)
    throw InputError(file, 0, fmt::format("truncated: {} vertices announced", nv));
  RenderMesh mesh;
  mesh.positions.resize(nv);
  mesh.radiosity.resize(nv);
  mesh.reflectance.assign(nv, Rgb::Zero());
  for (std::size_t i = 0; i < nv; ++i) {
    for (int c = 0; c < 3; ++c) mesh.positions[i][c] = get_le<float>(bytes, at);
    for (int c = 0; c < 3; ++c) mesh.radiosity[i][c] = get_le<float>(bytes, at);
    at += 3;
  }
  mesh.polys.resize(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    if (at >= bytes.size()) throw InputError(file, 0, fmt::format("truncated at face {}", f));
    const auto k = static_cast<unsigned char>(bytes[at++]);
    if (k != 3 && k != 4)
      throw InputError(file, 0, fmt::format("face {} has {} vertices (3 or 4 expected)", f, k));
    if (bytes.size() - at < 4u * k)
      throw InputError(file, 0, fmt::format("truncated at face {}", f));
    auto& poly = mesh.polys[f];
    poly.fill(RenderMesh::kNoVertex);
    for (unsigned j = 0; j < k; ++j) {
      const auto idx = get_le<std::int32_t>(bytes, at);
      if (idx < 0 || static_cast<std::size_t>(idx) >= nv)
        throw InputError(file, 0, fmt::format("face {} has vertex index {} out of range", f, idx));
      poly[j] = static_cast<std::uint32_t>(idx);
    }
  }
  if (at != bytes.size())
    throw InputError(file, 0, fmt::format("{} bytes after the last face", bytes.size() - at));
  return mesh;
}

RenderMesh read_ply(const std::filesystem::path& path) {
  check_input_file(path, "the PLY file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), 0, "cannot open the file");
  std::stringstream ss;
  ss << in.rdbuf();
  return decode_ply(ss.str(), path.string());
}

}  // namespace hrad
