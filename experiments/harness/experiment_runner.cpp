#include "experiments/harness/experiment_runner.h"

#include "core/clock.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "core/scene_loader.h"
#include "core/solver.h"
#include "experiments/harness/accuracy.h"
#include "experiments/harness/result_files.h"
#include "experiments/harness/run_rows.h"
#include "experiments/harness/task_cost.h"

#include <fmt/format.h>
#include <unistd.h>

#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>

namespace hrad::experiment {
namespace {

namespace fs = std::filesystem;
// The existing folder must have been made by the same resolved configuration, and its
// rows must name the same points: otherwise resuming would mix two experiments.
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
      throw std::runtime_error(fmt::format(
          "{}: point {} is '{} {}' there but '{} {}' in this sweep",
          (dir / ResultFiles::kRuns).string(), id.point, row[scene], row[swept], p.scene,
          describe_point(p)));
  }
}

}  // namespace

bool is_result_folder(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "manifest.json", ec);
}

ExperimentSummary run_experiment(const ManifestInputs& inputs,
                                 const std::vector<SweepPoint>& points,
                                 const RunnerSettings& settings) {
  const fs::path& dir = settings.dir;
  const ExperimentConfig& config = inputs.config;
  const auto start = Clock::now();

  // Bad probe files are bad input: report them before anything is created.
  if (config.accuracy.enabled)
    for (const SweepPoint& p : points) (void)accuracy_probes(config.accuracy, p.scene);

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
  ResultFiles files(dir);
  check_rows(files, points, config.repetitions, dir);
  manifest["runs_done"] = files.done().size();
  write_manifest(dir, manifest);

  ExperimentSummary summary;
  summary.runs = static_cast<int>(points.size()) * config.repetitions;
  summary.skipped = static_cast<int>(files.done().size());
  if (!settings.quiet && summary.skipped > 0)
    fmt::print(settings.log, "hrad experiment: resuming {}: {} of {} runs already done\n",
               dir.string(), summary.skipped, summary.runs);

  std::optional<Scene> scene;
  std::optional<SceneReference> reference;
  std::string scene_spec;
  SceneLoadOptions scene_options;  // the `sides` and `segments` the scene was loaded with
  double run_seconds = 0;
  int number = summary.skipped;
  TaskCostTable task_costs;
  try {
    for (const SweepPoint& p : points) {
      for (int rep = 0; rep < config.repetitions; ++rep) {
        const RunId id{p.index, rep};
        if (files.done().count(id)) continue;
        throw_if_interrupted();
        if (!scene || scene_spec != p.scene || !(scene_options == scene_load_options(p.options))) {
          scene.reset();  // free the previous scene before loading the next
          reference.reset();
          scene_options = scene_load_options(p.options);
          scene = load_scene(p.scene, scene_options);
          scene_spec = p.scene;
          if (!settings.quiet)
            for (const std::string& w : scene->warnings)
              fmt::print(settings.log, "hrad: warning: {}: {}\n", p.scene, w);
          if (config.accuracy.enabled)
            reference = scene_reference(
                dir, p.scene, *scene, config.accuracy,
                static_cast<int>(std::max(1u, std::thread::hardware_concurrency())),
                settings.log, settings.quiet);
        }
        ++number;
        const std::string label =
            fmt::format("[{}/{}] {} {} rep {}", number, summary.runs, p.scene, describe_point(p),
                        rep + 1);
        const bool draw = !settings.quiet && ::isatty(::fileno(settings.log)) == 1;
        ProgressReporter progress(settings.log, draw, [] { return Clock::now(); });
        const auto run_start = Clock::now();
        const std::string started = now_iso8601();
        RunStats stats;
        std::optional<AccuracyFigures> accuracy;
        {
          Solver solver(*scene, p.options, [&](const std::string& phase, double f) {
            progress.update(label + " " + phase, f);
          });
          stats = solver.run();
          if (reference) accuracy = measure_accuracy(solver, *reference, config.accuracy);
        }
        progress.finish();
        files.append(id, make_run_rows(config.name, p, rep, stats, started,
                                       accuracy ? &*accuracy : nullptr));
        task_costs.add(p.scene, p.options, stats.totals.task_cpu_ns);
        const double took = seconds_since(run_start);
        run_seconds += took;
        ++summary.ran;
        if (!settings.quiet) {
          const int left = summary.runs - number;
          fmt::print(settings.log, "hrad experiment: {}: {:.2f} s{}; {} elapsed, ~{} left\n",
                     label, took,
                     accuracy ? fmt::format(", probe error {:.2f}% mean, {:.2f}% max",
                                            100 * accuracy->mean, 100 * accuracy->max)
                              : std::string(),
                     ProgressReporter::format_duration(seconds_since(start)),
                     ProgressReporter::format_duration(run_seconds / summary.ran * left));
          std::fflush(settings.log);
        }
      }
    }
  } catch (const std::exception& e) {
    // An interrupt (core/interrupt.h) lands here between runs or from inside a run's
    // solve; the run in progress wrote no row.
    const bool stopped = dynamic_cast<const Interrupted*>(&e) != nullptr;
    manifest["status"] = stopped ? "interrupted" : "failed";
    manifest["error"] = e.what();
    manifest["runs_done"] = files.done().size();
    try {
      write_manifest(dir, manifest);
    } catch (const std::exception&) {
      // The run's own error is the one to report.
    }
    throw;
  }
  manifest["status"] = "complete";
  manifest["finished_at"] = now_iso8601();
  manifest["runs_done"] = files.done().size();
  manifest.erase("error");
  write_manifest(dir, manifest);
  summary.seconds = seconds_since(start);
  summary.warnings = task_costs.warnings();
  return summary;
}

}  // namespace hrad::experiment
