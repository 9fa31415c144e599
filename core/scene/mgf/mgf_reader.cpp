// MGF reader: splits text into entities, keeps the colour / material / vertex /
// transform contexts, expands includes and transform arrays, and feeds polygons to
// SceneBuilder. Entity table and conventions: mgf_reader.h.
#include "core/scene/mgf/mgf_reader.h"

#include "core/base/input_file.h"
#include "core/scene/mgf/cie_observer.h"
#include "core/scene/mgf/mgf_color.h"
#include "core/scene/mgf/mgf_context.h"
#include "core/scene/mgf/mgf_segments.h"
#include "core/scene/mgf/mgf_shapes.h"
#include "core/scene/mgf/mgf_xform.h"
#include "core/scene/scene_builder.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace hrad {

namespace {

namespace fs = std::filesystem;
using Args = std::span<const std::string_view>;

// cct below this is refused, as by the MGF parser library (its black-body routine
// rejects T < 1000 K).
constexpr double kMgfMinKelvin = 1000.0;

// One entity: a physical line plus those joined to it by a backslash-newline.
struct Entity {
  std::size_t begin = 0, end = 0;
  int line = 0;  ///< 1-based physical line where the entity starts
};

struct Source {
  std::string path;  ///< as shown in messages
  fs::path dir;      ///< includes resolve against this
  std::string owned;
  std::string_view text;
  std::vector<Entity> entities;
};

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

std::vector<Entity> split_entities(std::string_view text) {
  std::vector<Entity> out;
  std::size_t pos = 0;
  int line = 1;
  while (pos < text.size()) {
    Entity e{pos, pos, line};
    for (;;) {
      const std::size_t nl = text.find('\n', pos);
      if (nl == std::string_view::npos) {
        pos = text.size();
        break;
      }
      ++line;
      std::size_t last = nl;
      if (last > pos && text[last - 1] == '\r') --last;
      const bool continued = last > pos && text[last - 1] == '\\';
      pos = nl + 1;
      if (!continued) break;
    }
    e.end = pos;
    out.push_back(e);
  }
  return out;
}

// Splits on white space; a backslash before a newline (or at the very end) is space.
void tokenize(std::string_view s, std::vector<std::string_view>& toks) {
  toks.clear();
  auto escaped_newline = [&](std::size_t k) {
    if (s[k] != '\\') return false;
    if (k + 1 == s.size() || s[k + 1] == '\n') return true;
    return s[k + 1] == '\r' && k + 2 < s.size() && s[k + 2] == '\n';
  };
  std::size_t i = 0;
  while (i < s.size()) {
    if (is_space(s[i]) || escaped_newline(i)) {
      ++i;
      continue;
    }
    const std::size_t b = i;
    while (i < s.size() && !is_space(s[i]) && !escaped_newline(i)) ++i;
    toks.push_back(s.substr(b, i - b));
  }
}

struct XfFrame {
  XfSpec spec;
  std::vector<long> index;  ///< current array instance, one entry per -a group
  Affine world = Affine::Identity();
  bool mirrored = false;
  std::uint64_t id = 0;   ///< identifies `world` for the vertex cache
  std::size_t begin = 0;  ///< entity index of the xf begin (arrays rewind here)
  int line = 0;
  long instances = 1;  ///< array instances of this frame times its enclosing frames'
};

struct VertexKey {
  std::uint64_t clock, xf;
  bool operator==(const VertexKey&) const = default;
};
struct VertexKeyHash {
  std::size_t operator()(const VertexKey& k) const {
    return std::hash<std::uint64_t>()(k.clock * 0x9E3779B97F4A7C15ull ^ k.xf);
  }
};

// A primitive, kept until the scene's size is known (its segment count depends on it,
// core/scene/mgf/mgf_segments.h): its arguments in its own frame, the transform and material
// current at its line, and the radius (in world units) its count follows.
struct PendingShape {
  std::string_view kind;  ///< "sph", "cyl", "cone", "ring", "torus", "prism"
  Vec3 a = Vec3::Zero(), b = Vec3::Zero(), n = Vec3::Zero();
  double r0 = 0, r1 = 0;
  std::vector<Vec3> base;  ///< prism
  Affine world = Affine::Identity();
  bool mirrored = false;
  double radius = 0;  ///< world units
};

// A face or a shape, in file order: the polygons reach SceneBuilder in that order.
struct PendingPolygon {
  std::vector<std::uint32_t> face;  ///< vertex indices, already in world order
  std::int64_t shape = -1;          ///< index into the shapes, or -1 for a face
  std::uint32_t material = 0;
  const std::string* file = nullptr;
  int line = 0;
};

class MgfParser {
 public:
  MgfParser(const std::string& name, const std::string& source, const MgfOptions& opt)
      : opt_(opt), builder_(name, source) {}

