// MGF transform-argument parsing and array instances; see mgf_xform.h.
#include "core/scene/mgf/mgf_xform.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <numbers>

namespace hrad {

namespace {

Affine power(const Affine& m, long k) {
  Affine result = Affine::Identity(), base = m;
  while (k > 0) {
    if (k & 1) result = result * base;
    base = base * base;
    k >>= 1;
  }
  return result;
}

Affine rotation(int axis, double degrees) {
  const double rad = degrees * std::numbers::pi / 180.0;
  return Affine(Eigen::AngleAxisd(rad, Vec3::Unit(axis)));
}

Affine mirror(int axis) {
  Affine m = Affine::Identity();
  m(axis, axis) = -1.0;
  return m;
}

std::string_view strip_plus(std::string_view tok) {
  if (tok.size() > 1 && tok[0] == '+' && tok[1] != '-' && tok[1] != '+') tok.remove_prefix(1);
  return tok;
}

}  // namespace

double parse_mgf_number(std::string_view tok, const SourceLoc& at, std::string_view what) {
  const std::string_view t = strip_plus(tok);
  double v = 0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || ptr != t.data() + t.size())
    throw InputError(at.file, at.line, fmt::format("{}: '{}' is not a number", what, tok));
  if (!std::isfinite(v))
    throw InputError(at.file, at.line, fmt::format("{}: '{}' is not a finite number", what, tok));
  return v;
}

long parse_mgf_integer(std::string_view tok, long lo, long hi, const SourceLoc& at,
                       std::string_view what) {
  const std::string_view t = strip_plus(tok);
  long v = 0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || ptr != t.data() + t.size())
    throw InputError(at.file, at.line, fmt::format("{}: '{}' is not an integer", what, tok));
  if (v < lo || v > hi)
    throw InputError(at.file, at.line, fmt::format("{}: {} is outside [{}, {}]", what, v, lo, hi));
  return v;
}

bool XfSpec::has_array() const { return array_dims() > 0; }

std::size_t XfSpec::array_dims() const {
  std::size_t n = 0;
  for (const XfGroup& g : groups) n += g.array ? 1 : 0;
  return n;
}

Affine XfSpec::instance(std::span<const long> index) const {
  Affine t = Affine::Identity();
  std::size_t a = 0;
  for (const XfGroup& g : groups) t = power(g.m, g.array ? index[a++] : g.count) * t;
  return t;
}

XfSpec parse_xf(std::span<const std::string_view> args, const SourceLoc& at, const XfLimits& lim) {
  XfSpec spec;
  spec.groups.emplace_back();
  std::size_t i = 0;
  auto value = [&](std::string_view opt) -> std::string_view {
    if (i >= args.size())
      throw InputError(at.file, at.line, fmt::format("transform option {} needs a value", opt));
    return args[i++];
  };
  auto number = [&](std::string_view opt) {
    return parse_mgf_number(value(opt), at, fmt::format("transform {}", opt));
  };
  while (i < args.size()) {
    const std::string_view opt = args[i++];
    Affine step = Affine::Identity();
    if (opt == "-t") {
      const double x = number(opt), y = number(opt), z = number(opt);
      step = Affine(Eigen::Translation3d(x, y, z));
    } else if (opt == "-rx" || opt == "-ry" || opt == "-rz") {
      step = rotation(opt[2] - 'x', number(opt));
    } else if (opt == "-s") {
      const double s = number(opt);
      if (s == 0) throw InputError(at.file, at.line, "transform -s: scale factor is zero");
      step = Affine(Eigen::Scaling(s));
    } else if (opt == "-mx" || opt == "-my" || opt == "-mz") {
      step = mirror(opt[2] - 'x');
    } else if (opt == "-i" || opt == "-a") {
      XfGroup g;
      g.array = opt == "-a";
      g.count = g.array ? parse_mgf_integer(value(opt), 1, lim.max_array, at, "transform -a")
                        : parse_mgf_integer(value(opt), 0, lim.max_repeat, at, "transform -i");
      spec.groups.push_back(g);
      continue;
    } else {
      throw InputError(at.file, at.line, fmt::format("unknown transform option '{}'", opt));
    }
    spec.groups.back().m = step * spec.groups.back().m;
  }
  return spec;
}

}  // namespace hrad
