// `hrad experiment CONFIG.json [options]`: run an experiment configuration (a sweep
// over scenes and solver options, experiments/harness/experiment_config.h) and write
// its result folder: runs.csv, iterations.csv, manifest.json, then the plots.
//
// Order of events, so that bad input never leaves a folder behind:
//   1. the config is read and checked; --quick, then each --set, are applied;
//   2. the sweep is expanded (every point's options range-checked);
//   3. with --dry-run the points are listed and nothing is written;
//   4. the result folder is created (or reopened: --resume DIR, or --out naming an
//      existing result folder) and the missing runs run (experiment_runner.h);
//   5. the config's plot scripts run on the folder (unless --no-plot).
// Exit status: 0 on success; 1 for bad input or a failed run (message on stderr
// starting with "hrad: "); 2 when the runs succeeded but a plot failed.
//
// Under mpirun with more than one rank (experiments/harness/mpi_sweep.h) every rank
// reads the config; only rank 0 reports, writes and plots, and step 4 is spread over
// the ranks. Every rank leaves through mpi::end once MPI has started.
#include "core/base/input_file.h"
#include "core/base/interrupt.h"
#include "core/base/parse_number.h"
#include "core/config/options_io.h"
#include "core/scene/scene_loader.h"
#include "experiments/commands.h"
#include "experiments/harness/core_share.h"
#include "experiments/harness/csv.h"
#include "experiments/harness/experiment_config.h"
#include "experiments/harness/experiment_runner.h"
#include "experiments/harness/manifest.h"
#include "experiments/harness/mpi_sweep.h"
#include "experiments/harness/plot_runner.h"
#include "experiments/harness/result_files.h"
#include "experiments/harness/sweep.h"
#include "experiments/harness/time_estimate.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace hrad::cli {
namespace {

namespace fs = std::filesystem;
using namespace hrad::experiment;

struct ExperimentArgs {
  std::string config, out, resume, plots_dir, simulated;
  std::vector<std::string> sets;
  bool quick = false, no_plot = false, quiet = false, dry_run = false, no_estimate = false;
  double worker_timeout = 60;
  std::string rank_cores = "share";
};

// The --simulated file, before any run: a curve the speed-up plot can draw (rows of
// `hrad simulate --out`: columns procs and speedup, and rows of kind "simulated" over
// iteration "all" where the file has those columns). Anything else was found only
// after the runs, as a figure whose caption promised a dashed curve it did not draw.
void check_simulated_curve(const std::string& file) {
  check_input_file(file, "the --simulated file");
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const CsvText csv = parse_csv(checked_text(text.str(), file));
  const auto fail = [&](const std::string& why) {
    throw std::invalid_argument(fmt::format(
        "{}: {} (the --simulated file is the CSV of 'hrad simulate --out')", file, why));
  };
  if (csv.rows.empty()) fail("no header line");
  const std::vector<std::string>& head = csv.rows.front();
  const auto column = [&](const char* name) -> std::ptrdiff_t {
    const auto at = std::find(head.begin(), head.end(), name);
    return at == head.end() ? -1 : at - head.begin();
  };
  const std::ptrdiff_t procs = column("procs"), speedup = column("speedup"), kind = column("kind"),
                       iteration = column("iteration");
  if (procs < 0 || speedup < 0) fail("no 'procs' and 'speedup' columns");
  const auto positive = [](const std::string& v) {
    double x = 0;
    return parse_finite_number(v, x) && x > 0;
  };
  std::size_t points = 0;
  for (std::size_t r = 1; r < csv.rows.size(); ++r) {
    const std::vector<std::string>& row = csv.rows[r];
    const auto field = [&](std::ptrdiff_t c) {
      return c >= 0 && static_cast<std::size_t>(c) < row.size() ? row[static_cast<std::size_t>(c)]
                                                                : std::string();
    };
    if (row.size() != head.size())
      fail(fmt::format("data row {} has {} fields where the header has {}", r, row.size(),
                       head.size()));
    if ((kind >= 0 && field(kind) != "simulated") || (iteration >= 0 && field(iteration) != "all"))
      continue;
    if (!positive(field(procs)) || !positive(field(speedup)))
      fail(fmt::format("data row {}: procs '{}' and speedup '{}' must be positive numbers", r,
                       field(procs), field(speedup)));
    ++points;
  }
  if (points == 0)
    fail("no simulated speed-up over all iterations (kind 'simulated', iteration 'all')");
}

// Whether `hrad experiment CONFIG --resume DIR` would carry on: DIR holds the results
// of this configuration (as --quick and --set resolved it) and at least one finished run.
bool resumable(const fs::path& dir, const ExperimentConfig& config) {
  try {
    const auto m = read_manifest(dir);
    // A folder whose runs.csv has another version's columns cannot be resumed either.
    return m.value("runs_done", 0) > 0 &&
           m.value("/experiment/config"_json_pointer, nlohmann::ordered_json()) ==
               experiment_config_to_json(config) &&
           runs_header_matches(dir);
  } catch (const std::exception&) {
    return false;
  }
}

// The command that resumes `dir`, as a shell reads it: a name with a blank or a quote
// in it is quoted (the suggestion broke at the blank).
std::string resume_command(const std::string& config, const fs::path& dir) {
  const auto word = [](const std::string& w) {
    const bool plain = !w.empty() && w.find_first_not_of(
                                         "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "abcdefghijklmnopqrstuvwxyz"
                                         "0123456789_./:=@%+,-") == std::string::npos;
    return plain ? w : shell_quote(w);
  };
  return fmt::format("hrad experiment {} --resume {}", word(config), word(dir.string()));
}

// Points that ask for more refiner threads than this process may run on measure
// threads sharing CPUs, not scaling (a shipped sweep to 32 threads on two CPUs said
// nothing). "" when every point fits.
std::string oversubscription_warning(const std::vector<SweepPoint>& points) {
  const std::size_t cpus = allowed_cpus().size();
  std::size_t over = 0;
  int most = 0;
  for (const SweepPoint& p : points) {
    most = std::max(most, p.options.threads);
    if (static_cast<std::size_t>(p.options.threads) > cpus) ++over;
  }
  if (over == 0) return "";
  return fmt::format(
      "{} of the {} points ask for more threads than the {} CPU(s) this process may use (up "
      "to {}): their times measure threads sharing CPUs, not scaling; run them on a machine "
      "with {} or more, or narrow the sweep (--set sweep.threads=1,2,...)",
      over, points.size(), cpus, most, most);
}

// Reads every scene file of the sweep once for each way its points load it (sides,
// segments), before the result folder is made: a scene that does not parse (an OBJ
// with a bad vertex index) made a folder whose manifest said "failed", and --resume
// failed again the same way. A builtin scene's spec was checked already; it cannot
// fail to build.
void check_scene_files(const std::vector<SweepPoint>& points) {
  std::vector<std::pair<std::string, SceneLoadOptions>> read;
  for (const SweepPoint& p : points) {
    if (p.scene.starts_with("builtin:")) continue;
    std::pair<std::string, SceneLoadOptions> key{p.scene, scene_load_options(p.options)};
    if (std::ranges::find(read, key) != read.end()) continue;
    (void)load_scene(key.first, key.second);
    read.push_back(std::move(key));
  }
}

int run_command(ExperimentArgs a, const CommandContext& ctx) {
  // Started by an MPI launcher with several ranks: rank 0 speaks for all of them.
  const mpi::LaunchInfo launch = mpi::launch_info();
  const bool distributed = launch.size > 1, lead = launch.rank == 0;
  const auto print_error = [lead](std::string_view message) {
    if (lead) cli::print_error(message);
  };
  ExperimentConfig config;
  std::vector<SweepPoint> points;
  try {
    // --resume DIR without --quick or --set resumes as DIR was made: with the --quick
    // and --set its manifest records.
    if (!a.resume.empty() && !a.quick && a.sets.empty() && is_result_folder(a.resume)) {
      const auto m = read_manifest(a.resume);
      a.quick = m.value("/experiment/quick"_json_pointer, false);
      a.sets = m.value("/experiment/sets"_json_pointer, std::vector<std::string>{});
    }
    config = load_experiment_config(a.config);
    if (a.quick) config = apply_quick(config);
    for (const std::string& s : a.sets) apply_experiment_set(config, s);
    points = expand_sweep(config);
    // Before any folder is made: every scene must be one hrad can load, and every plot
    // one there is a script for.
    for (const std::string& s : config.scenes) check_scene_spec(s);
    check_scene_files(points);
    // The simulated curve is read after every run, by the plots: a wrong name or a file
    // that holds no curve would be found only then.
    if (!a.simulated.empty()) check_simulated_curve(a.simulated);
    if (!a.no_plot)
      require_plot_scripts(config.plots,
                           a.plots_dir.empty() ? default_plots_dir() : fs::path(a.plots_dir));
  } catch (const std::exception& e) {
    print_error(e.what());
    return 1;
  }
  if (!a.out.empty() && !a.resume.empty() && fs::path(a.out) != fs::path(a.resume)) {
    print_error("--out and --resume name different folders");
    return 1;
  }
  mpi::Options mpi_options;
  mpi_options.worker_timeout_s = a.worker_timeout;
  mpi_options.cores = a.rank_cores == "inherit" ? mpi::RankCores::Inherit : mpi::RankCores::Share;

  const std::string oversubscribed = distributed ? "" : oversubscription_warning(points);
  if (a.dry_run) {
    if (!lead) return 0;
    fmt::print("{}: {} points x {} repetitions = {} runs\n", config.name, points.size(),
               config.repetitions, points.size() * static_cast<std::size_t>(config.repetitions));
    std::optional<TimeEstimate> est;
    if (!a.no_estimate) {
      fmt::print("  timing pilot solves on this machine (--no-estimate skips them):\n");
      std::fflush(stdout);
      try {
        est = estimate_time(config, points, static_cast<int>(allowed_cpus().size()), stdout, false);
      } catch (const Interrupted& e) {
        print_error(fmt::format("{}: the estimate stopped; nothing was written", e.what()));
        return e.exit_status();
      } catch (const std::exception& e) {
        print_error(fmt::format("estimating the time: {}", e.what()));
        return 1;
      }
    }
    for (const SweepPoint& p : points) {
      const std::string what = describe_point(p);
      if (est)
        fmt::print("  {:4}  {}  {}{}{}\n", p.index, p.scene, what, what.empty() ? "" : "  ",
                   rough_duration(est->point_seconds[static_cast<std::size_t>(p.index)]));
      else
        fmt::print("  {:4}  {}  {}\n", p.index, p.scene, what);
    }
    if (est)
      fmt::print(
          "estimated time: {} for the {} runs (the pilots took {:.1f} s; accuracy references "
          "not counted; threads are taken to run at {:.0f} % of the ideal up to this "
          "machine's {} CPU(s))\n",
          rough_duration(est->total_seconds),
          points.size() * static_cast<std::size_t>(config.repetitions), est->pilot_seconds,
          100 * kParallelEfficiency, allowed_cpus().size());
    std::fflush(stdout);  // the list, then the warning
    if (!oversubscribed.empty()) fmt::print(stderr, "hrad: warning: {}\n", oversubscribed);
    return 0;
  }
  if (!oversubscribed.empty()) fmt::print(stderr, "hrad: warning: {}\n", oversubscribed);

  fs::path dir;
  if (!a.resume.empty()) {
    dir = a.resume;
    if (lead && !is_result_folder(dir)) {
      print_error(
          fmt::format("--resume {}: not an experiment result folder (no manifest.json)", a.resume));
      return 1;
    }
  } else if (!a.out.empty()) {
    dir = a.out;
  } else {
    const fs::path base =
        fs::path("results") / config.name / (now_stamp() + (a.quick ? "-quick" : ""));
    dir = base;
    for (int i = 2; fs::exists(dir); ++i) dir = base.string() + "-" + std::to_string(i);
  }

  ManifestInputs inputs;
  inputs.config = config;
  inputs.config_file = a.config;
  inputs.quick = a.quick;
  inputs.sets = a.sets;
  inputs.command_line = ctx.argv;
  inputs.version = kVersion;
  inputs.git_revision = git_revision();
  inputs.points = static_cast<int>(points.size());

  RunnerSettings settings;
  settings.dir = dir;
  settings.quiet = a.quiet;
  // Once MPI has started, every way out goes through mpi::end.
  const auto leave = [distributed](int status) {
    if (distributed) mpi::end(status);
    return status;
  };
  bool mpi_started = false;
  try {
    if (distributed) {
      mpi::init();
      mpi_started = true;
    }
    const ExperimentSummary s = distributed ? mpi::run_sweep(inputs, points, settings, mpi_options)
                                            : run_experiment(inputs, points, settings);
    if (!lead) return leave(0);
    if (!a.quiet)
      fmt::print(
          "Experiment {}: {} runs ({} run now, {} already done) in {:.1f} s. Results in "
          "{}: runs.csv, iterations.csv, manifest.json.\n",
          config.name, s.runs, s.ran, s.skipped, s.seconds, dir.string());
    for (const std::string& w : s.warnings) fmt::print(stderr, "hrad: warning: {}\n", w);
  } catch (const Interrupted& e) {
    // The manifest says "interrupted"; the finished runs' rows are complete.
    print_error(fmt::format("{}: the experiment stopped; {}", e.what(),
                            resumable(dir, config) ? "finished runs are kept; resume with: " +
                                                         resume_command(a.config, dir)
                                                   : std::string("no run had finished")));
    return mpi_started ? leave(e.exit_status()) : e.exit_status();
  } catch (const std::exception& e) {
    if (distributed && !lead) {
      // A worker's own failure (rank 0 reports failed runs): say which rank.
      fmt::print(stderr, "hrad: rank {}: {}\n", launch.rank, e.what());
      return mpi_started ? leave(1) : 1;
    }
    print_error(e.what());
    if (resumable(dir, config))
      fmt::print(stderr, "hrad: finished runs are kept; resume with: {}\n",
                 resume_command(a.config, dir));
    return mpi_started ? leave(1) : 1;
  }

  std::fflush(stdout);  // the summary before the plots' own lines
  if (a.no_plot) return leave(0);
  std::vector<std::string> extra;
  if (!a.simulated.empty()) extra = {"--simulated", a.simulated};
  const fs::path plots_dir = a.plots_dir.empty() ? default_plots_dir() : fs::path(a.plots_dir);
  return leave(run_plots(config.plots, dir, plots_dir, extra, stderr) ? 0 : 2);
}

}  // namespace