  void run_main(std::unique_ptr<Source> src) {
    Source& s = *src;
    sources_.emplace(s.path, std::move(src));
    run(s, 0);
  }
  Scene finish(const std::string& file);

 private:
  void run(const Source& src, int depth);
  void entity(Args t, const SourceLoc& at, const Source& src, int depth);
  void include(Args t, const SourceLoc& at, const Source& src, int depth);
  const Source& load(const fs::path& p, const SourceLoc& at);
  void push_xf(XfSpec spec, std::size_t begin, int line, const SourceLoc& at);
  void set_world(XfFrame& f);
  bool next_instance(XfFrame& f) const;
  void charge(std::int64_t n, const SourceLoc& at);

  void colour_entity(Args t, const SourceLoc& at);
  MgfColour spectrum_colour(Args t, const SourceLoc& at);
  MgfColour mixed_colour(Args t, const SourceLoc& at);
  // The colour of a spectrum's XYZ; InputError "kw: empty" when it has no light.
  static MgfColour xyz_colour(const Eigen::Vector3d& xyz, const SourceLoc& at, std::string_view kw,
                              std::string_view empty);
  void material_entity(Args t, const SourceLoc& at);
  void face(Args names, const SourceLoc& at);
  void primitive(Args t, const SourceLoc& at);
  void emit(const ShapeMesh& mesh, std::uint32_t material, const Affine& world, bool mirrored,
            const SourceLoc& at);
  void defer_shape(PendingShape shape, const Aabb& world_bounds, const SourceLoc& at);
  ShapeMesh tessellate(const PendingShape& s, int segments) const;
  const MgfVertex& vertex(std::string_view name, const SourceLoc& at) {
    return vertices_.get(name, at).value;
  }
  std::uint32_t vertex_index(std::string_view name, const SourceLoc& at);
  std::uint32_t material(const SourceLoc& at);
  Affine world() const { return xf_.empty() ? Affine::Identity() : xf_.back().world; }
  bool mirrored() const { return !xf_.empty() && xf_.back().mirrored; }
  std::uint64_t xf_id() const { return xf_.empty() ? 0 : xf_.back().id; }

