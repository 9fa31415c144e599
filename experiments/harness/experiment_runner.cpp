#include "experiments/harness/experiment_runner.h"

#include "core/base/clock.h"
#include "core/base/interrupt.h"
#include "core/base/progress.h"
#include "experiments/harness/accuracy.h"
#include "experiments/harness/run_executor.h"
#include "experiments/harness/task_cost.h"

#include <fmt/format.h>

#include <stdexcept>

namespace hrad::experiment {

std::string run_label(int number, int runs, const SweepPoint& p, int repetition) {
  return fmt::format("[{}/{}] {} {} rep {}", number, runs, p.scene, describe_point(p),
                     repetition + 1);
}

std::string run_line(const std::string& label, double seconds, const AccuracyFigures* accuracy,
                     double elapsed, double left) {
  return fmt::format("hrad experiment: {}: {:.2f} s{}; {} elapsed, ~{} left", label, seconds,
                     accuracy ? fmt::format(", probe error {:.2f}% mean, {:.2f}% max",
                                            100 * accuracy->mean, 100 * accuracy->max)
                              : std::string(),
                     ProgressReporter::format_duration(elapsed),
                     ProgressReporter::format_duration(left));
}

ExperimentSummary run_experiment(const ManifestInputs& inputs,
                                 const std::vector<SweepPoint>& points,
                                 const RunnerSettings& settings) {
  const ExperimentConfig& config = inputs.config;
  const auto start = Clock::now();

  // Bad probe files are bad input: report them before anything is created.
  if (config.accuracy.enabled)
    for (const SweepPoint& p : points) (void)accuracy_probes(config.accuracy, p.scene);

  ResultFolder folder(inputs, points, settings.dir);
  ExperimentSummary summary;
  summary.runs = folder.runs();
  summary.skipped = folder.skipped();
  if (!settings.quiet && summary.skipped > 0)
    fmt::print(settings.log, "hrad experiment: resuming {}: {} of {} runs already done\n",
               settings.dir.string(), summary.skipped, summary.runs);

  RunExecutor executor(config, settings.dir, settings.log, settings.quiet, inputs.git_revision);
  double run_seconds = 0;
  int number = summary.skipped;
  TaskCostTable task_costs;
  try {
    for (const RunId& id : folder.pending()) {
      throw_if_interrupted();
      const SweepPoint& p = points[static_cast<std::size_t>(id.point)];
      ++number;
      const std::string label = run_label(number, summary.runs, p, id.repetition);
      const RunOutcome out = executor.run(p, id.repetition, label);
      folder.record(id, out.rows);
      task_costs.add(p.scene, p.options, out.task_cpu_ns);
      run_seconds += out.seconds;
      ++summary.ran;
      if (!settings.quiet) {
        fmt::print(
            settings.log, "{}\n",
            run_line(label, out.seconds, out.accuracy ? &*out.accuracy : nullptr,
                     seconds_since(start), run_seconds / summary.ran * (summary.runs - number)));
        std::fflush(settings.log);
      }
    }
  } catch (const std::exception& e) {
    // An interrupt (core/base/interrupt.h) lands here between runs or from inside a run's
    // solve; the run in progress wrote no row.
    folder.fail(e);
    throw;
  }
  folder.complete();
  summary.seconds = seconds_since(start);
  summary.warnings = task_costs.warnings();
  return summary;
}

}  // namespace hrad::experiment
