#include "core/scene/obj_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "core/base/input_error.h"
#include "core/base/input_file.h"
#include "core/scene/scene_builder.h"

// tinyobjloader, compiled into this file in double precision under a private
// namespace name. Debian's libtinyobjloader.so is the float build (7 digits would
// not do for millimetre scenes), and a private copy is also instrumented in
// sanitizer and fuzzing builds, which an uninstrumented shared library is not.
#define TINYOBJLOADER_IMPLEMENTATION
#define TINYOBJLOADER_USE_DOUBLE
#define tinyobj hrad_tinyobj
#include <tiny_obj_loader.h>
#undef tinyobj

namespace hrad {
namespace {

namespace tobj = ::hrad_tinyobj;

// ---------------------------------------------------------------------------
// Text helpers. The pre-scan must see exactly the lines and tokens tinyobjloader
// sees, so it splits the way tinyobjloader does.

/// Lines as tinyobjloader's safeGetline cuts them: "\n", "\r\n" and a lone "\r"
/// each end a line; a last line without an ending counts; line k is lines[k-1].
std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '\n' && text[i] != '\r') continue;
    lines.push_back(text.substr(start, i - start));
    if (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
    start = i + 1;
  }
  if (start < text.size()) lines.push_back(text.substr(start));
  return lines;
}

/// The text with each backslash-newline (OBJ's and MTL's line continuation) replaced by
/// a space, and the newlines it removed put back after the joined line, so that every
/// other line keeps its number (tinyobjloader does not join lines; before, `f 1 2 \`
/// was "malformed vertex reference '\'").
std::string join_continuations(std::string_view text) {
  if (text.find('\\') == std::string_view::npos) return std::string(text);
  std::string out;
  out.reserve(text.size());
  std::size_t owed = 0;  // newlines to put back after the current joined line
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\\') {
      std::size_t j = i + 1;
      if (j < text.size() && text[j] == '\r') ++j;
      if (j < text.size() && text[j] == '\n') {
        out += ' ';
        ++owed;
        i = j;
        continue;
      }
    }
    out += c;
    if (c == '\n') {
      out.append(owed, '\n');
      owed = 0;
    }
  }
  out.append(owed, '\n');
  return out;
}

/// Tokens separated by spaces and tabs (tinyobjloader's only separators), up to
/// the first token that starts a comment.
std::vector<std::string_view> split_tokens(std::string_view line) {
  std::vector<std::string_view> t;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i == line.size()) break;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (line[start] == '#') break;
    t.push_back(line.substr(start, i - start));
  }
  return t;
}

void reject_nul(std::string_view line, const std::string& file, int line_no) {
  if (line.find('\0') != std::string_view::npos)
    throw InputError(file, line_no, "NUL byte in the text (is this a binary file?)");
}

/// A plain decimal number ("-1.5e3", "+2", ".5"); `what` names it in errors.
double parse_number(std::string_view tok, const char* what, const std::string& file, int line) {
  std::string_view s = tok;
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec == std::errc::result_out_of_range)
    throw InputError(file, line, fmt::format("{} '{}' is out of range", what, tok));
  if (ec != std::errc() || end != s.data() + s.size())
    throw InputError(file, line, fmt::format("{} '{}' is not a number", what, tok));
  if (!std::isfinite(v))
    throw InputError(file, line, fmt::format("{} '{}' is not a finite number", what, tok));
  return v;
}

std::optional<long long> parse_integer(std::string_view s) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  long long v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

/// tinyobjloader's values must agree with the strict pre-scan; they can differ for
/// numbers with hundreds of digits or huge exponents, which its parser mishandles.
void cross_check(double ours, double theirs, std::string_view tok, const std::string& file,
                 int line) {
  if (!(std::abs(theirs - ours) <= 1e-9 * std::abs(ours)))
    throw InputError(file, line,
                     fmt::format("number '{}' cannot be read reliably (tinyobjloader reads {}); "
                                 "write it with fewer digits",
                                 tok, theirs));
}

/// Line number quoted in a tinyobjloader message ("... line 12.)"), or 0.
int line_in_message(std::string_view msg) {
  const std::size_t at = msg.rfind("line ");
  if (at == std::string_view::npos) return 0;
  const std::string_view rest = msg.substr(at + 5);
  const std::string_view digits = rest.substr(0, rest.find_first_not_of("0123456789"));
  const auto n = parse_integer(digits);
  return n && *n > 0 && *n <= INT32_MAX ? static_cast<int>(*n) : 0;
}