  const MgfOptions& opt_;
  SceneBuilder builder_;
  std::map<std::string, std::unique_ptr<Source>> sources_;
  std::uint64_t clock_ = 0;
  MgfContextTable<MgfColour> colours_{"c", "colour", clock_};
  MgfContextTable<MgfMaterial> materials_{"m", "material", clock_};
  MgfContextTable<MgfVertex> vertices_{"v", "vertex", clock_};
  bool material_selected_ = false;
  std::vector<XfFrame> xf_;
  std::uint64_t xf_ids_ = 0;
  std::unordered_map<VertexKey, std::uint32_t, VertexKeyHash> vertex_cache_;
  std::map<std::tuple<std::string, double, double, double, double, double, double, bool>,
           std::uint32_t>
      material_cache_;
  std::int64_t work_ = 0;
  std::vector<PendingPolygon> pending_;
  std::vector<PendingShape> shapes_;
  Aabb bounds_;                        ///< of the faces' vertices and every shape's extent (world)
  const std::string* file_ = nullptr;  ///< the file being read (stable: sources_ owns it)
  int object_depth_ = 0;
  // Counted warnings.
  std::map<std::string, std::size_t, std::less<>> unknown_;
  std::size_t specular_ignored_ = 0, unmatched_o_ = 0, unclosed_xf_ = 0;
  std::size_t negative_samples_ = 0;  // cspec values taken as zero
  SourceLoc first_negative_;
  // Scene materials whose reflectance / emission colour was gamut-mapped.
  std::size_t mapped_reflectance_ = 0, mapped_emission_ = 0;
};

void need(Args t, std::size_t n, const SourceLoc& at, std::string_view usage) {
  if (t.size() != n + 1)
    throw InputError(
        at.file, at.line,
        fmt::format("{}: expected {} argument(s) ({}), got {}", t[0], n, usage, t.size() - 1));
}

double number(std::string_view tok, const SourceLoc& at, std::string_view entity) {
  return parse_mgf_number(tok, at, entity);
}

void MgfParser::charge(std::int64_t n, const SourceLoc& at) {
  work_ += n;
  if (work_ > opt_.max_work)
    throw InputError(at.file, at.line,
                     fmt::format("more than {} entities and polygons after expanding includes "
                                 "and arrays (MgfOptions::max_work)",
                                 opt_.max_work));
}

void MgfParser::set_world(XfFrame& f) {
  const std::size_t me = static_cast<std::size_t>(&f - xf_.data());
  const Affine parent = me == 0 ? Affine::Identity() : xf_[me - 1].world;
  f.world = parent * f.spec.instance(f.index);
  f.mirrored = f.world.linear().determinant() < 0;
  f.id = ++xf_ids_;
}

void MgfParser::push_xf(XfSpec spec, std::size_t begin, int line, const SourceLoc& at) {
  XfFrame f;
  f.instances = xf_.empty() ? 1 : xf_.back().instances;
  for (const XfGroup& g : spec.groups) {
    if (!g.array) continue;
    if (g.count > opt_.max_instances / f.instances)
      throw InputError(at.file, line,
                       fmt::format("xf: this array makes more than {} instances with the arrays "
                                   "around it (MgfOptions::max_instances)",
                                   opt_.max_instances));
    f.instances *= g.count;
  }
  f.index.assign(spec.array_dims(), 0);
  f.spec = std::move(spec);
  f.begin = begin;
  f.line = line;
  xf_.push_back(std::move(f));
  set_world(xf_.back());
}

bool MgfParser::next_instance(XfFrame& f) const {
  std::vector<long> counts;
  for (const XfGroup& g : f.spec.groups)
    if (g.array) counts.push_back(g.count);
  for (std::size_t d = f.index.size(); d-- > 0;) {
    if (++f.index[d] < counts[d]) return true;
    f.index[d] = 0;
  }
  return false;
}

void MgfParser::run(const Source& src, int depth) {
  const std::size_t base = xf_.size();
  const XfLimits lim{opt_.max_array, opt_.max_repeat};
  SourceLoc at{src.path, 0};
  const std::string* outer_file = file_;
  file_ = &src.path;
  std::vector<std::string_view> t;
  for (std::size_t k = 0; k < src.entities.size(); ++k) {
    const Entity& e = src.entities[k];
    tokenize(src.text.substr(e.begin, e.end - e.begin), t);
    if (t.empty() || t[0].front() == '#') continue;
    at.line = e.line;
    charge(1, at);
    if (t[0] != "xf") {
      entity(t, at, src, depth);
      continue;
    }
    if (t.size() > 1) {
      push_xf(parse_xf(Args(t).subspan(1), at, lim), k, e.line, at);
      continue;
    }
    if (xf_.size() <= base)
      throw InputError(at.file, at.line, "xf end without a matching xf begin in this file");
    if (next_instance(xf_.back())) {
      set_world(xf_.back());
      k = xf_.back().begin;  // the loop's ++k resumes after the xf begin
      continue;
    }
    xf_.pop_back();
  }
  file_ = outer_file;
  while (xf_.size() > base) {
    if (xf_.back().spec.has_array())
      throw InputError(src.path, xf_.back().line,
                       "this xf array is not ended (xf) before the end of its file");
    xf_.pop_back();
    ++unclosed_xf_;
  }
}

void MgfParser::entity(Args t, const SourceLoc& at, const Source& src, int depth) {
  const std::string_view kw = t[0];
  if (kw == "f") {
    if (t.size() < 4) throw InputError(at.file, at.line, "f: a face needs at least 3 vertices");
    face(t.subspan(1), at);
  } else if (kw == "v") {
    vertices_.select(t.subspan(1), at);
  } else if (kw == "p" || kw == "n") {
    need(t, 3, at, kw == "p" ? "p x y z" : "n dx dy dz");
    const Vec3 x(number(t[1], at, kw), number(t[2], at, kw), number(t[3], at, kw));
    (kw == "p" ? vertices_.current().value.p : vertices_.current().value.n) = x;
    vertices_.touch();
  } else if (kw == "sph" || kw == "cyl" || kw == "cone" || kw == "ring" || kw == "torus" ||
             kw == "prism") {
    primitive(t, at);
  } else if (kw == "c" || kw == "cxy" || kw == "cspec" || kw == "cct" || kw == "cmix") {
    colour_entity(t, at);
  } else if (kw == "m" || kw == "sides" || kw == "rd" || kw == "ed" || kw == "td" || kw == "rs" ||
             kw == "ts" || kw == "ir") {
    material_entity(t, at);
  } else if (kw == "o") {
    if (t.size() > 2) throw InputError(at.file, at.line, "o: expected 'o [name]'");
    if (t.size() == 2) {
      ++object_depth_;
    } else if (object_depth_ > 0) {
      --object_depth_;
    } else {
      ++unmatched_o_;
    }
  } else if (kw == "i") {
    include(t, at, src, depth);
  } else if (kw == "ies") {
    throw InputError(at.file, at.line,
                     "ies: goniometric (IES LM-63) luminaires are not supported: hrad's "
                     "emitters are ideal diffuse; describe the luminaire as MGF geometry with "
                     "an emitting (ed) material");
  } else {
    ++unknown_[std::string(kw)];
  }
}

const Source& MgfParser::load(const fs::path& p, const SourceLoc& at) {
  const std::string key = p.lexically_normal().string();
  if (const auto it = sources_.find(key); it != sources_.end()) return *it->second;
  std::error_code ec;
  std::ifstream in;
  if (fs::is_regular_file(p, ec)) in.open(p, std::ios::binary);
  if (!in.is_open())
    throw InputError(at.file, at.line,
                     fmt::format("i: cannot open included file '{}'", p.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  auto src = std::make_unique<Source>();
  src->path = p.string();
  src->dir = p.parent_path();
  src->owned = checked_text(std::move(ss).str(), p.string());
  src->text = src->owned;
  src->entities = split_entities(src->text);
  return *sources_.emplace(key, std::move(src)).first->second;
}

void MgfParser::include(Args t, const SourceLoc& at, const Source& src, int depth) {
  if (t.size() < 2) throw InputError(at.file, at.line, "i: expected 'i pathname [transform]'");
  if (depth + 1 > opt_.max_include_depth)
    throw InputError(at.file, at.line,
                     fmt::format("i: includes nested deeper than {} (does a file include "
                                 "itself?)",
                                 opt_.max_include_depth));
  const fs::path rel(t[1]);
  const Source& inc = load(rel.is_absolute() ? rel : src.dir / rel, at);
  if (t.size() == 2) {
    run(inc, depth + 1);
    return;
  }
  push_xf(parse_xf(t.subspan(2), at, {opt_.max_array, opt_.max_repeat}), 0, at.line, at);
  const std::size_t mine = xf_.size() - 1;
  for (;;) {
    run(inc, depth + 1);
    if (!next_instance(xf_[mine])) break;
    set_world(xf_[mine]);
  }
  xf_.pop_back();
}

void MgfParser::colour_entity(Args t, const SourceLoc& at) {
  const std::string_view kw = t[0];
  if (kw == "c") {
    colours_.select(t.subspan(1), at);
    return;
  }
  MgfColour& c = colours_.current().value;
  if (kw == "cxy") {
    need(t, 2, at, "cxy x y");
    const double x = number(t[1], at, kw), y = number(t[2], at, kw);
    if (!is_mgf_chromaticity(x, y))
      throw InputError(at.file, at.line,
                       fmt::format("cxy: ({}, {}) is not a chromaticity (need x >= 0, y >= 0, "
                                   "x + y <= 1)",
                                   x, y));
    c = MgfColour{x, y, is_equal_energy_grey(x, y)};
  } else if (kw == "cspec") {
    c = spectrum_colour(t, at);
  } else if (kw == "cct") {
    need(t, 1, at, "cct temperature");
    const double k = number(t[1], at, kw);
    if (!(k >= kMgfMinKelvin))
      throw InputError(at.file, at.line,
                       fmt::format("cct: {} K is below {} K (the MGF parser's lowest "
                                   "black-body temperature)",
                                   k, kMgfMinKelvin));
    c = xyz_colour(blackbody_xyz(k), at, kw, "no usable black-body spectrum");
  } else {
    c = mixed_colour(t, at);
  }
  colours_.touch();
}

// cspec l_min l_max v1 .. vN (cie_observer.h): N >= 2 values, not all zero, evenly
// spaced over 0 < l_min < l_max nm; only 360..830 nm is seen. Measured spectra carry
// small negative samples (noise around zero: RenderPark's hospital has -0.8 beside a
// peak of 38): a negative value no larger in magnitude than the spectrum's largest is
// taken as zero, counted, and reported once with the first place it was met; a larger
// one is an error, as is a spectrum with no positive value.
MgfColour MgfParser::spectrum_colour(Args t, const SourceLoc& at) {
  const std::string_view kw = t[0];
  if (t.size() < 5)
    throw InputError(at.file, at.line,
                     "cspec: expected 'cspec l_min l_max v1 v2 ...' (at least 2 values)");
  const double lo = number(t[1], at, kw), hi = number(t[2], at, kw);
  if (!(lo > 0 && lo < hi))
    throw InputError(at.file, at.line,
                     fmt::format("cspec: need 0 < l_min < l_max (got {} and {} nm)", lo, hi));
  std::vector<double> v;
  v.reserve(t.size() - 3);
  for (std::size_t i = 3; i < t.size(); ++i) v.push_back(number(t[i], at, kw));
  const double peak = *std::max_element(v.begin(), v.end());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i] >= 0) continue;
    if (!(-v[i] <= peak))
      throw InputError(at.file, at.line,
                       fmt::format("cspec: value {} ({}) is negative and larger in magnitude "
                                   "than the spectrum's largest value ({})",
                                   i + 1, v[i], peak));
    if (negative_samples_++ == 0) first_negative_ = at;
    v[i] = 0;
  }
  return xyz_colour(spectrum_to_xyz(lo, hi, v), at, kw,
                    "the spectrum has no power between 360 and 830 nm");
}

