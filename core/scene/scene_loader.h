// One entry point for every scene the tools accept, chosen by the spec's form:
//   "builtin:NAME..."  -> make_builtin(spec)   (core/scene/builtin_scenes.h)
//   "*.obj"            -> read_obj(path)       (core/scene/obj_reader.h; Ke is radiance)
//   "*.mgf"            -> read_mgf(path)       (core/scene/mgf/mgf_reader.h)
// Extensions are compared case-insensitively. Anything else is an InputError.
// Then add_back_faces (core/scene/back_faces.h) applies the `sides` and `emitter_sides`
// options to every scene.
#pragma once

#include <string>

#include "core/scene/back_faces.h"
#include "core/scene/scene.h"

namespace hrad {

/// The options that shape the scene itself: the `sides`, `emitter_sides` and `segments`
/// keys.
struct SceneLoadOptions {
  Sides sides = Sides::Auto;
  int segments = 0;  ///< MgfOptions::segments (0: automatic)
  EmitterSides emitter_sides = EmitterSides::Front;
  bool operator==(const SceneLoadOptions&) const = default;
};

Scene load_scene(const std::string& spec, const SceneLoadOptions& options = {});

/// Throws the InputError load_scene(spec) would throw for what can be told without
/// reading the scene: an unknown builtin scene or parameter, an unknown format, a file
/// that does not exist. For checking a list of scenes before any work starts.
void check_scene_spec(const std::string& spec);

}  // namespace hrad
