// Error metrics: see error_metrics.h.
#include "core/reference/error_metrics.h"

#include "core/base/hash.h"
#include "core/base/input_error.h"
#include "core/base/input_file.h"
#include "core/base/median.h"
#include "core/raycast/ray_scene.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

namespace hrad {

namespace {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::size_t at = 0;
  for (;;) {
    const std::size_t comma = line.find(',', at);
    std::string f = line.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
    while (!f.empty() && (f.back() == ' ' || f.back() == '\r' || f.back() == '\t')) f.pop_back();
    while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.erase(0, 1);
    out.push_back(std::move(f));
    if (comma == std::string::npos) return out;
    at = comma + 1;
  }
}

double parse_field(const std::string& f, const std::string& column, const std::string& file,
                   int line) {
  double v = 0;
  const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
  if (ec != std::errc() || end != f.data() + f.size() || !std::isfinite(v))
    throw InputError(file, line, fmt::format("column {}: '{}' is not a finite number", column, f));
  return v;
}

/// A mesh as a RayScene plus the per-polygon data the lookups need.
struct MeshLookup {
  const RenderMesh& mesh;
  std::vector<std::uint32_t> indices;
  std::vector<PolygonRange> ranges;
  std::vector<Vec3> normals;
  std::vector<double> areas;
  std::optional<RayScene> rays;

  explicit MeshLookup(const RenderMesh& m) : mesh(m) {
    for (const auto& q : m.polys) {
      const std::uint32_t k = RenderMesh::is_triangle(q) ? 3 : 4;
      ranges.push_back({static_cast<std::uint32_t>(indices.size()), k});
      std::vector<Vec3> pts;
      for (std::uint32_t j = 0; j < k; ++j) {
        indices.push_back(q[j]);
        pts.push_back(m.positions[q[j]]);
      }
      const Vec3 a = vector_area(pts);
      areas.push_back(a.norm());
      normals.push_back(a.norm() > 0 ? Vec3(a / a.norm()) : Vec3::Zero());
    }
    rays.emplace(m.positions, indices, ranges);
  }

  /// Interpolated radiosity at the polygon found below p + delta n (facing n).
  std::optional<Rgb> at(const Vec3& p, const Vec3& n, double delta) const {
    const auto hit = rays->intersect(p + delta * n, -n, 2 * delta);
    if (!hit || normals[hit->prim].dot(n) < 0.5) return std::nullopt;
    const auto& q = mesh.polys[hit->prim];
    const auto& b = mesh.radiosity;
    const double u = hit->u, v = hit->v;
    if (RenderMesh::is_triangle(q)) return Rgb((1 - u - v) * b[q[0]] + u * b[q[1]] + v * b[q[2]]);
    return Rgb((1 - u) * (1 - v) * b[q[0]] + u * (1 - v) * b[q[1]] + u * v * b[q[2]] +
               (1 - u) * v * b[q[3]]);
  }
};

double uniform(std::uint64_t& s) { return static_cast<double>(splitmix64(s) >> 11) * 0x1.0p-53; }

}  // namespace

ProbeTable parse_probe_table(const std::string& text, const std::string& file) {
  ProbeTable t;
  t.file = file;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  std::map<std::string, std::size_t> col;
  std::size_t fields = 0;
  const char* required[] = {"x", "y", "z", "nx", "ny", "nz", "E_r", "E_g", "E_b"};
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> f = split_csv(line);
    if (col.empty()) {
      for (std::size_t k = 0; k < f.size(); ++k) col[f[k]] = k;
      for (const char* r : required)
        if (!col.count(r))
          throw InputError(file, line_no,
                           fmt::format("header has no column '{}' (expected x,y,z,nx,ny,nz,"
                                       "E_r,E_g,E_b as probes.csv)",
                                       r));
      fields = f.size();
      continue;
    }
    if (f.size() != fields)
      throw InputError(file, line_no,
                       fmt::format("{} fields, the header has {}", f.size(), fields));
    const auto num = [&](const char* c) { return parse_field(f[col.at(c)], c, file, line_no); };
    Probe p;
    p.p = Vec3(num("x"), num("y"), num("z"));
    p.n = Vec3(num("nx"), num("ny"), num("nz"));
    t.probes.push_back(p);
    t.irradiance.emplace_back(num("E_r"), num("E_g"), num("E_b"));
    if (col.count("SE_r") && col.count("SE_g") && col.count("SE_b"))
      t.std_error.emplace_back(num("SE_r"), num("SE_g"), num("SE_b"));
  }
  if (col.empty()) throw InputError(file, 0, "empty file (no header)");
  return t;
}

ProbeTable read_probe_table(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::path file =
      std::filesystem::is_directory(path, ec) ? path / "probes.csv" : path;
  check_input_file(file, "the probe table");
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), 0, "cannot open the file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_probe_table(checked_text(ss.str(), file.string()), file.string());
}