MgfColour MgfParser::xyz_colour(const Eigen::Vector3d& xyz, const SourceLoc& at,
                                std::string_view kw, std::string_view empty) {
  const double sum = xyz.sum();
  if (!xyz.allFinite() || !std::isfinite(sum))
    throw InputError(at.file, at.line, fmt::format("{}: the colour's CIE XYZ overflows", kw));
  if (!(sum > 0) || !(xyz.minCoeff() >= 0))
    throw InputError(at.file, at.line, fmt::format("{}: {}", kw, empty));
  const double x = xyz.x() / sum, y = xyz.y() / sum;
  return MgfColour{x, y, is_equal_energy_grey(x, y)};
}

// cmix w1 c1 w2 c2 ...: the weights are luminances (MGF: "relative photometric
// brightness"), so the mix is the sum of each colour's XYZ at luminance w_i,
// w_i (x_i, y_i, z_i) / y_i. That is exact for spectral colours too (XYZ is linear in
// the spectrum; the MGF parser's own spectral mixing normalises each spectrum to its
// luminance the same way). A colour with y_i = 0 and w_i > 0 has infinite XYZ: the
// limit (all such y_i -> 0 together) is the w_i-weighted sum of their (x_i, 0, z_i)
// alone, again a y = 0 colour.
MgfColour MgfParser::mixed_colour(Args t, const SourceLoc& at) {
  const std::string_view kw = t[0];
  if (t.size() < 3 || t.size() % 2 == 0)
    throw InputError(at.file, at.line, "cmix: expected 'cmix w1 c1 w2 c2 ...'");
  Eigen::Vector3d finite = Eigen::Vector3d::Zero(), unbounded = Eigen::Vector3d::Zero();
  bool grey = true;
  for (std::size_t i = 1; i + 1 < t.size(); i += 2) {
    const double w = number(t[i], at, kw);
    if (w < 0) throw InputError(at.file, at.line, "cmix: a weight is negative");
    const MgfColour& ci = colours_.get(t[i + 1], at).value;
    grey = grey && ci.grey;
    if (w == 0) continue;
    const Eigen::Vector3d xyz(ci.x, ci.y, std::max(0.0, 1.0 - ci.x - ci.y));
    if (ci.y > 0) {
      finite += (w / ci.y) * xyz;
    } else {
      unbounded += w * xyz;
    }
  }
  const Eigen::Vector3d& xyz = unbounded.sum() > 0 ? unbounded : finite;
  const double sum = xyz.sum();
  if (!(sum > 0) || !std::isfinite(sum))
    throw InputError(at.file, at.line, "cmix: the weights sum to zero or overflow");
  const double x = xyz.x() / sum, y = xyz.y() / sum;
  return MgfColour{x, y, grey || is_equal_energy_grey(x, y)};
}

