// The experiment loop: every (point, repetition) of a sweep that the result folder
// does not hold yet runs in this process (run_executor.h), and its rows are appended
// to runs.csv / iterations.csv at once (result_folder.h), so an interrupted experiment
// resumes where it stopped. Progress goes to a log stream (stderr): one line per run
// with point i/n, the run's time, the elapsed time and an estimate of the time left
// (mean time of the runs done so far x runs left), plus hrad's in-place progress line
// within a run when the log is a terminal. The MPI sweep (mpi_sweep.h) shares the
// folder, the executor and the line format.
#pragma once

#include "experiments/harness/manifest.h"
#include "experiments/harness/result_folder.h"
#include "experiments/harness/run_rows.h"
#include "experiments/harness/sweep.h"

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace hrad::experiment {

struct RunnerSettings {
  std::filesystem::path dir;  ///< result folder; created if missing
  bool quiet = false;         ///< no progress lines (errors still thrown)
  std::FILE* log = stderr;
};

struct ExperimentSummary {
  int runs = 0;     ///< points x repetitions
  int skipped = 0;  ///< already in runs.csv (resume)
  int ran = 0;
  double seconds = 0;  ///< wall time of this invocation
  /// Runs of this invocation whose CPU per task at P threads exceeds 1.2x the same
  /// point's at 1 thread (experiments/harness/task_cost.h), one line each; then, for
  /// an MPI sweep, one line per worker rank that was lost.
  std::vector<std::string> warnings;
};

/// Runs what is missing. For an existing result folder the manifest's resolved
/// configuration must equal `inputs.config` and every runs.csv row must match its
/// point's scene and swept values; otherwise std::runtime_error (nothing is changed).
/// A failing run marks the manifest "failed" with the message and rethrows; rows of
/// finished runs stay.
ExperimentSummary run_experiment(const ManifestInputs& inputs,
                                 const std::vector<SweepPoint>& points,
                                 const RunnerSettings& settings);

/// "[3/12] builtin:office threads=2 rep 1" (`number` is 1-based over all runs).
[[nodiscard]] std::string run_label(int number, int runs, const SweepPoint& p, int repetition);

/// The progress line after a run: "hrad experiment: LABEL: 1.23 s[, probe error ...];
/// 4.0 s elapsed, ~8.0 s left" (no newline).
[[nodiscard]] std::string run_line(const std::string& label, double seconds,
                                   const AccuracyFigures* accuracy, double elapsed, double left);

}  // namespace hrad::experiment
