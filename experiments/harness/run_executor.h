// One experiment run in this process: the point's scene (loaded once and kept while
// consecutive runs share it), its accuracy reference when the config has an `accuracy`
// block, the solve through hrad::Solver, and the run's rows. The serial loop
// (experiment_runner.h) and every MPI worker rank (mpi_sweep.h) run runs through it.
#pragma once

#include "core/scene/scene.h"
#include "core/scene/scene_loader.h"
#include "experiments/harness/accuracy.h"
#include "experiments/harness/experiment_config.h"
#include "experiments/harness/run_rows.h"
#include "experiments/harness/sweep.h"

#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>
#include <string>

namespace hrad::experiment {

struct RunOutcome {
  RunRows rows;
  double seconds = 0;      ///< wall time of the run (solve and probe gather)
  double task_cpu_ns = 0;  ///< RunTotals::task_cpu_ns (task_cost.h)
  std::optional<AccuracyFigures> accuracy;
};

class RunExecutor {
 public:
  /// `dir` is the result folder (accuracy references are cached there). With
  /// `cached_references_only`, a reference missing from `dir` is an error instead of
  /// being traced here (MPI workers: rank 0 traces them first, so that every rank
  /// compares against the same reference).
  /// `revision`: hrad's git revision, for the rows (RunOrigin; the host, its CPU and
  /// the load at each run's start are this one's).
  RunExecutor(const ExperimentConfig& config, std::filesystem::path dir, std::FILE* log, bool quiet,
              std::string revision, bool cached_references_only = false);

  /// Runs repetition `repetition` of `p`. `label` prefixes hrad's in-place progress
  /// line (drawn when the log is a terminal and not quiet) and the run's warnings,
  /// printed to the log unless quiet (a solve's warning about refiners that waited for
  /// a core says the run's timings measure the sharing). Throws what the scene loader
  /// or the solver throws (hrad::Interrupted included).
  RunOutcome run(const SweepPoint& p, int repetition, const std::string& label);

 private:
  const ExperimentConfig& config_;
  std::filesystem::path dir_;
  std::FILE* log_;
  bool quiet_, cached_only_;
  RunOrigin origin_;
  std::optional<Scene> scene_;
  std::optional<SceneReference> reference_;
  std::string scene_spec_;
  SceneLoadOptions scene_options_;  ///< the `sides` and `segments` it was loaded with
  std::set<std::string> printed_;   ///< the runs' warnings logged for this scene
  void load(const std::string& spec, const SceneLoadOptions& options);
};

}  // namespace hrad::experiment
