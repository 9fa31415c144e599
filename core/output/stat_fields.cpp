#include "core/output/stat_fields.h"

#include <cmath>

namespace hrad {
namespace {

FieldValue count(std::uint64_t v) { return {true, v, 0}; }
FieldValue real(double v) { return {false, 0, v}; }

template <class V>
V at(const std::map<std::string, V>& m, const char* key) {
  const auto it = m.find(key);
  return it == m.end() ? V{} : it->second;
}

template <class V>
V total(const std::map<std::string, V>& m) {
  V s{};
  for (const auto& [k, v] : m) s += v;
  return s;
}

// Bytes of one structure per item; NaN (null, empty) when there are no items.
double per(const std::map<std::string, std::uint64_t>& bytes, const char* key, std::uint64_t n) {
  const auto it = bytes.find(key);
  if (n == 0 || it == bytes.end()) return std::nan("");
  return static_cast<double>(it->second) / static_cast<double>(n);
}

using S = IterationStats;
// A getter of one figure, as a count or as a real, from an expression of `it`.
#define HRAD_COUNT(expr) [](const S& it) { return count(static_cast<std::uint64_t>(expr)); }
#define HRAD_REAL(expr) [](const S& it) { return real(expr); }

}  // namespace

const std::vector<IterationField>& iteration_fields() {
  static const std::vector<IterationField> fields = {
      {"iteration", "iteration", "", HRAD_COUNT(it.iteration)},
      {"refine_wall_s", "refine_wall_s", "s", HRAD_REAL(it.refine_wall_s)},
      {"refine_cpu_s", "refine_cpu_s", "s", HRAD_REAL(it.refine_cpu_s)},
      {"refine_thread_cpu_s", "refine_thread_cpu_s", "s", HRAD_REAL(it.refine_thread_cpu_s)},
      {"task_cpu_ns", "task_cpu_ns", "ns", HRAD_REAL(it.task_cpu_ns)},
      {"propagate_wall_s", "propagate_wall_s", "s", HRAD_REAL(it.propagate_wall_s)},
      {"prepare_s", "prepare_s", "s", HRAD_REAL(it.prepare_s)},
      {"open_s", "open_s", "s", HRAD_REAL(it.open_s)},
      {"push_weights_s", "push_weights_s", "s", HRAD_REAL(it.push_weights_s)},
      {"row_sums_s", "row_sums_s", "s", HRAD_REAL(it.row_sums_s)},
      {"sweeps_s", "sweeps_s", "s", HRAD_REAL(it.sweeps_s)},
      {"stage_start_s", "stage_start_s", "s", HRAD_REAL(it.stage_start_s)},
      {"stage_end_s", "stage_end_s", "s", HRAD_REAL(it.stage_end_s)},
      {"links_created", "links_created", "count", HRAD_COUNT(it.links_created)},
      {"links", "links", "count", HRAD_COUNT(it.links)},
      {"elements", "elements", "count", HRAD_COUNT(it.elements)},
      {nullptr, "bytes_elements", "bytes", HRAD_COUNT(at(it.bytes, "elements"))},
      {nullptr, "bytes_links", "bytes", HRAD_COUNT(at(it.bytes, "links"))},
      {nullptr, "bytes_total", "bytes", HRAD_COUNT(total(it.bytes))},
      {"peak_rss_bytes", "peak_rss_bytes", "bytes", HRAD_COUNT(it.peak_rss_bytes)},
      {"tasks", "tasks", "count", HRAD_COUNT(it.tasks)},
      {"scheduler_ops", "scheduler_ops", "count", HRAD_COUNT(it.scheduler_ops)},
      {"steals", "steals", "count", HRAD_COUNT(it.steals)},
      {"idle_s", "idle_s", "s", HRAD_REAL(it.idle_s)},
      {nullptr, "lock_wait_scheduler_s", "s", HRAD_REAL(at(it.lock_wait_s, "scheduler"))},
      {nullptr, "lock_wait_element_s", "s", HRAD_REAL(at(it.lock_wait_s, "element"))},
      {nullptr, "lock_wait_link_s", "s", HRAD_REAL(at(it.lock_wait_s, "link"))},
      {nullptr, "lock_wait_total_s", "s", HRAD_REAL(total(it.lock_wait_s))},
      {"peak_parallelism", "peak_parallelism", "count", HRAD_COUNT(it.peak_parallelism)},
      {"local_access_ratio", "local_access_ratio", "", HRAD_REAL(it.local_access_ratio)},
      {"rays_cast", "rays_cast", "count", HRAD_COUNT(it.rays_cast)},
      {"rays_skipped", "rays_skipped", "count", HRAD_COUNT(it.rays_skipped)},
      {"gather_sweeps", "gather_sweeps", "count", HRAD_COUNT(it.gather_sweeps)},
      {"max_change", "max_change", "", HRAD_REAL(it.max_change)},
      {"contraction", "contraction", "", HRAD_REAL(it.contraction)},
      {"open/area_fraction", "open_area_fraction", "", HRAD_REAL(it.open_area_fraction)},
      // Columns after this line were in stats.json only before this table.
      {"load_s", "load_s", "s", HRAD_REAL(it.load_s)},
      {"link_compact_s", "link_compact_s", "s", HRAD_REAL(it.link_compact_s)},
      {"bytes_per_link", "bytes_per_link", "bytes", HRAD_REAL(per(it.bytes, "links", it.links))},
      {"bytes_per_element", "bytes_per_element", "bytes",
       HRAD_REAL(per(it.bytes, "elements", it.elements))},
      {"row_sums/min", "row_sums_min", "", HRAD_REAL(it.row_sum_min)},
      {"row_sums/max", "row_sums_max", "", HRAD_REAL(it.row_sum_max)},
      {"row_sums/area_mean", "row_sums_area_mean", "", HRAD_REAL(it.row_sum_mean)},
      {"row_sums/within_3pct", "row_sums_within_3pct", "", HRAD_REAL(it.row_sum_within_band)},
      {"row_sums/corrected", "row_sums_corrected", "count", HRAD_COUNT(it.row_sum_corrected)},
      {"open/rays", "open_rays", "count", HRAD_COUNT(it.open_rays)},
      {"exposure/rays", "exposure_rays", "count", HRAD_COUNT(it.exposure_rays)},
      {"exposure/mean", "exposure_mean", "", HRAD_REAL(it.mean_exposure)},
      {"gather_rows_kept", "gather_rows_kept", "count", HRAD_COUNT(it.gather_rows_kept)},
      {"min_area_held/links", "min_area_held_links", "count", HRAD_COUNT(it.min_area_held)},
      {"min_area_held/error_share", "min_area_held_error_share", "",
       HRAD_REAL(it.min_area_held_error)},
  };
  return fields;
}

#undef HRAD_COUNT
#undef HRAD_REAL

namespace {
using R = RunStats;
using T = IterationTotals;
#define HRAD_COUNT(expr)                                              \
  []([[maybe_unused]] const R& run, [[maybe_unused]] const T& sums) { \
    return count(static_cast<std::uint64_t>(expr));                   \
  }
#define HRAD_REAL(expr) \
  []([[maybe_unused]] const R& run, [[maybe_unused]] const T& sums) { return real(expr); }
}  // namespace

const std::vector<RunField>& run_fields() {
  // Totals the solver keeps (RunTotals) or sums over the iterations (IterationTotals).
  static const std::vector<RunField> fields = {
      {"wall_s", "wall_s", "s", HRAD_REAL(run.totals.wall_s)},
      {"refine_wall_s", "refine_wall_s", "s", HRAD_REAL(run.totals.refine_wall_s)},
      {"refine_cpu_s", "refine_cpu_s", "s", HRAD_REAL(run.totals.refine_cpu_s)},
      {"refine_thread_cpu_s", "refine_thread_cpu_s", "s",
       HRAD_REAL(run.totals.refine_thread_cpu_s)},
      {"task_cpu_ns", "task_cpu_ns", "ns", HRAD_REAL(run.totals.task_cpu_ns)},
      {"propagate_wall_s", "propagate_wall_s", "s", HRAD_REAL(sums.propagate_wall_s)},
      {"prepare_s", "prepare_s", "s", HRAD_REAL(sums.prepare_s)},
      {"open_s", "open_s", "s", HRAD_REAL(sums.open_s)},
      {"push_weights_s", "push_weights_s", "s", HRAD_REAL(sums.push_weights_s)},
      {"row_sums_s", "row_sums_s", "s", HRAD_REAL(sums.row_sums_s)},
      {"sweeps_s", "sweeps_s", "s", HRAD_REAL(sums.sweeps_s)},
      {"load_s", "load_s", "s", HRAD_REAL(sums.load_s)},
      {"link_compact_s", "link_compact_s", "s", HRAD_REAL(sums.link_compact_s)},
      {"stage_start_s", "stage_start_s", "s", HRAD_REAL(sums.stage_start_s)},
      {"stage_end_s", "stage_end_s", "s", HRAD_REAL(sums.stage_end_s)},
      {"setup_s", "setup_s", "s", HRAD_REAL(run.totals.setup_s)},
      {"scene_load_s", "scene_load_s", "s", HRAD_REAL(run.totals.scene_load_s)},
      {"links", "links", "count", HRAD_COUNT(run.totals.links)},
      {"elements", "elements", "count", HRAD_COUNT(run.totals.elements)},
      {nullptr, "links_created", "count", HRAD_COUNT(sums.links_created)},
      {"rays_cast", "rays_cast", "count", HRAD_COUNT(run.totals.rays_cast)},
      {"rays_skipped", "rays_skipped", "count", HRAD_COUNT(run.totals.rays_skipped)},
      {"peak_rss_bytes", "peak_rss_bytes", "bytes", HRAD_COUNT(run.totals.peak_rss_bytes)},
      {nullptr, "bytes_elements", "bytes", HRAD_COUNT(at(sums.bytes, "elements"))},
      {nullptr, "bytes_links", "bytes", HRAD_COUNT(at(sums.bytes, "links"))},
      {nullptr, "bytes_total", "bytes", HRAD_COUNT(total(sums.bytes))},
      {nullptr, "tasks", "count", HRAD_COUNT(sums.tasks)},
      {nullptr, "scheduler_ops", "count", HRAD_COUNT(sums.scheduler_ops)},
      {nullptr, "steals", "count", HRAD_COUNT(sums.steals)},
      {nullptr, "idle_s", "s", HRAD_REAL(sums.idle_s)},
      {nullptr, "lock_wait_scheduler_s", "s", HRAD_REAL(at(sums.lock_wait_s, "scheduler"))},
      {nullptr, "lock_wait_element_s", "s", HRAD_REAL(at(sums.lock_wait_s, "element"))},
      {nullptr, "lock_wait_link_s", "s", HRAD_REAL(at(sums.lock_wait_s, "link"))},
      {nullptr, "lock_wait_total_s", "s", HRAD_REAL(total(sums.lock_wait_s))},
      {nullptr, "peak_parallelism", "count", HRAD_COUNT(sums.peak_parallelism)},
      {nullptr, "local_access_ratio", "", HRAD_REAL(sums.local_access_ratio)},
      {nullptr, "gather_sweeps", "count", HRAD_COUNT(sums.gather_sweeps)},
      {"iterations_run", "iterations_run", "count", HRAD_COUNT(run.totals.iterations_run)},
  };
  return fields;
}

#undef HRAD_COUNT
#undef HRAD_REAL

}  // namespace hrad
