// runs.csv and iterations.csv of one result folder, written run by run so that an
// interrupted experiment loses at most the run in progress, and reopened for resume.
//
// A run is on disk once its runs.csv row is: its iterations.csv rows are appended and
// flushed first, then the runs.csv row. Reopening a folder (resume) reads runs.csv,
// checks its header against run_columns(), drops a last line that was cut off, drops
// the iterations.csv rows of runs that have no runs.csv row, and rewrites both files
// atomically (core/base/atomic_file.h) before appending again. Runs may land out of run
// order (the ranks of an MPI sweep finish in any order); sort_by_run() puts both files
// into run order at the end.
#pragma once

#include "experiments/harness/run_rows.h"
#include "experiments/harness/sweep.h"

#include <filesystem>
#include <fstream>
#include <map>

namespace hrad::experiment {

/// Whether `dir`'s runs.csv has this hrad's columns (run_columns()) as its header, the
/// check ResultFiles makes when it reopens the folder; false when it has none.
[[nodiscard]] bool runs_header_matches(const std::filesystem::path& dir);

class ResultFiles {
 public:
  /// Opens (or creates) runs.csv and iterations.csv in `dir`, which must exist.
  /// Throws std::runtime_error naming the file when an existing file has another
  /// header, a row of the wrong width or a point/repetition that is not a number.
  explicit ResultFiles(const std::filesystem::path& dir);

  /// The runs already in runs.csv, each with its row (aligned with run_columns()).
  [[nodiscard]] const std::map<RunId, Row>& done() const { return done_; }

  /// Appends one run (iterations first, then the run row), flushing both files.
  /// Throws std::runtime_error when a write fails.
  void append(const RunId& id, const RunRows& rows);

  /// Rewrites both files (atomically) with the runs in run order (point, then
  /// repetition), each run's iteration rows in their order; a no-op when the runs are
  /// in run order already. Throws std::runtime_error when a write fails.
  void sort_by_run();

  static constexpr const char* kRuns = "runs.csv";
  static constexpr const char* kIterations = "iterations.csv";

 private:
  std::filesystem::path dir_;
  std::map<RunId, Row> done_;
  std::vector<RunId> order_;  ///< the runs in file order
  void open_for_append();
  std::ofstream runs_, iterations_;
};

}  // namespace hrad::experiment
