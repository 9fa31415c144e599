#include "core/scene/camera_spec.h"

#include "core/base/input_error.h"
#include "core/base/input_file.h"
#include "core/base/json_input.h"
#include "core/base/parse_number.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace hrad {
namespace {

constexpr const char* kParts = "eye=X,Y,Z, look=X,Y,Z, up=X,Y,Z, fov=DEG";

std::vector<std::string_view> split(std::string_view text, char sep) {
  std::vector<std::string_view> parts;
  for (std::size_t start = 0;;) {
    const std::size_t at = text.find(sep, start);
    parts.push_back(text.substr(start, at == std::string_view::npos ? at : at - start));
    if (at == std::string_view::npos) return parts;
    start = at + 1;
  }
}

bool parallel(const Vec3& a, const Vec3& b) {
  // Each scaled by its largest part first: the products overflowed for an eye 1e200
  // away, and every view came out "parallel to the scene's up axis".
  const double sa = a.cwiseAbs().maxCoeff(), sb = b.cwiseAbs().maxCoeff();
  if (!(sa > 0) || !(sb > 0)) return true;
  const Vec3 x = a / sa, y = b / sb;
  return !(x.cross(y).norm() > 1e-9 * x.norm() * y.norm());
}

/// As far as a scene's own coordinates may reach (SceneBuilder).
constexpr double kMaxCameraCoordinate = 1e30;

/// What is wrong with a spec whose parts are each valid, or "" when nothing is.
std::string inconsistency(const CameraSpec& s) {
  for (const auto& [name, p] : {std::pair{"eye", s.eye}, std::pair{"look", s.look}})
    if (!(p.cwiseAbs().maxCoeff() <= kMaxCameraCoordinate))
      return fmt::format("{} ({:g},{:g},{:g}) is beyond +-1e30, as no scene's coordinates are",
                         name, p.x(), p.y(), p.z());
  if (s.look == s.eye) return "look is the same point as eye";
  if (s.up && parallel(*s.up, s.look - s.eye))
    return fmt::format("up ({:g},{:g},{:g}) is parallel to the view from eye to look", s.up->x(),
                       s.up->y(), s.up->z());
  return "";
}

std::string fov_error(double fov) {
  return fov > 0 && fov < 180
             ? ""
             : fmt::format("fov {:g} is outside (0, 180) degrees (the vertical field of view)",
                           fov);
}

}  // namespace

bool is_auto_camera(std::string_view text) { return text == "auto"; }

std::optional<int> automatic_camera_up(std::string_view text) {
  if (text.starts_with("auto:")) text.remove_prefix(5);
  if (!text.starts_with("up=") || text.find(':') != std::string_view::npos) return std::nullopt;
  const auto numbers = split(text.substr(3), ',');
  Vec3 v;
  bool ok = numbers.size() == 3;
  for (std::size_t i = 0; ok && i < 3; ++i)
    ok = parse_finite_number(numbers[i], v[static_cast<int>(i)]);
  if (!ok)
    throw std::invalid_argument(fmt::format("'{}' needs three numbers up=X,Y,Z", brief_text(text)));
  for (int axis = 0; axis < 3; ++axis)
    if (v[axis] > 0 && v[(axis + 1) % 3] == 0 && v[(axis + 2) % 3] == 0) return axis;
  throw std::invalid_argument(fmt::format(
      "the automatic camera takes up along +x, +y or +z (up=1,0,0, up=0,1,0 or up=0,0,1), "
      "not ({:g},{:g},{:g}); give eye and look as well for any other up",
      v.x(), v.y(), v.z()));
}

CameraSpec parse_camera_spec(std::string_view text) {
  if (text.empty()) throw std::invalid_argument(fmt::format("empty camera; give {}", kParts));
  CameraSpec s;
  bool have_eye = false, have_look = false;
  for (std::string_view part : split(text, ':')) {
    if (part.empty())
      throw std::invalid_argument(
          fmt::format("empty part (two ':' in a row, or one at an end); parts are {}", kParts));
    const std::size_t eq = part.find('=');
    const std::string name(part.substr(0, eq == std::string_view::npos ? part.size() : eq));
    if (eq == std::string_view::npos ||
        (name != "eye" && name != "look" && name != "up" && name != "fov"))
      throw std::invalid_argument(
          fmt::format("unknown part '{}'; parts are {}", brief_text(part), kParts));
    const std::string_view value = part.substr(eq + 1);
    const bool twice = (name == "eye" && have_eye) || (name == "look" && have_look) ||
                       (name == "up" && s.up) || (name == "fov" && s.fov_deg);
    if (twice) throw std::invalid_argument(fmt::format("{} is given twice", name));
    if (name == "fov") {
      double fov = 0;
      if (!parse_finite_number(value, fov))
        throw std::invalid_argument(
            fmt::format("'{}': '{}' is not a number", brief_text(part), brief_text(value)));
      if (const std::string e = fov_error(fov); !e.empty()) throw std::invalid_argument(e);
      s.fov_deg = fov;
      continue;
    }
    const auto numbers = split(value, ',');
    if (numbers.size() != 3)
      throw std::invalid_argument(fmt::format("'{}' needs three numbers {}=X,Y,Z, got {}",
                                              brief_text(part), name, numbers.size()));
    Vec3 v;
    for (int i = 0; i < 3; ++i)
      if (!parse_finite_number(numbers[i], v[i]))
        throw std::invalid_argument(fmt::format("'{}': '{}' is not a finite number",
                                                brief_text(part), brief_text(numbers[i])));
    if (name == "eye") {
      s.eye = v;
      have_eye = true;
    } else if (name == "look") {
      s.look = v;
      have_look = true;
    } else {
      if (v.isZero()) throw std::invalid_argument(fmt::format("'{}': up must not be zero", part));
      s.up = v;
    }
  }
  if (!have_eye) throw std::invalid_argument("no eye=X,Y,Z part");
  if (!have_look) throw std::invalid_argument("no look=X,Y,Z part");
  if (const std::string e = inconsistency(s); !e.empty()) throw std::invalid_argument(e);
  return s;
}

