// Probe error of experiment runs (the experiment config's `accuracy` block, issue 7).
//
// Per scene, once: the probes of accuracy.probes and a path-traced reference at them
// (core/reference/path_tracer.h, to accuracy.reference_rel_error), cached in the result folder as
// reference-<scene>.csv (the columns of `hrad reference`'s probes.csv, SE included) and
// reference-<scene>.json (options, time, convergence). A resumed experiment reads the
// cached file back instead of tracing again. Per run: Solver::probe_irradiance at the
// probes, compared by compare_probes (core/reference/error_metrics.h) with the accuracy floor.
#pragma once

#include "core/reference/error_metrics.h"
#include "core/scene/probes.h"
#include "core/scene/scene.h"
#include "experiments/harness/experiment_config.h"
#include "experiments/harness/run_rows.h"

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace hrad {
class Solver;
}

namespace hrad::experiment {

/// "reference-<scene>.csv" with every character of the spec outside [A-Za-z0-9_.-]
/// replaced by '_' (builtin:office,desks=4 -> reference-builtin_office_desks_4.csv; the
/// '?' form of the same spec gives the same name).
[[nodiscard]] std::string reference_file_name(const std::string& scene);

struct SceneReference {
  std::vector<Probe> probes;
  ProbeTable table;       ///< the reference irradiance and standard errors
  bool computed = false;  ///< traced now (false: read from the cache)
  double seconds = 0;     ///< tracing time (0 when read back)
};

/// Reads the probes of `scene` (InputError for a bad file; std::invalid_argument when
/// the accuracy block names no file for it).
[[nodiscard]] std::vector<Probe> accuracy_probes(const AccuracySpec& a, const std::string& scene);

/// The reference of `scene`: read from `dir`/reference-<scene>.csv when it exists (its
/// probes must equal the probe file's), else traced with `threads` threads and written
/// there (atomically) with its .json. Progress and warnings (unconverged probes) go to
/// `log` unless `quiet`.
[[nodiscard]] SceneReference scene_reference(const std::filesystem::path& dir,
                                             const std::string& scene_spec, const Scene& scene,
                                             const AccuracySpec& a, int threads, std::FILE* log,
                                             bool quiet);

/// Gathers the solver's irradiance at the reference's probes and compares.
[[nodiscard]] AccuracyFigures measure_accuracy(const Solver& solver, const SceneReference& ref,
                                               const AccuracySpec& a);

}  // namespace hrad::experiment
