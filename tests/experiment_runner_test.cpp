// The experiment runner end to end on the Cornell box (milliseconds per run): every
// run lands in runs.csv and iterations.csv, the link counts do not depend on the
// scheduler or thread count, the manifest records how the folder was made, and an
// interrupted experiment resumes without redoing finished runs. Also the CLI.
#include "experiments/harness/experiment_runner.h"
#include "experiments/harness/csv.h"
#include "experiments/harness/manifest.h"
#include "experiments/harness/result_files.h"
#include "experiments/harness/run_rows.h"
#include "experiments/harness/time_estimate.h"
#include "tests/experiment_test_util.h"
#include "tests/read_text.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace hrad::experiment {
namespace {

namespace fs = std::filesystem;

using test::read_text;
using Folder = test::ScratchFolder;

ManifestInputs inputs_for(const ExperimentConfig& c, std::size_t points) {
  return test::manifest_inputs_for(c, points, "runner-test.json");
}

ExperimentConfig small_config() {
  return parse_experiment_config(nlohmann::ordered_json::parse(R"({
    "name": "runner-test", "scenes": ["builtin:cornell"],
    "settings": {"eps": 0.01, "iterations": 2, "image_width": 8},
    "sweep": {"scheduler": ["stack", "blocked"], "threads": [1, 2]},
    "repetitions": 2})"),
                                 "runner-test.json");
}

std::vector<Row> data_rows(const fs::path& file) {
  CsvText t = parse_csv(read_text(file));
  EXPECT_FALSE(t.truncated);
  EXPECT_FALSE(t.rows.empty());
  return {t.rows.begin() + 1, t.rows.end()};
}

TEST(ExperimentRunner, RunsEveryPointAndWritesTheFiles) {
  Folder out("hrad_runner_all");
  const ExperimentConfig c = small_config();
  const auto points = expand_sweep(c);
  RunnerSettings s{out.path, /*quiet=*/true, stderr};
  const ExperimentSummary sum = run_experiment(inputs_for(c, points.size()), points, s);
  EXPECT_EQ(sum.runs, 8);
  EXPECT_EQ(sum.ran, 8);
  EXPECT_EQ(sum.skipped, 0);

  const auto runs = data_rows(out.path / "runs.csv");
  ASSERT_EQ(runs.size(), 8u);
  const auto& rc = run_columns();
  std::set<std::string> links;
  std::set<std::pair<std::string, std::string>> ids;
  for (const Row& r : runs) {
    ASSERT_EQ(r.size(), rc.size());
    links.insert(r[column_index(rc, "links")]);
    ids.insert({r[column_index(rc, "point")], r[column_index(rc, "repetition")]});
    EXPECT_GT(std::stod(r[column_index(rc, "refine_cpu_s")]), 0.0);
    EXPECT_GT(std::stoull(r[column_index(rc, "tasks")]), 0u);
    EXPECT_EQ(r[column_index(rc, "iterations_run")], "2");
    EXPECT_EQ(r[column_index(rc, "eps")], "0.01");
    EXPECT_EQ(r[column_index(rc, "hrad_revision")], "abc");  // inputs_for's
    EXPECT_FALSE(r[column_index(rc, "host")].empty());
    // This host's figures, as the manifest records them; the load at the run's start.
    EXPECT_EQ(r[column_index(rc, "cpu_model")], this_host().cpu_model);
    EXPECT_EQ(r[column_index(rc, "cores")],
              this_host().cores > 0 ? std::to_string(this_host().cores) : "");
    EXPECT_GE(std::stod(r[column_index(rc, "load_avg")]), 0.0);
  }
  EXPECT_EQ(links.size(), 1u) << "links depend on the scheduler or thread count";
  EXPECT_EQ(ids.size(), 8u);
  const auto iterations = data_rows(out.path / "iterations.csv");
  EXPECT_EQ(iterations.size(), 16u);
  const auto& ic = iteration_columns();
  for (const Row& r : iterations) {
    ASSERT_EQ(r.size(), ic.size());
    EXPECT_EQ(r[column_index(ic, "hrad_revision")], "abc");
    EXPECT_EQ(r[column_index(ic, "host")], this_host().hostname);
  }

  const auto m = nlohmann::json::parse(read_text(out.path / "manifest.json"));
  EXPECT_EQ(m["status"], "complete");
  EXPECT_EQ(m["runs_done"], 8);
  EXPECT_EQ(m["experiment"]["name"], "runner-test");
  EXPECT_EQ(m["experiment"]["runs"], 8);
  EXPECT_EQ(m["hrad"]["git_revision"], "abc");
  EXPECT_FALSE(m["hrad"]["compiler"].get<std::string>().empty());
  EXPECT_FALSE(m["hrad"]["cxx_flags"].get<std::string>().empty());
  EXPECT_GE(m["topology"]["pus"].get<int>(), 1);
  EXPECT_TRUE(m["environment"].is_object());
  EXPECT_TRUE(m["machine"].contains("hostname"));
  EXPECT_EQ(m["columns"]["runs"].get<std::vector<std::string>>(), run_columns());
  EXPECT_FALSE(m["finished_at"].is_null());
}

