#include "core/scene/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include <fmt/format.h>

#include "core/base/input_error.h"
#include "core/scene/builtin_scenes.h"
#include "core/scene/mgf/mgf_reader.h"
#include "core/scene/obj_reader.h"

namespace hrad {

namespace {

/// " (did you mean builtin:NAME?)" when the spec, without its folder, extension and
/// parameters, is the name of a built-in scene ("cornell", "office.obj"), else "".
std::string builtin_hint(const std::string& spec) {
  const std::size_t q = spec.find_first_of(",?");
  const std::string name = std::filesystem::path(spec.substr(0, q)).stem().string();
  const std::string params = q == std::string::npos ? "" : spec.substr(q);
  for (const BuiltinInfo& b : builtin_scenes())
    if (b.name == name) return fmt::format(" (did you mean builtin:{}{}?)", name, params);
  return "";
}

/// The file extension, lower case; throws for one that is not a scene format.
std::string scene_format(const std::string& spec) {
  std::string ext = std::filesystem::path(spec.substr(0, spec.find('?'))).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".obj" && ext != ".mgf")
    throw InputError(spec, 0,
                     "unknown scene format '" + ext + "' (expected .obj, .mgf or builtin:NAME)" +
                         builtin_hint(spec));
  return ext;
}

}  // namespace

Scene load_scene(const std::string& spec, const SceneLoadOptions& options) {
  // Every "builtin:" spec goes to make_builtin, so an unknown builtin name gets its
  // own message rather than "unknown format".
  Scene scene;
  if (spec.starts_with("builtin:")) {
    scene = make_builtin(spec);
  } else if (check_scene_spec(spec), scene_format(spec) == ".obj") {
    scene = read_obj(spec);
  } else {
    MgfOptions mgf;
    mgf.segments = options.segments;
    scene = read_mgf(spec, mgf);
  }
  add_back_faces(scene, options.sides, options.emitter_sides);
  return scene;
}

void check_scene_spec(const std::string& spec) {
  if (spec.starts_with("builtin:")) return check_builtin_spec(spec);
  scene_format(spec);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(spec, ec))
    throw InputError(spec, 0,
                     std::filesystem::exists(spec, ec)
                         ? "the file is not a regular file"
                         : "the file does not exist" + builtin_hint(spec));
}

}  // namespace hrad
