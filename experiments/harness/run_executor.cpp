#include "experiments/harness/run_executor.h"

#include "core/base/clock.h"
#include "core/base/progress.h"
#include "core/config/options_io.h"
#include "core/scene/scene_builder.h"
#include "core/scene/scene_loader.h"
#include "core/solver/solver.h"
#include "experiments/harness/manifest.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <stdexcept>
#include <thread>

namespace hrad::experiment {

namespace fs = std::filesystem;

RunExecutor::RunExecutor(const ExperimentConfig& config, fs::path dir, std::FILE* log, bool quiet,
                         std::string revision, bool cached_references_only)
    : config_(config),
      dir_(std::move(dir)),
      log_(log),
      quiet_(quiet),
      cached_only_(cached_references_only) {
  const HostInfo host = this_host();
  origin_.host = host.hostname;
  origin_.cpu_model = host.cpu_model;
  origin_.cores = host.cores;
  origin_.revision = std::move(revision);
}

void RunExecutor::load(const std::string& spec, const SceneLoadOptions& options) {
  scene_.reset();  // free the previous scene before loading the next
  reference_.reset();
  scene_ = load_scene(spec, options);
  scene_spec_ = spec;
  scene_options_ = options;
  printed_.clear();
  if (!quiet_)
    for (const std::string& w : scene_->warnings)
      if (w != kNoEmitterWarning)  // each run's solver says it, with what it skipped
        fmt::print(log_, "hrad: warning: {}: {}\n", spec, w);
  if (!config_.accuracy.enabled) return;
  const fs::path cached = dir_ / reference_file_name(spec);
  if (cached_only_ && !fs::exists(cached))
    throw std::runtime_error(fmt::format(
        "{}: no accuracy reference there; rank 0 writes it before any run, so the result "
        "folder must be on a file system every rank sees",
        cached.string()));
  reference_ = scene_reference(dir_, spec, *scene_, config_.accuracy,
                               static_cast<int>(std::max(1u, std::thread::hardware_concurrency())),
                               log_, quiet_);
}

RunOutcome RunExecutor::run(const SweepPoint& p, int repetition, const std::string& label) {
  // A new scene, or the same one loaded with other `sides` or `segments`.
  const SceneLoadOptions options = scene_load_options(p.options);
  if (!scene_ || scene_spec_ != p.scene || !(scene_options_ == options)) load(p.scene, options);
  const bool draw = !quiet_ && ::isatty(::fileno(log_)) == 1;
  ProgressReporter progress(log_, draw, [] { return Clock::now(); });
  const auto start = Clock::now();
  const std::string started = now_iso8601();
  RunOrigin origin = origin_;
  origin.load_avg = load_average_1min();
  RunStats stats;
  RunOutcome out;
  {
    Solver solver(*scene_, p.options, [&](const std::string& phase, double f) {
      progress.update(label + " " + phase, f);
    });
    stats = solver.run();
    if (reference_) out.accuracy = measure_accuracy(solver, *reference_, config_.accuracy);
  }
  progress.finish();
  // A warning about the scene comes from every run of it ("scene has no emitter"): the
  // log has it once per scene, runs.csv with each run.
  if (!quiet_)
    for (const std::string& w : stats.warnings)
      if (printed_.insert(w).second) fmt::print(log_, "hrad: warning: {}: {}\n", label, w);
  out.rows = make_run_rows(config_.name, p, repetition, stats, started,
                           out.accuracy ? &*out.accuracy : nullptr, origin);
  out.task_cpu_ns = stats.totals.task_cpu_ns;
  out.seconds = seconds_since(start);
  return out;
}

}  // namespace hrad::experiment
