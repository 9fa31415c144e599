// Built-in procedural scenes, named by a spec string:
//
//   builtin:NAME                 e.g. builtin:cornell
//   builtin:NAME,k=v,k=v         e.g. builtin:office,desks=40,lights=6
//   builtin:NAME?k=v&k=v         e.g. 'builtin:office?desks=40&lights=6' (quoted: the
//                                shell would end the command at '&')
//
// Every scene is a pure function of its spec (no global random state): the same spec
// gives a bit-identical Scene. Units are metres, y is up; Material::emission is
// exitance in W/m². Rooms face inward, objects outward (see core/scene/builtin/shapes.h).
//
// Scenes (each file in core/scene/builtin/ opens with its parameter table):
//   cornell   the classic Cornell box, open front                  ~16 polygons
//   furnace   closed room + closed objects, one material (analytic)  20 polygons
//   office    desks, chairs, monitors, shelves, ceiling lights    ~5,000 polygons
//   lab       two floors with a stair void, many tiny patches    ~30,000 polygons
//   cabin     aircraft-cabin tube, all small triangles          ~186,000 triangles
#pragma once

#include "core/scene/scene.h"

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace hrad {

struct BuiltinParam {
  std::string name;
  double default_value = 0;
  double min_value = 0;
  double max_value = 0;
  std::string meaning;
  bool integer = false;
};

struct BuiltinInfo {
  std::string name;
  std::string description;
  std::vector<BuiltinParam> params;
};

/// Every built-in scene with its parameters, in a fixed order (for `hrad scenes`).
const std::vector<BuiltinInfo>& builtin_scenes();

/// True when `spec` names a built-in scene ("builtin:..."), valid or not.
bool is_builtin_spec(std::string_view spec);

/// "builtin:NAME" for a builtin spec with or without parameters; any other spec as it is.
std::string builtin_base(std::string_view spec);

/// A builtin spec in the comma form (builtin:office?desks=4&lights=2 ->
/// builtin:office,desks=4,lights=2), for telling whether two specs name the same scene;
/// any other spec as it is.
std::string normal_builtin_spec(std::string_view spec);

/// A comma-separated list of scene specs, where the comma-form parameters stay with
/// their builtin scene: "builtin:cornell,blocks=0,room.obj,builtin:office" ->
/// {"builtin:cornell,blocks=0", "room.obj", "builtin:office"}. A piece "name=value"
/// after a builtin spec is one of its parameters; empty pieces are dropped.
std::vector<std::string> split_scene_list(std::string_view list);

/// Builds the scene named by `spec`. Throws InputError (file = spec, line 0) for an
/// unknown scene or parameter, a value that is not a number, not an integer where one
/// is required, or outside the parameter's [min, max].
Scene make_builtin(const std::string& spec);

/// Throws what make_builtin(spec) would for a bad spec, without building the scene.
void check_builtin_spec(const std::string& spec);

namespace builtin {

/// The parsed parameters of one spec: every declared parameter, given or defaulted.
class Args {
 public:
  Args(std::string spec, std::map<std::string, double> values)
      : spec_(std::move(spec)), values_(std::move(values)) {}
  [[nodiscard]] const std::string& spec() const { return spec_; }
  /// The value of a declared parameter (std::logic_error for an undeclared name:
  /// that is a bug in the scene, not bad input).
  [[nodiscard]] double get(const std::string& name) const;
  [[nodiscard]] int get_int(const std::string& name) const;

 private:
  std::string spec_;
  std::map<std::string, double> values_;
};

// One generator and one description per scene, defined in core/scene/builtin/NAME.cpp.
BuiltinInfo cornell_info();
Scene make_cornell(const Args& args);
BuiltinInfo furnace_info();
Scene make_furnace(const Args& args);
BuiltinInfo office_info();
Scene make_office(const Args& args);
BuiltinInfo lab_info();
Scene make_lab(const Args& args);
BuiltinInfo cabin_info();
Scene make_cabin(const Args& args);

}  // namespace builtin
}  // namespace hrad