void MgfParser::material_entity(Args t, const SourceLoc& at) {
  const std::string_view kw = t[0];
  if (kw == "m") {
    materials_.select(t.subspan(1), at);
    material_selected_ = true;
    return;
  }
  MgfMaterial& m = materials_.current().value;
  auto fraction = [&](std::string_view tok) {
    const double v = number(tok, at, kw);
    if (v < 0 || v > 1)
      throw InputError(at.file, at.line, fmt::format("{}: {} is outside [0, 1]", kw, v));
    return v;
  };
  if (kw == "sides") {
    need(t, 1, at, "sides 1|2");
    m.sides = static_cast<int>(parse_mgf_integer(t[1], 1, 2, at, "sides"));
  } else if (kw == "rd") {
    need(t, 1, at, "rd rho_d");
    m.rd = fraction(t[1]);
    m.rd_colour = colours_.current().value;
  } else if (kw == "ed") {
    need(t, 1, at, "ed epsilon_d");
    m.ed = number(t[1], at, kw);
    if (m.ed < 0) throw InputError(at.file, at.line, "ed: the emittance is negative");
    m.ed_colour = colours_.current().value;
  } else if (kw == "td") {
    need(t, 1, at, "td tau_d");
    specular_ignored_ += fraction(t[1]) > 0 ? 1 : 0;
  } else if (kw == "rs" || kw == "ts") {
    need(t, 2, at, fmt::format("{} value roughness", kw));
    const double v = fraction(t[1]);
    if (number(t[2], at, kw) < 0)
      throw InputError(at.file, at.line, fmt::format("{}: the roughness is negative", kw));
    specular_ignored_ += v > 0 ? 1 : 0;
  } else {  // ir n_real n_imag: only matters with specular terms, which are ignored
    need(t, 2, at, "ir n_real n_imag");
    number(t[1], at, kw);
    number(t[2], at, kw);
  }
  materials_.touch();
}

