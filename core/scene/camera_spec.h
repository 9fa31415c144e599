// Cameras written as text: the `--camera` option and `camera` configuration key, and
// the `--view` file. Both name the same four things; docs/cli.md, "The camera".
//
// Spec (one line):  eye=X,Y,Z:look=X,Y,Z[:up=X,Y,Z][:fov=DEG]
//   parts separated by ':', in any order, each at most once; eye and look required.
//   The single word "auto" asks for the automatic camera (core/output/auto_camera.h);
//   "up=X,Y,Z" alone (or "auto:up=X,Y,Z") asks for it with that up axis.
// View file:  one "keyword numbers" per line, whitespace-separated:
//   eye X Y Z / look X Y Z / up X Y Z / fov DEG; blank lines and '#' comments ignored.
// Defaults: up = the scene's up axis (Scene::up_axis: +y, or +z for z-up scenes),
// fov = kDefaultFovDeg (vertical, degrees). Coordinates are in scene units.
#pragma once

#include "core/base/geometry.h"
#include "core/scene/scene.h"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace hrad {

inline constexpr double kDefaultFovDeg = 60.0;

/// A camera as given: up and fov may be left to the scene's defaults.
struct CameraSpec {
  Vec3 eye = Vec3::Zero();
  Vec3 look = Vec3::Zero();
  std::optional<Vec3> up;
  std::optional<double> fov_deg;
};

/// True for the word "auto".
[[nodiscard]] bool is_auto_camera(std::string_view text);

/// The automatic camera with a given up axis: for "up=X,Y,Z" or "auto:up=X,Y,Z", the
/// axis (0, 1 or 2) that X,Y,Z points along; nullopt for any other text. Throws
/// std::invalid_argument when X,Y,Z is not +x, +y or +z (the automatic camera looks
/// along the other two).
[[nodiscard]] std::optional<int> automatic_camera_up(std::string_view text);

/// Parses a spec (not "auto"). Throws std::invalid_argument whose message names the
/// bad part: "'eye=1,2' needs three numbers x,y,z", "unknown part 'pos=1,2,3' ...",
/// "no look=X,Y,Z part", "look is the same point as eye", ...
[[nodiscard]] CameraSpec parse_camera_spec(std::string_view text);

/// Reads a view file. Throws InputError naming the file and, where there is one, the
/// line: "room.view:3: 'eye' needs three numbers, got 2".
[[nodiscard]] CameraSpec read_view_file(const std::filesystem::path& path);

/// The camera with up and fov filled in (default_up when none is given). Throws
/// std::invalid_argument when the view direction is parallel to the default up.
[[nodiscard]] Camera resolve_camera(const CameraSpec& spec, const Vec3& default_up);

/// The spec of a camera, "eye=...:look=...:up=...:fov=...", its numbers written so that
/// they read back exactly: parse_camera_spec of it gives the camera again.
[[nodiscard]] std::string camera_spec_string(const Camera& cam);

}  // namespace hrad