ProbeComparison compare_probes(const ProbeTable& a, const ProbeTable& r, double floor) {
  if (a.probes.size() != r.probes.size())
    throw std::invalid_argument(
        fmt::format("{} has {} probes but {} has {}: not the same probe set", a.file,
                    a.probes.size(), r.file, r.probes.size()));
  if (r.probes.empty()) throw std::invalid_argument(fmt::format("{}: no probes", r.file));
  Aabb box;
  for (const Probe& p : r.probes) box.extend(p.p);
  const double tol = 1e-6 * std::max(box.diagonal(), box.hi.cwiseAbs().maxCoeff()) + 1e-300;
  for (std::size_t i = 0; i < r.probes.size(); ++i)
    if ((a.probes[i].p - r.probes[i].p).norm() > tol ||
        (a.probes[i].n - r.probes[i].n).norm() > 1e-6)
      throw std::invalid_argument(
          fmt::format("probe {} (data row {}) differs between {} and {}: not the same probe set", i,
                      i + 1, a.file, r.file));

  ProbeComparison c;
  c.has_se = !r.std_error.empty();
  double mean_ref = 0;
  for (const Rgb& e : r.irradiance) mean_ref += e.abs().sum() / 3;
  mean_ref /= static_cast<double>(r.irradiance.size());
  c.floor = floor > 0 ? floor : 1e-3 * mean_ref;
  // A reference that is zero everywhere gives no scale: relative errors were inf and nan.
  if (!(c.floor > 0))
    throw std::invalid_argument(fmt::format(
        "{}: the reference irradiance is zero at every probe, so relative errors are "
        "undefined; give an absolute floor (--floor X, in the scene's irradiance units)",
        r.file));
  double sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < r.probes.size(); ++i) {
    ProbeError e;
    e.result = a.irradiance[i];
    e.reference = r.irradiance[i];
    const Rgb diff = (e.result - e.reference).abs();
    e.rel_error = (diff / e.reference.abs().max(c.floor)).maxCoeff();
    if (c.has_se) {
      e.z = 0;
      for (int k = 0; k < 3; ++k) {
        const double se = r.std_error[i][k];
        e.z = std::max(e.z, se > 0 ? diff[k] / se
                                   : (diff[k] > 0 ? std::numeric_limits<double>::infinity() : 0.0));
      }
      if (e.z <= 2) ++c.within_2se;
    }
    e.signed_error =
        (e.result.mean() - e.reference.mean()) / std::max(std::abs(e.reference.mean()), c.floor);
    c.bias += e.signed_error;
    if (e.signed_error < 0) ++c.low;
    sum += e.rel_error;
    sum2 += e.rel_error * e.rel_error;
    if (e.rel_error > c.max) {
      c.max = e.rel_error;
      c.worst = i;
    }
    c.probes.push_back(e);
  }
  const auto n = static_cast<double>(c.probes.size());
  c.mean = sum / n;
  c.rms = std::sqrt(sum2 / n);
  c.bias /= n;
  std::vector<double> errors;
  for (const ProbeError& e : c.probes) errors.push_back(e.rel_error);
  c.median = median(std::move(errors));
  return c;
}

SurfaceComparison compare_surfaces(const RenderMesh& result, const RenderMesh& reference,
                                   std::size_t samples, std::uint64_t seed) {
  if (result.polys.empty() || reference.polys.empty())
    throw std::invalid_argument("compare_surfaces: a mesh has no polygon");
  const MeshLookup a(result), r(reference);
  SurfaceComparison s;
  for (double x : a.areas) s.area_result += x;
  for (double x : r.areas) s.area_reference += x;
  if (std::abs(s.area_result - s.area_reference) > 0.01 * s.area_reference)
    throw std::invalid_argument(
        fmt::format("the meshes cover different areas ({:.6g} and {:.6g}): not the same scene",
                    s.area_result, s.area_reference));
  const double delta = 1e-4 * std::max(a.rays->scale(), r.rays->scale());

  Rgb sum_abs = Rgb::Zero(), sum_sq = Rgb::Zero(), sum_ref = Rgb::Zero();
  double weight = 0;
  std::uint64_t state = seed;
  for (std::size_t i = 0; i < reference.polys.size(); ++i) {
    const double area = r.areas[i];
    if (!(area > 0)) continue;
    const auto& q = reference.polys[i];
    const auto k = static_cast<std::size_t>(
        std::max(1.0, std::ceil(static_cast<double>(samples) * area / s.area_reference)));
    const Vec3& p0 = reference.positions[q[0]];
    const Vec3& p1 = reference.positions[q[1]];
    const Vec3& p2 = reference.positions[q[2]];
    const bool tri = RenderMesh::is_triangle(q);
    const double a012 = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    for (std::size_t j = 0; j < k; ++j) {
      // Uniform by area: triangle (0,1,2), or for a quad (0,2,3) with its share.
      Vec3 b = p1, c = p2;
      if (!tri && uniform(state) * area >= a012) {
        b = p2;
        c = reference.positions[q[3]];
      }
      const double su = std::sqrt(uniform(state)), t = uniform(state);
      const Vec3 p = (1 - su) * p0 + su * (1 - t) * b + su * t * c;
      ++s.samples;
      const auto va = a.at(p, r.normals[i], delta);
      const auto vr = r.at(p, r.normals[i], delta);
      if (!va || !vr) {
        ++s.unmatched;
        continue;
      }
      const double w = area / static_cast<double>(k);
      const Rgb d = *va - *vr;
      sum_abs += w * d.abs();
      sum_sq += w * d.square();
      sum_ref += w * vr->abs();
      weight += w;
    }
  }
  if (!(weight > 0)) throw std::invalid_argument("compare_surfaces: no sample point matched");
  s.reference_mean = sum_ref / weight;
  const Rgb ref = sum_ref.max(1e-300);
  s.l1 = sum_abs / ref;
  s.l2 = (sum_sq / weight).sqrt() / (ref / weight);
  s.l1_all = sum_abs.sum() / std::max(sum_ref.sum(), 1e-300);
  // Channel means of the squared difference and of the reference.
  s.l2_all =
      std::sqrt(sum_sq.sum() / (3 * weight)) / std::max(sum_ref.sum() / (3 * weight), 1e-300);
  return s;
}

}  // namespace hrad
