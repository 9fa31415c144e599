// The flat rows of the result files: one runs.csv row per run (a point and a
// repetition) and one iterations.csv row per run and refinement iteration, made from
// the run's RunStats (core/output/run_stats.h). The columns are fixed (same order in every
// experiment) so scripts can rely on them; see docs/results.md, "Experiment result files":
//
//   identity   config, point, repetition, scene, swept
//   options    every SolverOptions key, in core/config/options.h order (resolved values)
//   runs.csv   wall_s refine_wall_s refine_cpu_s propagate_wall_s links elements
//              links_created rays_cast rays_skipped peak_rss_bytes bytes_elements
//              bytes_links bytes_total tasks scheduler_ops steals idle_s
//              lock_wait_scheduler_s lock_wait_element_s lock_wait_link_s
//              lock_wait_total_s peak_parallelism local_access_ratio gather_sweeps
//              iterations_run started_at probe_err_mean probe_err_max probe_err_rms
//              probe_s warnings host hrad_revision cpu_model cores load_avg
//   iterations.csv  iteration, then the same per-iteration figures (max_change too),
//              host hrad_revision
//
// Sums over iterations: times, links_created, rays, tasks, scheduler_ops, steals, idle,
// lock waits, gather_sweeps; local_access_ratio is tasks whose receiver lives on the
// refiner's NUMA node over all located tasks, all iterations (empty: none). At the end of the run: links, elements, bytes_*,
// peak_rss_bytes (the process's peak so far: runs share one process, so it never
// decreases within an experiment; bytes_total is the per-run memory figure).
#pragma once

#include "core/output/run_stats.h"
#include "experiments/harness/sweep.h"

#include <limits>
#include <string>
#include <vector>

namespace hrad::experiment {

using Row = std::vector<std::string>;

/// The header of runs.csv.
[[nodiscard]] const std::vector<std::string>& run_columns();
/// The header of iterations.csv.
[[nodiscard]] const std::vector<std::string>& iteration_columns();

/// Probe error of a run against the reference (experiment `accuracy` block): mean, max
/// and RMS over the probes of the relative error (core/reference/error_metrics.h), and the time
/// the solver's probe gather took (not part of wall_s).
struct AccuracyFigures {
  double mean = 0, max = 0, rms = 0;
  double probe_s = 0;
};

/// Where a run ran: its host, hrad's git revision, the host's CPU model and core count,
/// and the 1-minute load average when the run started (the manifest gives the
/// experiment's, but a resumed folder or an MPI sweep's ranks may mix them).
struct RunOrigin {
  std::string host, revision;
  std::string cpu_model;  ///< tidied (core/parallel/topology.h); "" when unknown
  int cores = 0;          ///< physical cores; 0 when unknown
  double load_avg = std::numeric_limits<double>::quiet_NaN();  ///< NaN: unknown (empty cell)
};

struct RunRows {
  Row run;                      ///< aligned with run_columns()
  std::vector<Row> iterations;  ///< aligned with iteration_columns()
};

/// Flattens one run. `started_at` is an ISO 8601 time stamp. The probe_err_* and probe_s
/// columns are empty when `accuracy` is null. `warnings` holds the run's warnings
/// (RunStats::warnings, the solve's stats.json `warnings`), joined by " | ".
[[nodiscard]] RunRows make_run_rows(const std::string& config_name, const SweepPoint& point,
                                    int repetition, const RunStats& stats,
                                    const std::string& started_at,
                                    const AccuracyFigures* accuracy = nullptr,
                                    const RunOrigin& origin = {});

/// Index of `name` in `columns` (std::logic_error when absent: a programming error).
[[nodiscard]] std::size_t column_index(const std::vector<std::string>& columns,
                                       const std::string& name);

}  // namespace hrad::experiment
