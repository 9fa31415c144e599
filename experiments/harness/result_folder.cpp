#include "experiments/harness/result_folder.h"

#include "core/base/interrupt.h"

#include <fmt/format.h>

#include <stdexcept>

namespace hrad::experiment {
namespace {

namespace fs = std::filesystem;

// The existing folder must have been made by the same resolved configuration:
// otherwise resuming would mix two experiments.
void check_resumable(const nlohmann::ordered_json& manifest, const ManifestInputs& in,
                     const fs::path& dir) {
  const auto stored = manifest.value("/experiment/config"_json_pointer, nlohmann::ordered_json());
  if (stored != experiment_config_to_json(in.config))
    throw std::runtime_error(fmt::format(
        "{} holds results of a different configuration (manifest.json, experiment.config); "
        "choose another --out folder, or the same config, --quick and --set as before",
        dir.string()));
}

void check_rows(const ResultFiles& files, const std::vector<SweepPoint>& points, int repetitions,
                const fs::path& dir) {
  const auto& rc = run_columns();
  const std::size_t scene = column_index(rc, "scene"), swept = column_index(rc, "swept");
  for (const auto& [id, row] : files.done()) {
    if (id.point >= static_cast<int>(points.size()) || id.repetition >= repetitions)
      throw std::runtime_error(fmt::format("{}: run (point {}, repetition {}) is not in this sweep",
                                           (dir / ResultFiles::kRuns).string(), id.point,
                                           id.repetition));
    const SweepPoint& p = points[static_cast<std::size_t>(id.point)];
    if (row[scene] != p.scene || row[swept] != describe_point(p))
      throw std::runtime_error(
          fmt::format("{}: point {} is '{} {}' there but '{} {}' in this sweep",
                      (dir / ResultFiles::kRuns).string(), id.point, row[scene], row[swept],
                      p.scene, describe_point(p)));
  }
}

// The manifest of the folder, before ResultFiles touches runs.csv: a folder of another
// configuration must be left as it was.
nlohmann::ordered_json open_manifest(const ManifestInputs& inputs, const fs::path& dir) {
  nlohmann::ordered_json manifest;
  if (is_result_folder(dir)) {
    manifest = read_manifest(dir);
    check_resumable(manifest, inputs, dir);
    manifest["status"] = "running";
    manifest["finished_at"] = nullptr;
    manifest["resumed_at"].push_back(now_iso8601());
  } else {
    if (fs::exists(dir) && !(fs::is_directory(dir) && fs::is_empty(dir)))
      throw std::runtime_error(fmt::format(
          "{} exists and is not an experiment result folder (no manifest.json)", dir.string()));
    fs::create_directories(dir);
    manifest = make_manifest(inputs);
  }
  return manifest;
}

}  // namespace

bool is_result_folder(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "manifest.json", ec);
}

ResultFolder::ResultFolder(const ManifestInputs& inputs, const std::vector<SweepPoint>& points,
                           const fs::path& dir)
    : dir_(dir), manifest_(open_manifest(inputs, dir)), files_(dir) {
  repetitions_ = inputs.config.repetitions;
  points_ = static_cast<int>(points.size());
  runs_ = points_ * repetitions_;
  check_rows(files_, points, repetitions_, dir);
  skipped_ = runs_done();
  save_manifest();
}

std::vector<RunId> ResultFolder::pending() const {
  std::vector<RunId> left;
  for (int p = 0; p < points_; ++p)
    for (int rep = 0; rep < repetitions_; ++rep)
      if (!done({p, rep})) left.push_back({p, rep});
  return left;
}

void ResultFolder::save_manifest() {
  manifest_["runs_done"] = files_.done().size();
  write_manifest(dir_, manifest_);
}

void ResultFolder::complete() {
  files_.sort_by_run();
  manifest_["status"] = "complete";
  manifest_["finished_at"] = now_iso8601();
  manifest_.erase("error");
  save_manifest();
}

void ResultFolder::fail(const std::exception& e) noexcept {
  try {
    manifest_["status"] = dynamic_cast<const Interrupted*>(&e) ? "interrupted" : "failed";
    manifest_["error"] = e.what();
    save_manifest();
  } catch (const std::exception&) {
    // The run's own error is the one to report.
  }
}

}  // namespace hrad::experiment