std::uint32_t MgfParser::material(const SourceLoc& at) {
  if (!material_selected_) return builder_.default_material();
  MgfEntry<MgfMaterial>& e = materials_.current();
  if (e.built != UINT32_MAX && e.built_clock == e.clock) return e.built;
  Material m;
  m.name = e.name.empty() ? "(unnamed MGF material)" : e.name;
  const MgfColour& rc = e.value.rd_colour;
  const MgfColour& ec = e.value.ed_colour;
  const GamutRgb r = xyY_to_gamut_rgb(rc.x, rc.y, e.value.rd, 1.0);
  const GamutRgb em = xyY_to_gamut_rgb(ec.x, ec.y, e.value.ed / kMgfLumensPerWatt,
                                       std::numeric_limits<double>::infinity());
  m.reflectance = r.rgb;
  m.emission = em.rgb;
  m.two_sided = e.value.sides == 2;
  const auto key = std::make_tuple(m.name, r.rgb[0], r.rgb[1], r.rgb[2], em.rgb[0], em.rgb[1],
                                   em.rgb[2], m.two_sided);
  auto it = material_cache_.find(key);
  if (it == material_cache_.end()) {
    it = material_cache_.emplace(key, builder_.add_material(std::move(m), at)).first;
    mapped_reflectance_ += r.mapped ? 1 : 0;
    mapped_emission_ += em.mapped ? 1 : 0;
  }
  e.built = it->second;
  e.built_clock = e.clock;
  return e.built;
}

std::uint32_t MgfParser::vertex_index(std::string_view name, const SourceLoc& at) {
  const MgfEntry<MgfVertex>& v = vertices_.get(name, at);
  const VertexKey key{v.clock, xf_id()};
  if (const auto it = vertex_cache_.find(key); it != vertex_cache_.end()) return it->second;
  const Vec3 p = world() * v.value.p;
  const std::uint32_t i = builder_.add_vertex(p, at);
  bounds_.extend(p);
  vertex_cache_.emplace(key, i);
  return i;
}

void MgfParser::face(Args names, const SourceLoc& at) {
  std::vector<std::uint32_t> idx;
  idx.reserve(names.size());
  for (std::string_view n : names) idx.push_back(vertex_index(n, at));
  if (mirrored()) std::reverse(idx.begin(), idx.end());
  PendingPolygon f;
  f.face = std::move(idx);
  f.material = material(at);
  f.file = file_;
  f.line = at.line;
  pending_.push_back(std::move(f));
}

// A shape's points are transformed and added once, so that its facets share them.
void MgfParser::emit(const ShapeMesh& mesh, std::uint32_t material, const Affine& world,
                     bool mirrored, const SourceLoc& at) {
  charge(static_cast<std::int64_t>(mesh.polygons.size()), at);
  std::vector<std::uint32_t> index;
  index.reserve(mesh.points.size());
  for (const Vec3& p : mesh.points) index.push_back(builder_.add_vertex(world * p, at));
  std::vector<std::uint32_t> idx;
  for (const auto& poly : mesh.polygons) {
    idx.clear();
    for (std::uint32_t i : poly) idx.push_back(index[i]);
    if (mirrored) std::reverse(idx.begin(), idx.end());
    builder_.add_polygon(idx, material, at);
  }
}

void MgfParser::defer_shape(PendingShape shape, const Aabb& world_bounds, const SourceLoc& at) {
  // The shape's points will lie in these bounds: refuse them here, at its line, if they
  // would not fit a scene (as SceneBuilder::add_vertex would when it is tessellated).
  for (const Vec3& corner : {world_bounds.lo, world_bounds.hi})
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(corner[i]) || std::abs(corner[i]) > 1e30)
        throw InputError(
            at.file, at.line,
            fmt::format("{}: the shape reaches a coordinate beyond +-1e30", shape.kind));
  bounds_.extend(world_bounds);
  shape.world = world();
  shape.mirrored = mirrored();
  PendingPolygon p;
  p.shape = static_cast<std::int64_t>(shapes_.size());
  p.material = material(at);
  p.file = file_;
  p.line = at.line;
  shapes_.push_back(std::move(shape));
  pending_.push_back(std::move(p));
}

