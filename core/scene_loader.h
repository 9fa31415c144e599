// One entry point for every scene the tools accept, chosen by the spec's form:
//   "builtin:NAME..."  -> make_builtin(spec)   (core/builtin_scenes.h)
//   "*.obj"            -> read_obj(path)       (core/obj_reader.h; Ke is radiance)
//   "*.mgf"            -> read_mgf(path)       (core/mgf_reader.h)
// Extensions are compared case-insensitively. Anything else is an InputError.
#pragma once

#include <string>

#include "core/scene.h"

namespace hrad {

Scene load_scene(const std::string& spec);

}  // namespace hrad