std::vector<std::string> message_lines(const std::string& text) {
  std::vector<std::string> out;
  for (std::string_view l : split_lines(text))
    if (l.find_first_not_of(" \t.") != std::string_view::npos) out.emplace_back(l);
  return out;
}

// ---------------------------------------------------------------------------
// OBJ pre-scan.

struct ObjFace {
  int line = 0;
  std::uint32_t first = 0;  ///< into ObjScan::indices
  std::uint32_t count = 0;
  int usemtl = -1;  ///< into ObjScan::usemtls; -1 before any usemtl
};

struct Statement {
  std::string text;  ///< usemtl: the name; mtllib: the rest of the line
  int line = 0;
};

struct ObjScan {
  std::string sanitized;  ///< for tinyobjloader: same line count, only checked v/f
  std::vector<int> vertex_line;
  std::vector<double> coords;           ///< 3 per vertex, strictly parsed
  std::vector<std::string_view> texts;  ///< 3 per vertex, the tokens (for messages)
  std::vector<ObjFace> faces;
  std::vector<std::uint32_t> indices;  ///< 0-based absolute vertex indices
  std::vector<Statement> usemtls;
  std::vector<Statement> mtllibs;
  std::size_t unsupported = 0;  ///< l, p, curves, surfaces
  std::size_t unknown = 0;
  Statement first_unknown;
};

bool is_one_of(std::string_view kw, std::initializer_list<std::string_view> set) {
  for (std::string_view s : set)
    if (kw == s) return true;
  return false;
}

/// One "v", "v/vt", "v//vn" or "v/vt/vn" reference; returns the 0-based vertex
/// index, not yet checked against the vertices that follow.
std::uint32_t parse_reference(std::string_view tok, std::size_t vertices_so_far,
                              const std::string& file, int line) {
  const std::string_view v = tok.substr(0, tok.find('/'));
  std::size_t parts = 1;
  for (std::size_t at = tok.find('/'); at != std::string_view::npos; at = tok.find('/', at + 1)) {
    ++parts;
    const std::size_t end = tok.find('/', at + 1);
    const std::string_view part =
        tok.substr(at + 1, end == std::string_view::npos ? end : end - at - 1);
    if (!part.empty() && !parse_integer(part))
      throw InputError(file, line, fmt::format("malformed vertex reference '{}'", tok));
  }
  const auto i = parse_integer(v);
  if (parts > 3 || !i)
    throw InputError(file, line, fmt::format("malformed vertex reference '{}'", tok));
  if (*i == 0) throw InputError(file, line, "vertex index 0 is invalid (OBJ indices start at 1)");
  if (*i > 0) {
    if (*i > UINT32_MAX)
      throw InputError(file, line, fmt::format("vertex index {} is out of range", *i));
    return static_cast<std::uint32_t>(*i - 1);
  }
  const long long n = static_cast<long long>(vertices_so_far);
  if (*i < -n)
    throw InputError(file, line,
                     fmt::format("relative vertex index {} points before the first vertex "
                                 "(only {} vertices precede this line)",
                                 *i, n));
  return static_cast<std::uint32_t>(n + *i);
}

