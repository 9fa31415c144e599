#include "core/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "core/builtin_scenes.h"
#include "core/input_error.h"
#include "core/mgf_reader.h"
#include "core/obj_reader.h"

namespace hrad {

Scene load_scene(const std::string& spec) {
  // Every "builtin:" spec goes to make_builtin, so an unknown builtin name gets its
  // own message rather than "unknown format".
  if (spec.starts_with("builtin:")) return make_builtin(spec);
  std::string ext = std::filesystem::path(spec).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".obj") return read_obj(spec);
  if (ext == ".mgf") return read_mgf(spec);
  throw InputError(spec, 0,
                   "unknown scene format '" + ext + "' (expected .obj, .mgf or builtin:NAME)");
}

}  // namespace hrad