// A run's warnings (here: the scene has no emitter) are printed to the log and kept in
// its runs.csv row.
TEST(ExperimentRunner, PassesOnTheRunsWarnings) {
  Folder out("hrad_runner_warnings", /*create=*/true);
  std::ofstream(out.path / "dark.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
                                          "v 0 0 1\nv 0 1 1\nv 1 1 1\nv 1 0 1\nf 5 6 7 8\n";
  const ExperimentConfig c = parse_experiment_config(
      nlohmann::ordered_json::parse(R"({"name": "dark", "scenes": [")" +
                                    (out.path / "dark.obj").string() + R"("],
        "settings": {"iterations": 1, "image_width": 8}})"),
      "dark.json");
  const auto points = expand_sweep(c);
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  RunnerSettings s{out.path / "run", /*quiet=*/false, log};
  run_experiment(inputs_for(c, points.size()), points, s);
  std::rewind(log);
  std::string text;
  for (int ch; (ch = std::fgetc(log)) != EOF;) text.push_back(static_cast<char>(ch));
  std::fclose(log);
  EXPECT_NE(text.find("hrad: warning: "), std::string::npos) << text;
  EXPECT_NE(text.find("no emitter"), std::string::npos) << text;
  const auto runs = data_rows(out.path / "run" / "runs.csv");
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_NE(runs[0][column_index(run_columns(), "warnings")].find("no emitter"), std::string::npos);
}

TEST(ExperimentRunner, ResumesAnInterruptedRun) {
  Folder out("hrad_runner_resume");
  const ExperimentConfig c = small_config();
  const auto points = expand_sweep(c);
  RunnerSettings s{out.path, true, stderr};
  run_experiment(inputs_for(c, points.size()), points, s);
  const std::string full_runs = read_text(out.path / "runs.csv");

  // Simulate a kill: keep 3 finished runs and half of the 4th row.
  const CsvText t = parse_csv(full_runs);
  std::string partial;
  for (int i = 0; i < 4; ++i) partial += csv_line(t.rows[i]);
  const std::string fourth = csv_line(t.rows[4]);
  partial += fourth.substr(0, fourth.size() / 3);
  std::ofstream(out.path / "runs.csv", std::ios::binary | std::ios::trunc) << partial;

  const ExperimentSummary sum = run_experiment(inputs_for(c, points.size()), points, s);
  EXPECT_EQ(sum.skipped, 3);
  EXPECT_EQ(sum.ran, 5);
  const auto runs = data_rows(out.path / "runs.csv");
  ASSERT_EQ(runs.size(), 8u);
  const auto& rc = run_columns();
  std::set<std::pair<std::string, std::string>> ids;
  for (const Row& r : runs)
    ids.insert({r[column_index(rc, "point")], r[column_index(rc, "repetition")]});
  EXPECT_EQ(ids.size(), 8u);
  // The first three rows are the original ones, untouched.
  for (int i = 1; i < 4; ++i) EXPECT_EQ(runs[i - 1], t.rows[i]);
  EXPECT_EQ(data_rows(out.path / "iterations.csv").size(), 16u);
  const auto m = nlohmann::json::parse(read_text(out.path / "manifest.json"));
  EXPECT_EQ(m["status"], "complete");
  EXPECT_EQ(m["resumed_at"].size(), 1u);

  // Everything done: resuming again runs nothing.
  const ExperimentSummary again = run_experiment(inputs_for(c, points.size()), points, s);
  EXPECT_EQ(again.ran, 0);
  EXPECT_EQ(again.skipped, 8);
}