ObjScan scan_obj(std::string_view text, const std::string& file) {
  ObjScan s;
  s.sanitized.reserve(text.size());
  const std::vector<std::string_view> lines = split_lines(text);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const int line = static_cast<int>(k + 1);
    reject_nul(lines[k], file, line);
    const std::vector<std::string_view> tok = split_tokens(lines[k]);
    const std::string_view kw = tok.empty() ? std::string_view() : tok[0];
    if (kw == "v") {
      if (tok.size() < 4)
        throw InputError(
            file, line,
            fmt::format("a vertex needs 3 coordinates, this one has {}", tok.size() - 1));
      s.sanitized += "v";
      for (int c = 1; c <= 3; ++c) {
        s.coords.push_back(parse_number(tok[c], "coordinate", file, line));
        s.texts.push_back(tok[c]);
        (s.sanitized += ' ') += tok[c];
      }
      s.vertex_line.push_back(line);
    } else if (kw == "f") {
      if (tok.size() < 4)
        throw InputError(
            file, line,
            fmt::format("a face needs at least 3 vertices, this one has {}", tok.size() - 1));
      ObjFace f{line, static_cast<std::uint32_t>(s.indices.size()),
                static_cast<std::uint32_t>(tok.size() - 1), static_cast<int>(s.usemtls.size()) - 1};
      s.sanitized += "f";
      for (std::size_t c = 1; c < tok.size(); ++c) {
        s.indices.push_back(parse_reference(tok[c], s.vertex_line.size(), file, line));
        (s.sanitized += ' ') += tok[c].substr(0, tok[c].find('/'));
      }
      s.faces.push_back(f);
    } else if (kw == "usemtl") {
      s.usemtls.push_back({tok.size() > 1 ? std::string(tok[1]) : std::string(), line});
    } else if (kw == "mtllib") {
      const std::string_view l = lines[k];
      const std::size_t from = l.find_first_not_of(" \t", l.find("mtllib") + 6);
      const std::size_t to = l.find_last_not_of(" \t");
      if (from != std::string_view::npos)
        s.mtllibs.push_back({std::string(l.substr(from, to + 1 - from)), line});
    } else if (kw.empty() || is_one_of(kw, {"vn", "vt", "vp", "g", "o", "s", "mg", "usemap",
                                            "maplib", "lod", "shadow_obj", "trace_obj", "bevel",
                                            "c_interp", "d_interp", "call", "csh"})) {
      // Grouping, smoothing, normals and texture data: nothing for a radiosity solver.
    } else if (is_one_of(kw, {"l", "p", "curv", "curv2", "surf", "cstype", "deg", "bmat", "step",
                              "parm", "trim", "hole", "scrv", "sp", "end", "con", "vw", "t"})) {
      ++s.unsupported;
    } else {
      if (s.unknown++ == 0) s.first_unknown = {std::string(kw), line};
    }
    s.sanitized += '\n';
  }
  const std::size_t n = s.vertex_line.size();
  for (const ObjFace& f : s.faces)
    for (std::uint32_t i = 0; i < f.count; ++i)
      if (s.indices[f.first + i] >= n)
        throw InputError(file, f.line,
                         fmt::format("vertex index {} is out of range (the file has {} vertices)",
                                     std::uint64_t{s.indices[f.first + i]} + 1, n));
  return s;
}

// ---------------------------------------------------------------------------
// MTL pre-scan: where each newmtl block, and its Kd and Ke, are.

struct MtlBlock {
  std::string name;
  int line = 0;
  int kd_line = 0, ke_line = 0;  ///< 0 when absent
  std::array<double, 3> kd{}, ke{};
  std::array<std::string_view, 3> kd_text{}, ke_text{};
  bool kd_grey = false, ke_grey = false;  ///< given as one number (MTL: g = b = r)
};

/// A Kd or Ke line's numbers as the file wrote them.
std::string as_written(const std::array<std::string_view, 3>& text, bool grey) {
  return grey ? std::string(text[0]) : fmt::format("{} {} {}", text[0], text[1], text[2]);
}

struct MtlScan {
  std::vector<MtlBlock> blocks;
  std::size_t stray = 0;  ///< Kd/Ke lines before the first newmtl
};

MtlScan scan_mtl(std::string_view text, const std::string& file) {
  MtlScan s;
  const std::vector<std::string_view> lines = split_lines(text);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const int line = static_cast<int>(k + 1);
    reject_nul(lines[k], file, line);
    const std::vector<std::string_view> tok = split_tokens(lines[k]);
    if (tok.empty()) continue;
    if (tok[0] == "newmtl") {
      if (tok.size() < 2) throw InputError(file, line, "newmtl needs a material name");
      s.blocks.push_back({std::string(tok[1]), line});
    } else if (tok[0] == "Kd" || tok[0] == "Ke") {
      if (tok.size() != 4 && tok.size() != 2)
        throw InputError(file, line,
                         fmt::format("{} needs three numbers r g b, or one for a grey (the "
                                     "spectral and xyz forms are not supported)",
                                     tok[0]));
      if (s.blocks.empty()) {
        ++s.stray;
        continue;
      }
      MtlBlock& b = s.blocks.back();
      const bool kd = tok[0] == "Kd";
      (kd ? b.kd_line : b.ke_line) = line;
      const bool grey = tok.size() == 2;
      (kd ? b.kd_grey : b.ke_grey) = grey;
      for (int c = 0; c < 3; ++c) {
        const std::string_view t = tok[grey ? 1 : static_cast<std::size_t>(c + 1)];
        (kd ? b.kd : b.ke)[c] = parse_number(t, kd ? "Kd" : "Ke", file, line);
        (kd ? b.kd_text : b.ke_text)[c] = t;
      }
    }
  }
  return s;
}