ShapeMesh MgfParser::tessellate(const PendingShape& s, int n) const {
  if (s.kind == "sph") return tessellate_sphere(s.a, s.r0, n);
  if (s.kind == "cyl" || s.kind == "cone") return tessellate_cone(s.a, s.r0, s.b, s.r1, n);
  if (s.kind == "ring") return tessellate_ring(s.a, s.n, s.r0, s.r1, n);
  if (s.kind == "torus") return tessellate_torus(s.a, s.n, s.r0, s.r1, n);
  return tessellate_prism(s.base, s.r0);
}

void MgfParser::primitive(Args t, const SourceLoc& at) {
  const std::string_view kw = t[0];
  // World frame: MGF transforms are rigid with a uniform scale s.
  const Affine w = world();
  const double scale = std::cbrt(std::abs(w.linear().determinant()));
  const auto kind_of = [&]() -> std::string_view {
    for (std::string_view k : {"sph", "cyl", "cone", "ring", "torus", "prism"})
      if (kw == k) return k;
    return "prism";
  };
  PendingShape shape;
  shape.kind = kind_of();
  auto fail = [&](std::string_view why) {
    throw InputError(at.file, at.line, fmt::format("{}: {}", kw, why));
  };
  auto axis = [&](const Vec3& a, const Vec3& b) {
    if (!((b - a).norm() > 0)) fail("the two end vertices coincide");
  };
  auto normal_of = [&](std::string_view name) {
    const Vec3 nv = vertex(name, at).n;
    if (!(nv.norm() > 0))
      fail(fmt::format("vertex '{}' has no normal (needed for the axis)", name));
    return nv;
  };
  if (kw == "sph") {
    need(t, 2, at, "sph vc radius");
    const Vec3 c = vertex(t[1], at).p;
    const double r = number(t[2], at, kw);
    if (r == 0) fail("the radius is zero");
    shape.a = c;
    shape.r0 = r;
    shape.radius = scale * std::abs(r);
    const Vec3 half = Vec3::Constant(shape.radius);
    Aabb box;
    box.extend(w * c - half);
    box.extend(w * c + half);
    defer_shape(std::move(shape), box, at);
  } else if (kw == "cyl" || kw == "cone") {
    const bool cyl = kw == "cyl";
    need(t, cyl ? 3 : 4, at, cyl ? "cyl v1 radius v2" : "cone v1 rad1 v2 rad2");
    const Vec3 a = vertex(t[1], at).p, b = vertex(t[3], at).p;
    const double ra = number(t[2], at, kw), rb = cyl ? ra : number(t[4], at, kw);
    if (ra == 0 && rb == 0) fail("both radii are zero");
    if ((ra < 0 && rb > 0) || (ra > 0 && rb < 0)) fail("the radii have opposite signs");
    axis(a, b);
    shape.a = a;
    shape.b = b;
    shape.r0 = ra;
    shape.r1 = rb;
    shape.radius = scale * std::max(std::abs(ra), std::abs(rb));
    const Vec3 dir = w.linear() * (b - a);
    Aabb box = circle_bounds(w * a, dir, scale * ra);
    box.extend(circle_bounds(w * b, dir, scale * rb));
    defer_shape(std::move(shape), box, at);
  } else if (kw == "ring" || kw == "torus") {
    need(t, 3, at, fmt::format("{} vc rmin rmax", kw));
    const Vec3 c = vertex(t[1], at).p;
    const double r0 = number(t[2], at, kw), r1 = number(t[3], at, kw);
    if (kw == "ring") {
      if (!(r0 >= 0 && r1 > r0)) fail("need 0 <= rmin < rmax");
      shape.n = normal_of(t[1]);
      shape.radius = scale * r1;
      const Aabb box = circle_bounds(w * c, w.linear() * shape.n, shape.radius);
      shape.a = c;
      shape.r0 = r0;
      shape.r1 = r1;
      defer_shape(std::move(shape), box, at);
    } else {
      if ((r0 < 0 && r1 > 0) || (r0 > 0 && r1 < 0) || !(std::abs(r1) > std::abs(r0)))
        fail("need |rmin| < |rmax| with the same sign (rmin may be 0)");
      shape.n = normal_of(t[1]);
      shape.radius = scale * std::abs(r1);
      const double big = 0.5 * scale * (std::abs(r1) + std::abs(r0));
      const double tube = 0.5 * scale * (std::abs(r1) - std::abs(r0));
      Aabb box = circle_bounds(w * c, w.linear() * shape.n, big);
      box.lo -= Vec3::Constant(tube);
      box.hi += Vec3::Constant(tube);
      shape.a = c;
      shape.r0 = r0;
      shape.r1 = r1;
      defer_shape(std::move(shape), box, at);
    }
  } else {  // prism v1 v2 v3 ... length
    if (t.size() < 5) fail("expected 'prism v1 v2 v3 ... length'");
    std::vector<Vec3> base;
    for (std::size_t i = 1; i + 1 < t.size(); ++i) base.push_back(vertex(t[i], at).p);
    const double len = number(t.back(), at, kw);
    if (len == 0) fail("the length is zero");
    if (!(polygon_area(base) > 0)) fail("the base polygon has zero area");
    const Vec3 off = -len * polygon_normal(base);
    Aabb box;
    for (const Vec3& p : base) {
      box.extend(w * p);
      box.extend(w * (p + off));
    }
    shape.base = std::move(base);
    shape.r0 = len;
    defer_shape(std::move(shape), box, at);
  }
}

