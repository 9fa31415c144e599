#include "core/scene/probes.h"

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"
#include "core/base/input_file.h"
#include "core/scene/scene.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace hrad {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// Splits a line (comment already removed) into blank-separated fields.
std::vector<std::string_view> fields_of(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

}  // namespace

std::vector<Probe> parse_probes(const std::string& text, const std::string& file) {
  std::vector<Probe> probes;
  std::string_view rest = text;
  int line_no = 0;
  while (!rest.empty()) {
    ++line_no;
    const std::size_t eol = rest.find('\n');
    std::string_view line = rest.substr(0, eol);
    rest = eol == std::string_view::npos ? std::string_view{} : rest.substr(eol + 1);
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    const auto fields = fields_of(line);
    if (fields.empty()) continue;
    if (fields.size() != 6)
      throw InputError(
          file, line_no,
          fmt::format("expected 6 numbers (x y z nx ny nz), found {} fields", fields.size()));
    std::array<double, 6> x{};
    for (std::size_t k = 0; k < 6; ++k) {
      const std::string_view f = fields[k];
      // from_chars rejects a leading '+'; accept it as people write it.
      const char* first = f.data() + (f.size() > 1 && f[0] == '+' ? 1 : 0);
      const char* last = f.data() + f.size();
      const auto [end, ec] = std::from_chars(first, last, x[k]);
      if (ec == std::errc::result_out_of_range)
        throw InputError(file, line_no,
                         fmt::format("field {} '{}' is out of double range", k + 1, f));
      if (ec != std::errc{} || end != last)
        throw InputError(file, line_no, fmt::format("field {} '{}' is not a number", k + 1, f));
      if (!std::isfinite(x[k]))
        throw InputError(file, line_no, fmt::format("field {} '{}' is not finite", k + 1, f));
    }
    Probe pr;
    pr.p = Vec3(x[0], x[1], x[2]);
    const Vec3 n(x[3], x[4], x[5]);
    const double len = n.stableNorm();
    if (!(len > 0) || !std::isfinite(len))
      throw InputError(file, line_no, "the normal (fields 4-6) is zero");
    pr.n = n / len;
    probes.push_back(pr);
  }
  return probes;
}

std::vector<Probe> read_probes(const std::string& path) {
  check_input_file(path, "the probe file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open the probe file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "error while reading the probe file");
  return parse_probes(checked_text(text.str(), path), path);
}

std::vector<Probe> random_surface_probes(const Scene& scene, std::size_t n, std::uint64_t seed) {
  if (n == 0) return {};
  // Triangles of every face (a fan from vertex 0: faces are convex), with their
  // cumulative areas.
  struct Tri {
    Vec3 a, b, c, normal;
  };
  std::vector<Tri> tris;
  std::vector<double> cumulative;
  double total = 0;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const std::vector<Vec3> p = scene.face_vertices(f);
    const Vec3 normal = scene.face_normal(f);
    for (std::size_t k = 1; k + 1 < p.size(); ++k) {
      const double a = 0.5 * (p[k] - p[0]).cross(p[k + 1] - p[0]).norm();
      if (!(a > 0)) continue;
      tris.push_back({p[0], p[k], p[k + 1], normal});
      total += a;
      cumulative.push_back(total);
    }
  }
  if (tris.empty()) throw std::invalid_argument("random probes: the scene has no surface area");
  const double lift = 1e-6 * scene.bounds().diagonal();
  std::mt19937_64 rng(seed ^ 0x5851F42D4C957F2Dull);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Probe> probes;
  probes.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = u(rng) * total;
    const std::size_t t = std::min<std::size_t>(
        static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), x) -
                                 cumulative.begin()),
        tris.size() - 1);
    double s = u(rng), v = u(rng);
    if (s + v > 1) {
      s = 1 - s;
      v = 1 - v;
    }
    const Tri& tri = tris[t];
    Probe pr;
    pr.n = tri.normal;
    pr.p = tri.a + s * (tri.b - tri.a) + v * (tri.c - tri.a) + lift * tri.normal;
    probes.push_back(pr);
  }
  return probes;
}

std::string probes_text(const std::vector<Probe>& probes, const std::string& comment) {
  std::string out = comment.empty() ? "" : "# " + comment + "\n";
  for (const Probe& pr : probes)
    out += fmt::format("{:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g}\n", pr.p[0], pr.p[1], pr.p[2],
                       pr.n[0], pr.n[1], pr.n[2]);
  return out;
}

std::string probes_csv(const std::vector<Probe>& probes, const std::vector<Rgb>& irradiance) {
  if (probes.size() != irradiance.size())
    throw std::invalid_argument(fmt::format("probes_csv: {} probes but {} irradiance values",
                                            probes.size(), irradiance.size()));
  for (std::size_t i = 0; i < irradiance.size(); ++i)
    if (!irradiance[i].allFinite())
      throw std::invalid_argument(
          fmt::format("probes_csv: probe {} has a non-finite irradiance", i + 1));
  std::string out = "x,y,z,nx,ny,nz,E_r,E_g,E_b\n";
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Vec3& p = probes[i].p;
    const Vec3& n = probes[i].n;
    const Rgb& e = irradiance[i];
    out += fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", p[0],
                       p[1], p[2], n[0], n[1], n[2], e[0], e[1], e[2]);
  }
  return out;
}

void write_probes_csv(const std::filesystem::path& path, const std::vector<Probe>& probes,
                      const std::vector<Rgb>& irradiance) {
  write_file_atomically(path, probes_csv(probes, irradiance));
}

}  // namespace hrad