// ---------------------------------------------------------------------------
// Building the scene.

struct MtlText {
  std::string file;  ///< for messages
  std::string text;
};

/// Adds the materials of one MTL text; `by_name` maps names to builder indices
/// (the first definition of a name wins, as in tinyobjloader).
void add_materials(const MtlText& mtl, SceneBuilder& b,
                   std::unordered_map<std::string, std::uint32_t>& by_name) {
  const MtlScan scan = scan_mtl(mtl.text, mtl.file);
  std::vector<tobj::material_t> mats;
  std::map<std::string, int> map;
  std::string warn, err;
  std::istringstream in(mtl.text);
  tobj::LoadMtl(&map, &mats, &in, &warn, &err);
  for (const std::string& w : message_lines(warn))
    b.warn(fmt::format("{}: tinyobjloader: {}", mtl.file, w));
  if (const auto e = message_lines(err); !e.empty())
    throw InputError(mtl.file, line_in_message(e[0]), "tinyobjloader: " + e[0]);
  // tinyobjloader returns one material per newmtl, or a single unnamed one if none.
  if (mats.size() != std::max<std::size_t>(scan.blocks.size(), 1))
    throw std::logic_error(
        fmt::format("obj_reader: {}: tinyobjloader found {} materials, the pre-scan {}", mtl.file,
                    mats.size(), scan.blocks.size()));
  if (scan.stray > 0)
    b.warn(
        fmt::format("{}: {} Kd/Ke line(s) before the first newmtl ignored", mtl.file, scan.stray));
  if (scan.blocks.empty()) b.warn(fmt::format("{}: defines no material (no newmtl)", mtl.file));
  std::size_t without_kd = 0;
  for (std::size_t k = 0; k < scan.blocks.size(); ++k) {
    const MtlBlock& blk = scan.blocks[k];
    const tobj::material_t& m = mats[k];
    Material mat;
    mat.name = blk.name;
    // tinyobjloader reads a one-number Kd or Ke as (v, 0, 0); the MTL format means
    // (v, v, v), so those come from the pre-scan, and three numbers must agree.
    for (int c = 0; c < 3; ++c) {
      if (blk.kd_line > 0 && !blk.kd_grey)
        cross_check(blk.kd[c], m.diffuse[c], blk.kd_text[c], mtl.file, blk.kd_line);
      if (blk.ke_line > 0 && !blk.ke_grey)
        cross_check(blk.ke[c], m.emission[c], blk.ke_text[c], mtl.file, blk.ke_line);
      mat.reflectance[c] = blk.kd_line > 0 ? blk.kd[c] : m.diffuse[c];
      // Ke is radiance L; a Lambertian emitter's exitance is pi * L.
      mat.emission[c] = std::numbers::pi * (blk.ke_line > 0 ? blk.ke[c] : m.emission[c]);
    }
    // Errors quote the numbers as the file has them (not pi x Ke, nor 0.7 printed
    // back as 0.7000000000000001).
    const auto in_range = [](const std::array<double, 3>& v, double hi) {
      return std::all_of(v.begin(), v.end(), [&](double x) { return x >= 0 && x <= hi; });
    };
    if (blk.kd_line > 0 && !in_range(blk.kd, 1))
      throw InputError(mtl.file, blk.kd_line,
                       fmt::format("material '{}': Kd {} is outside [0, 1]", blk.name,
                                   as_written(blk.kd_text, blk.kd_grey)));
    if (blk.ke_line > 0 && !in_range(blk.ke, std::numeric_limits<double>::max()))
      throw InputError(mtl.file, blk.ke_line,
                       fmt::format("material '{}': Ke {} is negative or not finite", blk.name,
                                   as_written(blk.ke_text, blk.ke_grey)));
    if (blk.ke_line > 0 && !in_range(blk.ke, kMaxExitance / std::numbers::pi))
      throw InputError(
          mtl.file, blk.ke_line,
          fmt::format("material '{}': Ke {} is too large: its exitance pi x Ke must not exceed "
                      "{:g} (results are 32-bit floats, and interreflection multiplies it)",
                      blk.name, as_written(blk.ke_text, blk.ke_grey), kMaxExitance));
    if (const double top = *std::max_element(blk.ke.begin(), blk.ke.end());
        blk.ke_line > 0 && top > 0 && top * std::numbers::pi < kMinExitance)
      throw InputError(mtl.file, blk.ke_line,
                       fmt::format("material '{}': Ke {} is too small: its exitance pi x Ke must "
                                   "be at least {:g} (results are 32-bit floats; the solution "
                                   "scales with the emission: give it in larger units)",
                                   blk.name, as_written(blk.ke_text, blk.ke_grey), kMinExitance));
    if (blk.kd_line == 0) ++without_kd;
    const Rgb& r = mat.reflectance;
    const bool rho_ok = r.isFinite().all() && (r >= 0).all() && (r <= 1).all();
    const int line =
        !rho_ok ? (blk.kd_line ? blk.kd_line : blk.line) : (blk.ke_line ? blk.ke_line : blk.line);
    const std::uint32_t id = b.add_material(std::move(mat), {mtl.file, line});
    if (!by_name.try_emplace(blk.name, id).second)
      b.warn(fmt::format("{}:{}: material '{}' is defined again; the first definition is used",
                         mtl.file, blk.line, blk.name));
  }
  if (without_kd > 0)
    b.warn(
        fmt::format("{}: {} material(s) without Kd got tinyobjloader's default reflectance "
                    "(0, or 0.6 with a map_Kd)",
                    mtl.file, without_kd));
}