Scene MgfParser::finish(const std::string& file) {
  // The polygons in file order, each shape tessellated now that the scene's diagonal
  // is known.
  const double diagonal = bounds_.diagonal();
  for (PendingPolygon& p : pending_) {
    const SourceLoc at{*p.file, p.line};
    if (p.shape < 0) {
      builder_.add_polygon(p.face, p.material, at);
      continue;
    }
    const PendingShape& s = shapes_[static_cast<std::size_t>(p.shape)];
    const int n = opt_.segments > 0 ? opt_.segments : automatic_segments(s.radius, diagonal);
    emit(tessellate(s, n), p.material, s.world, s.mirrored, at);
  }
  if (!unknown_.empty()) {
    std::size_t total = 0;
    std::string list;
    for (const auto& [kw, count] : unknown_) {
      total += count;
      if (list.size() < 80) list += fmt::format("{}{} ({})", list.empty() ? "" : ", ", kw, count);
    }
    builder_.warn(
        fmt::format("{} unknown MGF entit{} ignored: {}", total, total == 1 ? "y" : "ies", list));
  }
  if (specular_ignored_ > 0)
    builder_.warn(fmt::format("{} td/rs/ts value(s) ignored: hrad surfaces are ideal diffuse",
                              specular_ignored_));
  if (mapped_reflectance_ + mapped_emission_ > 0)
    builder_.warn(
        fmt::format("{} colour(s) outside the RGB gamut ({} reflectance, {} emission) "
                    "desaturated towards the grey of equal luminance (hue and "
                    "luminance kept)",
                    mapped_reflectance_ + mapped_emission_, mapped_reflectance_, mapped_emission_));
  if (negative_samples_ > 0)
    builder_.warn(
        fmt::format("{}:{}: {} small negative cspec value(s) taken as zero (the first "
                    "here; measured spectra carry noise around zero)",
                    first_negative_.file, first_negative_.line, negative_samples_));
  if (unmatched_o_ > 0 || object_depth_ > 0)
    builder_.warn(fmt::format("unbalanced objects: {} 'o' end(s) without a begin, {} never ended",
                              unmatched_o_, object_depth_));
  if (unclosed_xf_ > 0)
    builder_.warn(
        fmt::format("{} xf context(s) not ended in their file (closed there)", unclosed_xf_));
  return builder_.finish(file);
}

std::unique_ptr<Source> make_source(std::string path, fs::path dir, std::string owned,
                                    std::string_view text) {
  auto s = std::make_unique<Source>();
  s->path = std::move(path);
  s->dir = std::move(dir);
  s->owned = std::move(owned);
  s->text = s->owned.empty() ? text : std::string_view(s->owned);
  s->entities = split_entities(s->text);
  return s;
}

void check_options(const MgfOptions& o) {
  if (o.segments != 0 && (o.segments < 3 || o.segments > 4096))
    throw std::invalid_argument(fmt::format(
        "MgfOptions::segments {} is neither 0 (automatic) nor in [3, 4096]", o.segments));
  if (o.max_include_depth < 0 || o.max_array < 1 || o.max_repeat < 0 || o.max_work < 1 ||
      o.max_instances < 1)
    throw std::invalid_argument("MgfOptions: a limit is out of range");
}

}  // namespace

Scene read_mgf(const std::string& path, const MgfOptions& options) {
  check_options(options);
  std::error_code ec;
  std::ifstream in;
  if (fs::is_regular_file(path, ec)) in.open(path, std::ios::binary);
  if (!in.is_open()) throw InputError(path, 0, "cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  MgfParser p(fs::path(path).stem().string(), path, options);
  p.run_main(
      make_source(path, fs::path(path).parent_path(), checked_text(std::move(ss).str(), path), {}));
  return p.finish(path);
}

Scene parse_mgf(std::string_view text, const std::string& name_for_errors,
                const MgfOptions& options) {
  check_options(options);
  MgfParser p(fs::path(name_for_errors).stem().string(), name_for_errors, options);
  p.run_main(make_source(name_for_errors, fs::path(), {}, text));
  return p.finish(name_for_errors);
}

}  // namespace hrad
