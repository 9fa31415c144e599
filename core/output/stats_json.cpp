#include "core/output/stats_json.h"

#include "core/base/atomic_file.h"
#include "core/output/stat_fields.h"
#include "core/scene/camera_spec.h"

#include <cmath>
#include <filesystem>
#include <ostream>
#include <system_error>

namespace hrad {
namespace {

// JSON has no NaN or infinity; nlohmann would write them as null anyway, but say so.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; }

template <class V>
nlohmann::json json_map(const std::map<std::string, V>& m) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : m) {
    if constexpr (std::is_floating_point_v<V>)
      j[k] = number(v);
    else
      j[k] = v;
  }
  return j;
}

nlohmann::json refiners_json(const std::vector<RefinerStats>& refiners) {
  nlohmann::json out = nlohmann::json::array();
  for (const RefinerStats& r : refiners)
    out.push_back({{"tasks", r.tasks},
                   {"takes", r.takes},
                   {"submits", r.submits},
                   {"busy_s", number(r.busy_s)},
                   {"idle_s", number(r.idle_s)},
                   {"cpu_s", number(r.cpu_s)},
                   {"link_bytes", r.link_bytes},
                   {"lock_wait_s", number(r.lock_wait_s)},
                   {"rays_cast", r.rays_cast},
                   {"node", r.node},
                   {"pus", r.pus},
                   {"bound", r.bound},
                   {"tasks_local", r.tasks_local},
                   {"tasks_remote", r.tasks_remote}});
  return out;
}

nlohmann::json effect_json(const Effect& e) { return {{"on", e.on}, {"reason", e.reason}}; }

nlohmann::json field_json(const FieldValue& v) {
  return v.integer ? nlohmann::json(v.count) : number(v.real);
}

nlohmann::json iteration_json(const IterationStats& it) {
  nlohmann::json j = {
      {"bytes", json_map(it.bytes)},
      {"lock_wait_s", json_map(it.lock_wait_s)},
      {"refiners", refiners_json(it.refiners)},
      {"bytes_per_node", it.bytes_per_node},
      {"element_bytes_per_node", it.element_bytes_per_node},
      {"link_bytes_per_node", it.link_bytes_per_node},
      {"placement_check", it.placement_check.checked
                              ? nlohmann::json{{"pages", it.placement_check.pages},
                                               {"agree", it.placement_check.agree},
                                               {"unknown", it.placement_check.unknown}}
                              : nlohmann::json(nullptr)},
  };
  for (const IterationField& f : iteration_fields())
    if (f.path) j[nlohmann::json::json_pointer(std::string("/") + f.path)] = field_json(f.get(it));
  return j;
}

nlohmann::json totals_json(const RunStats& stats) {
  const IterationTotals sums = sum_iterations(stats.iterations);
  nlohmann::json j = nlohmann::json::object();
  for (const RunField& f : run_fields())
    if (f.path)
      j[nlohmann::json::json_pointer(std::string("/") + f.path)] = field_json(f.get(stats, sums));
  return j;
}

}  // namespace

nlohmann::json stats_to_json(const RunStats& stats) {
  nlohmann::json iterations = nlohmann::json::array();
  for (const IterationStats& it : stats.iterations) iterations.push_back(iteration_json(it));
  nlohmann::json effects = nlohmann::json::object();
  for (const auto& [name, effect] : stats.effects.table()) effects[name] = effect_json(*effect);
  return {
      {"iterations", std::move(iterations)},
      {"totals", totals_json(stats)},
      {"effects", std::move(effects)},
      {"warnings", stats.warnings},
  };
}

namespace {

// The absolute path of a scene file (null for a built-in scene), so that a later
// `hrad solve --config stats.json` finds it from any folder.
nlohmann::json scene_path(const std::string& source) {
  if (source.empty() || source.rfind("builtin:", 0) == 0) return nullptr;
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::absolute(source, ec);
  if (ec) return nullptr;
  return p.lexically_normal().string();
}

}  // namespace

nlohmann::json scene_summary_json(const Scene& scene) {
  const Rgb power = scene.emitted_power();
  const Aabb b = scene.bounds();
  nlohmann::json bounds = nullptr;
  if (!b.empty()) bounds = {{"lo", json_vec3(b.lo)}, {"hi", json_vec3(b.hi)}};
  return {
      {"name", scene.name},
      {"source", scene.source},
      {"path", scene_path(scene.source)},
      {"polygons", scene.polygon_count()},
      {"vertices", scene.vertices.size()},
      {"materials", scene.materials.size()},
      {"emitters", scene.emitter_count()},
      {"total_area", number(scene.total_area())},
      {"emitted_power", json_rgb(power)},
      {"bounds", std::move(bounds)},
      {"grey", scene.is_grey()},
      {"sides", scene.sides.empty() ? nlohmann::json(nullptr) : nlohmann::json(scene.sides)},
      {"emitter_sides",
       scene.emitter_sides.empty() ? nlohmann::json(nullptr) : nlohmann::json(scene.emitter_sides)},
      {"back_faces", scene.back_faces},
      {"dark_back_faces", scene.dark_back_faces},
      {"back_faces_present", scene.back_faces_present},
      {"warnings", scene.warnings},
  };
}

nlohmann::json camera_json(const Camera& cam, const std::string& source,
                           const std::string& view_file) {
  return {{"eye", json_vec3(cam.eye)},
          {"look", json_vec3(cam.target)},
          {"up", json_vec3(cam.up)},
          {"fov", number(cam.fov_y_deg)},
          {"source", source},
          {"view_file", view_file.empty() ? nlohmann::json(nullptr) : nlohmann::json(view_file)},
          {"spec", camera_spec_string(cam)}};
}

nlohmann::json json_vec3(const Vec3& v) {
  return nlohmann::json::array({number(v.x()), number(v.y()), number(v.z())});
}
nlohmann::json json_rgb(const Rgb& c) {
  return nlohmann::json::array({number(c[0]), number(c[1]), number(c[2])});
}

void write_json_atomically(const std::filesystem::path& path, const nlohmann::json& j) {
  // Invalid UTF-8 (a file name or warning taken from the input) is replaced, not fatal.
  write_file_atomically(path,
                        j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace hrad