Scene build(const ObjScan& scan, const std::string& obj_file, const std::vector<MtlText>& mtls,
            std::string name, std::string source) {
  SceneBuilder b(std::move(name), std::move(source));

  std::unordered_map<std::string, std::uint32_t> by_name;
  for (const MtlText& m : mtls) add_materials(m, b, by_name);

  tobj::ObjReaderConfig config;
  config.triangulate = false;  // polygons stay polygons; SceneBuilder decides
  config.vertex_color = false;
  tobj::ObjReader reader;
  const bool ok = reader.ParseFromString(scan.sanitized, "", config);
  for (const std::string& w : message_lines(reader.Warning()))
    b.warn(fmt::format("{}: tinyobjloader: {}", obj_file, w));
  if (const auto e = message_lines(reader.Error()); !ok || !e.empty()) {
    const std::string first = e.empty() ? std::string("parse failed") : e[0];
    throw InputError(obj_file, line_in_message(first), "tinyobjloader: " + first);
  }

  const std::vector<double>& v = reader.GetAttrib().vertices;
  if (v.size() != scan.coords.size())
    throw std::logic_error(
        fmt::format("obj_reader: {}: tinyobjloader read {} vertices, the pre-scan {}", obj_file,
                    v.size() / 3, scan.vertex_line.size()));
  for (std::size_t i = 0; i < scan.vertex_line.size(); ++i) {
    const int line = scan.vertex_line[i];
    for (std::size_t c = 0; c < 3; ++c)
      cross_check(scan.coords[3 * i + c], v[3 * i + c], scan.texts[3 * i + c], obj_file, line);
    b.add_vertex(Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]), {obj_file, line});
  }

  // usemtl names resolved once; unknown ones are counted per name.
  std::vector<std::int64_t> resolved(scan.usemtls.size(), -1);
  for (std::size_t u = 0; u < scan.usemtls.size(); ++u)
    if (const auto it = by_name.find(scan.usemtls[u].text); it != by_name.end())
      resolved[u] = it->second;
  std::map<std::string, std::pair<int, std::size_t>> unknown;  // name -> (first line, faces)

  // tinyobjloader keeps faces in file order across shapes; each must be the
  // pre-scan's face with the same vertices. It stores vertex counts in 8 bits
  // (a 300-gon is counted 44), so the pre-scan's counts are used, checked mod 256.
  std::size_t next = 0;
  std::vector<std::uint32_t> idx;
  for (const tobj::shape_t& shape : reader.GetShapes()) {
    std::size_t at = 0;
    for (const unsigned char count8 : shape.mesh.num_face_vertices) {
      if (next >= scan.faces.size() || count8 != (scan.faces[next].count & 0xffu) ||
          at + scan.faces[next].count > shape.mesh.indices.size())
        throw std::logic_error(
            fmt::format("obj_reader: {}: tinyobjloader's face {} differs from the pre-scan's",
                        obj_file, next + 1));
      const ObjFace& f = scan.faces[next++];
      const std::uint32_t count = f.count;
      idx.clear();
      for (std::uint32_t k = 0; k < count; ++k) {
        const int t = shape.mesh.indices[at + k].vertex_index;
        if (t < 0 || static_cast<std::uint32_t>(t) != scan.indices[f.first + k])
          throw std::logic_error(
              fmt::format("obj_reader: {}:{}: tinyobjloader's vertex index {} differs from the "
                          "pre-scan's {}",
                          obj_file, f.line, t, scan.indices[f.first + k]));
        idx.push_back(static_cast<std::uint32_t>(t));
      }
      at += count;
      std::uint32_t material = 0;
      if (f.usemtl >= 0 && resolved[static_cast<std::size_t>(f.usemtl)] >= 0) {
        material = static_cast<std::uint32_t>(resolved[static_cast<std::size_t>(f.usemtl)]);
      } else {
        if (f.usemtl >= 0) {
          const Statement& u = scan.usemtls[static_cast<std::size_t>(f.usemtl)];
          auto& entry = unknown.try_emplace(u.text, u.line, 0).first->second;
          ++entry.second;
        }
        material = b.default_material();
      }
      b.add_polygon(idx, material, {obj_file, f.line});
    }
  }
  if (next != scan.faces.size())
    throw std::logic_error(
        fmt::format("obj_reader: {}: tinyobjloader read {} faces, the pre-scan {}", obj_file, next,
                    scan.faces.size()));

  for (const auto& [mat, where] : unknown)
    b.warn(fmt::format(
        "{}:{}: usemtl '{}' names no material {}; its {} face(s) get the default grey", obj_file,
        where.first, mat, mtls.empty() ? "(no material library was loaded)" : "of the .mtl file(s)",
        where.second));
  if (scan.unsupported > 0)
    b.warn(
        fmt::format("{}: {} line, point, curve or surface statement(s) ignored: hrad reads "
                    "polygons only",
                    obj_file, scan.unsupported));
  if (scan.unknown > 0)
    b.warn(fmt::format("{}: {} line(s) with unknown statements ignored (the first, line {}: '{}')",
                       obj_file, scan.unknown, scan.first_unknown.line, scan.first_unknown.text));
  return b.finish(obj_file);
}