CameraSpec read_view_file(const std::filesystem::path& path) {
  const std::string file = path.string();
  check_input_file(path, "the view file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(file, 0, "cannot open the view file");
  std::ostringstream whole;
  whole << in.rdbuf();
  std::istringstream text(checked_text(std::move(whole).str(), file));
  CameraSpec s;
  int eye_line = 0, look_line = 0, up_line = 0, fov_line = 0;
  std::string line;
  for (int number = 1; std::getline(text, line); ++number) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword)) continue;
    std::vector<std::string> values;
    for (std::string w; words >> w;) values.push_back(w);
    int* seen = keyword == "eye"    ? &eye_line
                : keyword == "look" ? &look_line
                : keyword == "up"   ? &up_line
                : keyword == "fov"  ? &fov_line
                                    : nullptr;
    if (!seen)
      throw InputError(file, number,
                       fmt::format("unknown keyword '{}'; lines are 'eye X Y Z', 'look X Y Z', "
                                   "'up X Y Z', 'fov DEG'",
                                   brief_text(keyword)));
    if (*seen)
      throw InputError(file, number,
                       fmt::format("'{}' is given twice (first on line {})", keyword, *seen));
    *seen = number;
    const std::size_t want = keyword == "fov" ? 1 : 3;
    if (values.size() != want)
      throw InputError(file, number,
                       fmt::format("'{}' needs {} number{}, got {}", keyword, want,
                                   want == 1 ? "" : "s", values.size()));
    std::array<double, 3> v{};
    for (std::size_t i = 0; i < want; ++i)
      if (!parse_finite_number(values[i], v[i]))
        throw InputError(file, number,
                         fmt::format("'{}' is not a finite number", brief_text(values[i])));
    const Vec3 p(v[0], v[1], v[2]);
    if (keyword == "eye") {
      s.eye = p;
    } else if (keyword == "look") {
      s.look = p;
    } else if (keyword == "up") {
      if (p.isZero()) throw InputError(file, number, "up must not be zero");
      s.up = p;
    } else {
      if (const std::string e = fov_error(v[0]); !e.empty()) throw InputError(file, number, e);
      s.fov_deg = v[0];
    }
  }
  if (in.bad()) throw InputError(file, 0, "read error");
  if (!eye_line) throw InputError(file, 0, "no 'eye X Y Z' line");
  if (!look_line) throw InputError(file, 0, "no 'look X Y Z' line");
  if (const std::string e = inconsistency(s); !e.empty())
    throw InputError(file, std::max({eye_line, look_line, up_line}), e);
  return s;
}

Camera resolve_camera(const CameraSpec& spec, const Vec3& default_up) {
  Camera c;
  c.eye = spec.eye;
  c.target = spec.look;
  c.up = spec.up.value_or(default_up);
  c.fov_y_deg = spec.fov_deg.value_or(kDefaultFovDeg);
  if (!spec.up && parallel(c.up, c.target - c.eye))
    throw std::invalid_argument(
        fmt::format("the view from eye to look is parallel to the scene's up axis "
                    "({:g},{:g},{:g}); give up=X,Y,Z",
                    c.up.x(), c.up.y(), c.up.z()));
  return c;
}

std::string camera_spec_string(const Camera& c) {
  // fmt's "{}" writes the shortest text that reads back as the same double.
  const auto v = [](const Vec3& p) { return fmt::format("{},{},{}", p.x(), p.y(), p.z()); };
  return fmt::format("eye={}:look={}:up={}:fov={}", v(c.eye), v(c.target), v(c.up), c.fov_y_deg);
}

}  // namespace hrad
