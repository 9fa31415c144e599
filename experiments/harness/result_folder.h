// The life of one experiment's result folder, whoever runs its runs (the serial loop of
// experiment_runner.h or the ranks of mpi_sweep.h): created, or reopened and checked for
// a resume; each finished run recorded as it lands (result_files.h); at the end the rows
// put in run order and the manifest marked "complete", or on an error "failed" /
// "interrupted" with the rows of finished runs kept.
#pragma once

#include "experiments/harness/manifest.h"
#include "experiments/harness/result_files.h"
#include "experiments/harness/sweep.h"

#include <nlohmann/json.hpp>

#include <exception>
#include <filesystem>
#include <optional>
#include <vector>

namespace hrad::experiment {

/// True when `dir` holds a manifest.json (a result folder to resume or extend).
[[nodiscard]] bool is_result_folder(const std::filesystem::path& dir);

class ResultFolder {
 public:
  /// Creates `dir` (missing or empty) or reopens the result folder there. For an
  /// existing folder the manifest's resolved configuration must equal `inputs.config`
  /// and every runs.csv row must match its point's scene and swept values; otherwise
  /// std::runtime_error (nothing is changed). Writes the manifest ("running").
  ResultFolder(const ManifestInputs& inputs, const std::vector<SweepPoint>& points,
               const std::filesystem::path& dir);

  [[nodiscard]] const std::filesystem::path& dir() const { return dir_; }
  /// Runs already done when the folder was opened (resume).
  [[nodiscard]] int skipped() const { return skipped_; }
  /// points x repetitions.
  [[nodiscard]] int runs() const { return runs_; }
  /// The runs that runs.csv does not hold yet, in run order (point, then repetition).
  [[nodiscard]] std::vector<RunId> pending() const;
  [[nodiscard]] bool done(const RunId& id) const { return files_.done().count(id) > 0; }
  [[nodiscard]] int runs_done() const { return static_cast<int>(files_.done().size()); }

  /// Appends one finished run's rows (flushed: on disk when this returns).
  void record(const RunId& id, const RunRows& rows) { files_.append(id, rows); }

  /// The manifest as it will be written next; callers may add keys (the MPI layer
  /// adds "mpi").
  [[nodiscard]] nlohmann::ordered_json& manifest() { return manifest_; }
  /// Writes the manifest now (runs_done updated).
  void save_manifest();

  /// Rows into run order (a no-op when they already are), status "complete".
  void complete();
  /// Status "interrupted" (for hrad::Interrupted) or "failed" with `e`'s message; never
  /// throws (the caller's error is the one to report).
  void fail(const std::exception& e) noexcept;

 private:
  std::filesystem::path dir_;
  nlohmann::ordered_json manifest_;
  ResultFiles files_;
  int runs_ = 0, repetitions_ = 0, points_ = 0, skipped_ = 0;
};

}  // namespace hrad::experiment