/// The whole file; errors are reported at (err_file, err_line) and call the file
/// `what`.
std::string read_text(const std::string& path, const std::string& err_file, int err_line,
                      const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(err_file, err_line,
                     fmt::format("{} {}", what,
                                 std::filesystem::exists(path, ec) ? "is not a regular file"
                                                                   : "does not exist"));
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in.good() && !in.eof())
    throw InputError(err_file, err_line, fmt::format("cannot read {}", what));
  return checked_text(std::move(text).str(), path);
}

/// The files one mtllib statement names: the whole rest of the line when that is a
/// file (names with spaces), otherwise each whitespace-separated name.
std::vector<std::filesystem::path> mtllib_files(const Statement& st,
                                                const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(dir / st.text, ec)) return {dir / st.text};
  std::vector<fs::path> out;
  for (std::string_view t : split_tokens(st.text)) out.push_back(dir / std::string(t));
  return out;
}

}  // namespace

Scene read_obj(const std::string& path) {
  namespace fs = std::filesystem;
  const std::string text = join_continuations(read_text(path, path, 0, "the file"));
  const ObjScan scan = scan_obj(text, path);
  std::vector<MtlText> mtls;
  std::set<fs::path> seen;
  for (const Statement& st : scan.mtllibs) {
    for (const fs::path& p : mtllib_files(st, fs::path(path).parent_path())) {
      if (!seen.insert(p.lexically_normal()).second) continue;
      mtls.push_back({p.string(), join_continuations(read_text(
                                      p.string(), path, st.line,
                                      fmt::format("material library '{}'", p.string())))});
    }
  }
  return build(scan, path, mtls, fs::path(path).stem().string(), path);
}

Scene parse_obj(std::string_view obj_text, std::string_view mtl_text,
                const std::string& name_for_errors) {
  namespace fs = std::filesystem;
  std::string mtl_name = name_for_errors;
  if (mtl_name.size() >= 4 && mtl_name.ends_with(".obj")) mtl_name.resize(mtl_name.size() - 4);
  mtl_name += ".mtl";
  const std::string joined = join_continuations(obj_text);
  const ObjScan scan = scan_obj(joined, name_for_errors);
  std::vector<MtlText> mtls;
  if (!mtl_text.empty()) mtls.push_back({mtl_name, join_continuations(mtl_text)});
  return build(scan, name_for_errors, mtls, fs::path(name_for_errors).stem().string(),
               name_for_errors);
}

}  // namespace hrad