TEST(ExperimentRunner, RefusesAnotherConfigsFolder) {
  Folder out("hrad_runner_other");
  ExperimentConfig c = small_config();
  c.sweep.pop_back();  // threads fixed at 1: 2 points
  const auto points = expand_sweep(c);
  RunnerSettings s{out.path, true, stderr};
  run_experiment(inputs_for(c, points.size()), points, s);
  const std::string before = read_text(out.path / "runs.csv");

  const ExperimentConfig other = small_config();
  const auto other_points = expand_sweep(other);
  try {
    run_experiment(inputs_for(other, other_points.size()), other_points, s);
    ADD_FAILURE() << "resumed a folder of another configuration";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("different configuration"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_text(out.path / "runs.csv"), before);

  // A folder that is not a result folder is not written into.
  Folder junk("hrad_runner_junk");
  fs::create_directories(junk.path);
  std::ofstream(junk.path / "notes.txt") << "mine";
  RunnerSettings js{junk.path, true, stderr};
  EXPECT_THROW(run_experiment(inputs_for(c, points.size()), points, js), std::runtime_error);
  EXPECT_FALSE(fs::exists(junk.path / "runs.csv"));
}

TEST(ExperimentRunner, ProgressLinesNamePointsAndTimeLeft) {
  Folder out("hrad_runner_progress");
  ExperimentConfig c = small_config();
  c.repetitions = 1;
  c.sweep.pop_back();
  const auto points = expand_sweep(c);
  std::FILE* log = std::tmpfile();
  RunnerSettings s{out.path, false, log};
  run_experiment(inputs_for(c, points.size()), points, s);
  std::rewind(log);
  std::string text(4096, '\0');
  text.resize(std::fread(text.data(), 1, text.size(), log));
  std::fclose(log);
  EXPECT_NE(text.find("[1/2] builtin:cornell scheduler=stack rep 1"), std::string::npos) << text;
  EXPECT_NE(text.find("[2/2]"), std::string::npos) << text;
  EXPECT_NE(text.find("elapsed, ~0:00 left"), std::string::npos) << text;  // last run: none left
}

// The dry run's estimate (time_estimate.h): a point's one-thread time follows the
// pilots' rate to its eps, threads divide it up to the machine's cores.
TEST(TimeEstimate, FollowsThePilotsRateAndTheCores) {
  // Pilots 1 s at eps 4e-4 and 0.25 s at 1.6e-3: t ~ 1/eps (beta = 1).
  EXPECT_NEAR(scaled_estimate(1.0, 0.25, 4e-4, 1e-4, 1, 2), 4.0, 1e-9);
  EXPECT_NEAR(scaled_estimate(1.0, 0.25, 4e-4, 4e-4, 1, 2), 1.0, 1e-9);
  // Two threads on two cores: 2 x 0.9 faster; 16 threads on two cores: no faster.
  EXPECT_NEAR(scaled_estimate(1.0, 0.25, 4e-4, 1e-4, 2, 2), 4.0 / 1.8, 1e-9);
  EXPECT_NEAR(scaled_estimate(1.0, 0.25, 4e-4, 1e-4, 16, 2), 4.0 / 1.8, 1e-9);
  // Fixed costs dominate (the pilots take as long): beta 0, no growth; a slower
  // coarse pilot (noise) does not make finer runs faster.
  EXPECT_NEAR(scaled_estimate(1.0, 1.0, 4e-4, 1e-4, 1, 2), 1.0, 1e-9);
  EXPECT_NEAR(scaled_estimate(1.0, 1.2, 4e-4, 1e-4, 1, 2), 1.0, 1e-9);
  // Steeper than 1.5 is taken as 1.5; pilots too short to time use 0.8.
  EXPECT_NEAR(scaled_estimate(1.0, 0.01, 4e-4, 1e-4, 1, 2), std::pow(4.0, 1.5), 1e-9);
  EXPECT_NEAR(scaled_estimate(0.004, 0.001, 4e-4, 1e-4, 1, 2), 0.004 * std::pow(4.0, 0.8), 1e-12);
  EXPECT_EQ(rough_duration(0.3), "under a second");
  EXPECT_EQ(rough_duration(4.2), "about 5 s");
  EXPECT_EQ(rough_duration(42), "about 40 s");
  EXPECT_EQ(rough_duration(150), "about 3 min");
  EXPECT_EQ(rough_duration(7200), "about 2.0 h");
}

// The command line: bad input leaves nothing behind and says what is wrong.
int run_hrad(const std::string& args, std::string& output) {
  const std::string cmd = std::string(HRAD_BINARY) + " " + args + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  char buf[4096];
  output.clear();
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) output.append(buf, n);
  const int rc = ::pclose(p);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

TEST(ExperimentCli, BadConfigIsAnErrorAndCreatesNothing) {
  Folder d("hrad_cli_experiment");
  fs::create_directories(d.path);
  std::ofstream(d.path / "bad.json")
      << R"({"name": "x", "scenes": ["builtin:cornell"], "sweep": {"thread": [1]}})";
  std::string out;
  EXPECT_EQ(run_hrad("experiment " + (d.path / "bad.json").string() + " --out " +
                         (d.path / "res").string(),
                     out),
            1);
  EXPECT_NE(out.find("unknown option key 'thread'"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(d.path / "res"));
}

TEST(ExperimentCli, QuickRunWithSetAndDryRun) {
  Folder d("hrad_cli_experiment_run");
  fs::create_directories(d.path);
  std::ofstream(d.path / "c.json") << R"({"name": "c", "scenes": ["builtin:cornell"],
    "settings": {"eps": 0.05, "iterations": 1},
    "sweep": {"threads": [1, 2, 3]}, "repetitions": 3,
    "quick": {"sweep": {"threads": [1, 2]}, "repetitions": 1}})";
  std::string out;
  ASSERT_EQ(run_hrad("experiment " + (d.path / "c.json").string() + " --quick --dry-run", out), 0)
      << out;
  EXPECT_NE(out.find("2 points x 1 repetitions = 2 runs"), std::string::npos) << out;
  EXPECT_EQ(out.find("more threads than"), std::string::npos) << out;
  // The dry run estimates each point's time from two pilot solves of the group (the
  // points differ only in threads): eps 0.2 and 0.8 (4 and 16 x 0.05).
  EXPECT_NE(out.find("pilot builtin:cornell: eps 0.8 "), std::string::npos) << out;
  EXPECT_NE(out.find(", eps 0.2 "), std::string::npos) << out;
  EXPECT_NE(out.find("estimated time: "), std::string::npos) << out;
  EXPECT_NE(out.find(" for the 2 runs (the pilots took "), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(d.path / "results"));
  ASSERT_EQ(run_hrad("experiment " + (d.path / "c.json").string() +
                         " --quick --dry-run "
                         "--no-estimate",
                     out),
            0)
      << out;
  EXPECT_EQ(out.find("pilot"), std::string::npos) << out;
  EXPECT_EQ(out.find("estimated time"), std::string::npos) << out;
  // A sweep past this machine's CPUs says so, in --dry-run too (it did not), and the
  // manifest records the load the runs started under.
  ASSERT_EQ(run_hrad("experiment " + (d.path / "c.json").string() +
                         " --quick --dry-run --set sweep.threads=1,1024",
                     out),
            0)
      << out;
  EXPECT_NE(out.find("hrad: warning: 1 of the 2 points ask for more threads than the "),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("(up to 1024): their times measure threads sharing CPUs"), std::string::npos)
      << out;
  ASSERT_EQ(run_hrad("experiment " + (d.path / "c.json").string() +
                         " --quick --set sweep.threads=1 --set repetitions=2 --no-plot --out " +
                         (d.path / "res").string(),
                     out),
            0)
      << out;
  const auto runs = data_rows(d.path / "res" / "runs.csv");
  EXPECT_EQ(runs.size(), 2u);
  const auto m = nlohmann::json::parse(read_text(d.path / "res" / "manifest.json"));
  EXPECT_EQ(m["experiment"]["quick"], true);
  EXPECT_EQ(m["experiment"]["sets"].size(), 2u);
  EXPECT_EQ(m["command_line"][1], "experiment");
  EXPECT_EQ(m["machine"]["load_average"].size(), 3u);
  EXPECT_GE(m["machine"]["cpus_allowed"].get<int>(), 1);
  // Same command again: the folder is complete, nothing reruns.
  ASSERT_EQ(run_hrad("experiment " + (d.path / "c.json").string() +
                         " --quick --set sweep.threads=1 --set repetitions=2 --no-plot --out " +
                         (d.path / "res").string(),
                     out),
            0)
      << out;
  EXPECT_NE(out.find("(0 run now, 2 already done)"), std::string::npos) << out;
  // --resume of a folder made with other --set values is refused.
  EXPECT_EQ(run_hrad("experiment " + (d.path / "c.json").string() + " --quick --no-plot --resume " +
                         (d.path / "res").string(),
                     out),
            1);
  EXPECT_NE(out.find("different configuration"), std::string::npos) << out;
}

}  // namespace
}  // namespace hrad::experiment
