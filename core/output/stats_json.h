// stats.json building blocks: the measurements of a run (RunStats) and a summary of
// the scene, as JSON, plus an atomic JSON file writer. The keys are documented in
// docs/results.md; field names follow core/output/run_stats.h. Times are in
// seconds, sizes in bytes, areas in the scene's units squared, radiometric values in
// W per unit area of the scene's units.
#pragma once

#include "core/output/run_stats.h"
#include "core/scene/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace hrad {

/// {"iterations": [ {iteration, refine_wall_s, refine_cpu_s, propagate_wall_s,
///   links_created, links, elements, bytes{...}, peak_rss_bytes, tasks, scheduler_ops,
///   lock_wait_s{...}, idle_s, rays_cast, rays_skipped, gather_sweeps, max_change, contraction}, ...],
///  "totals": {wall_s, refine_wall_s, refine_cpu_s, links, elements, rays_cast,
///   rays_skipped, peak_rss_bytes},
///  "warnings": [...]}
/// A non-finite number (there should be none) is written as null, as JSON has no NaN.
[[nodiscard]] nlohmann::json stats_to_json(const RunStats& stats);

/// {name, source, polygons, vertices, materials, emitters (emitting polygons),
///  total_area, emitted_power [r,g,b] (sum of exitance x area), bounds {lo [x,y,z],
///  hi [x,y,z]} (null for an empty scene), grey (bool), sides (the `sides` mode applied,
///  null when none was), back_faces (faces added as the back of two-sided ones),
///  back_faces_present (two-sided faces whose back the input already had), warnings [...]}.
[[nodiscard]] nlohmann::json scene_summary_json(const Scene& scene);

/// {eye [x,y,z], look [x,y,z], up [x,y,z], fov (vertical, degrees), source (how it was
///  chosen: "option", "config", "view file", "scene", "automatic"), view_file (the path,
///  or null), spec (the --camera text that gives this camera again)}.
[[nodiscard]] nlohmann::json camera_json(const Camera& cam, const std::string& source,
                                         const std::string& view_file = "");

/// [x, y, z] and [r, g, b] as JSON arrays; a non-finite component is written as null.
[[nodiscard]] nlohmann::json json_vec3(const Vec3& v);
[[nodiscard]] nlohmann::json json_rgb(const Rgb& c);

/// Writes `j` pretty-printed (2-space indent, trailing newline) to `path` atomically
/// (core/base/atomic_file.h). Throws std::runtime_error naming the path on failure.
void write_json_atomically(const std::filesystem::path& path, const nlohmann::json& j);

}  // namespace hrad