void register_experiment(CLI::App& app, CommandContext& ctx) {
  auto args = std::make_shared<ExperimentArgs>();
  CLI::App* sub = app.add_subcommand(
      "experiment",
      "Run an experiment configuration (a sweep over scenes and options) and write "
      "runs.csv, iterations.csv, manifest.json and its plots.");
  sub->add_option("CONFIG", args->config,
                  "Experiment configuration (JSON; see docs/experiments.md)")
      ->required();
  sub->add_flag("--quick", args->quick,
                "Apply the config's 'quick' overrides (smaller scenes, fewer points and "
                "repetitions): a whole config in under a minute");
  sub->add_option("--set", args->sets,
                  "Override after the config (and --quick): an option key fixes that option "
                  "(removing it from the sweep), 'sweep.KEY=V1,V2,...' sweeps it, 'repetitions=N', "
                  "'scenes=SPEC[,SPEC...]'; "
                  "repeatable")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  sub->add_option("-o,--out", args->out,
                  "Result folder [default: results/<name>/<YYYYmmdd-HHMMSS>[-quick]/]; an "
                  "existing result folder of the same configuration is resumed")
      ->type_name("DIR");
  sub->add_option("--resume", args->resume,
                  "Resume an interrupted experiment in DIR: runs already in its runs.csv are "
                  "skipped (same config; without --quick or --set, those DIR's manifest "
                  "records apply)")
      ->type_name("DIR");
  sub->add_flag("--no-plot", args->no_plot, "Do not run the plot scripts at the end");
  sub->add_option("--plots-dir", args->plots_dir,
                  "Folder of the plot scripts [default: $HRAD_PLOTS_DIR, else the source "
                  "tree's plots/]")
      ->type_name("DIR");
  sub->add_option("--simulated", args->simulated,
                  "Simulated speedup CSV (from 'hrad simulate') for the speedup plot to draw "
                  "dashed")
      ->type_name("FILE");
  sub->add_flag("--dry-run", args->dry_run,
                "List the points with an estimate of each one's time and exit; nothing is "
                "written. The estimate comes from two one-thread pilot solves per group "
                "of points that differ only in eps and in how they run in parallel "
                "(docs/experiments.md)");
  sub->add_flag("--no-estimate", args->no_estimate,
                "With --dry-run: list the points only, without the pilot solves");
  sub->add_flag("--quiet", args->quiet, "No progress lines and no summary");
  sub->add_option("--worker-timeout", args->worker_timeout,
                  "Under mpirun: seconds without a heartbeat after which a worker rank is taken "
                  "for dead and its run handed to another (needs mpirun --enable-recovery) "
                  "[default: 60]")
      ->type_name("SECONDS")
      ->check(number_in(0.001, 1e6));
  sub->add_option("--rank-cores", args->rank_cores,
                  "Under mpirun: 'share' splits a host's CPUs between the worker ranks on it "
                  "(launch with --bind-to none); 'inherit' keeps the launcher's binding (one "
                  "rank per host) [default: share]")
      ->type_name("share|inherit")
      ->check(CLI::IsMember({"share", "inherit"}));
  sub->callback([args, &ctx] {
    install_interrupt_handlers();  // stops at a safe point (core/base/interrupt.h)
    ctx.status = run_command(*args, ctx);
  });
}

}  // namespace hrad::cli
