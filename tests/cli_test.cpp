// End-to-end tests of the hrad binary (HRAD_BINARY): help, errors, and real solves
// into a temporary folder.
#include "oracles/oracle.h"
#include "schedulers/scheduler.h"
#include "tests/cli_fixture.h"
#include "tests/read_text.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using hrad::test::Cli;
using hrad::test::contains;
using hrad::test::read_text;
using hrad::test::Result;

TEST_F(Cli, HelpListsEverySubcommand) {
  const Result r = hrad("--help");
  EXPECT_EQ(r.status, 0) << r.err;
  for (const char* sub : {"solve", "experiment", "scenes", "topology", "--version"})
    EXPECT_TRUE(contains(r.out, sub)) << sub << "\n" << r.out;
}

// hrad runs with GOMP_SPINCOUNT=10000 (experiments/openmp_spin.h) unless the user set
// GOMP_SPINCOUNT or OMP_WAIT_POLICY; libgomp shows what it runs with (OMP_DISPLAY_ENV).
TEST_F(Cli, RunsWithABoundedOpenMpSpinUnlessTheUserChose) {
  const auto spin = [&](const std::string& env) {
    const Result r = hrad("--version", "OMP_DISPLAY_ENV=verbose " + env);
    EXPECT_EQ(r.status, 0) << r.err;
    // The last block is the one of the process that ran (after executing itself again).
    const std::size_t at = r.err.rfind("GOMP_SPINCOUNT = '");
    if (at == std::string::npos) return std::string("(not shown)\n") + r.err;
    const std::size_t begin = at + 18;
    return r.err.substr(begin, r.err.find('\'', begin) - begin);
  };
  EXPECT_EQ(spin("env -u GOMP_SPINCOUNT -u OMP_WAIT_POLICY -u LD_PRELOAD "), "10000");
  EXPECT_EQ(spin("env -u OMP_WAIT_POLICY -u LD_PRELOAD GOMP_SPINCOUNT=7 "), "7");
  EXPECT_EQ(spin("env -u GOMP_SPINCOUNT -u LD_PRELOAD OMP_WAIT_POLICY=passive "), "0");
}

TEST_F(Cli, SolveHelpMentionsEveryOption) {
  const Result r = hrad("solve --help");
  EXPECT_EQ(r.status, 0) << r.err;
  for (const char* opt :
       {"--scheduler",  "--block-size", "--threads",   "--oracle", "--eps",    "--min-area",
        "--iterations", "--pin",        "--placement", "--probes", "--image",  "--out",
        "--seed",       "--config",     "--set",       "--quiet",  "--camera", "--view",
        "--shading",    "--exposure",   "--hdr",       "SCENE"})
    EXPECT_TRUE(contains(r.out, opt)) << opt << "\n" << r.out;
  EXPECT_TRUE(contains(r.out, "default 4"));  // --iterations shows its default
}

// The plug-in names come from the registries, so a new scheduler or oracle is listed
// without editing the help.
TEST_F(Cli, SolveHelpListsTheRegisteredSchedulersAndOracles) {
  const Result r = hrad("solve --help");
  EXPECT_EQ(r.status, 0) << r.err;
  const std::string schedulers = fmt::format("{}", fmt::join(hrad::scheduler_names(), ", "));
  const std::string oracles = fmt::format("{}", fmt::join(hrad::oracle_names(), ", "));
  EXPECT_TRUE(contains(r.out, "by name: " + schedulers + "; parameters")) << r.out;
  EXPECT_TRUE(contains(r.out, "by name: " + oracles + "; parameters")) << r.out;
  // ... and each declared parameter with its range and default.
  EXPECT_TRUE(contains(r.out, "stealing.victims (integer 0 ... 4096, default 0)")) << r.out;
  EXPECT_TRUE(contains(r.out, "bf.dark_floor (number 0.001 ... 1, default 0.25)")) << r.out;
}

TEST_F(Cli, VersionNamesProgramAndRevision) {
  const Result r = hrad("--version");
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(contains(r.out, "hrad ")) << r.out;
  EXPECT_TRUE(contains(r.out, "git ")) << r.out;
}

TEST_F(Cli, UnknownOptionIsNamedAndFails) {
  const Result r = hrad("solve builtin:cornell --no-such-flag 3 --out run");
  EXPECT_NE(r.status, 0);
  EXPECT_TRUE(contains(r.err, "--no-such-flag")) << r.err;
  EXPECT_EQ(entries(), 0);
  EXPECT_NE(hrad("frobnicate").status, 0);
}

// The traps of a first hour at the command line: bare `hrad` (CLI11 said "A subcommand
// is required"), -o and -t (its raw "The following arguments were not expected: out
// -o"), a configuration key given as a flag, a built-in scene's name without
// `builtin:`, and a stats.json as --config.
TEST_F(Cli, FirstHourTraps) {
  Result r = hrad("");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.out, "Subcommands:") && contains(r.out, "solve")) << r.out;

  r = hrad("solve builtin:cornell --max-memory-gb 4");
  EXPECT_NE(r.status, 0);
  EXPECT_TRUE(contains(r.err, "hrad: solve: ")) << r.err;
  EXPECT_TRUE(contains(r.err, "use --set max_memory_gb=VALUE")) << r.err;
  EXPECT_TRUE(contains(r.err, "(see hrad solve --help)")) << r.err;

  r = hrad("solve cornell");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "did you mean builtin:cornell?")) << r.err;
  r = hrad("solve office.obj");
  EXPECT_TRUE(contains(r.err, "the file does not exist (did you mean builtin:office?)")) << r.err;
  EXPECT_EQ(entries(), 0);

  r = hrad("solve builtin:cornell -t 2 -o first --set eps=1e-3 --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto first = nlohmann::json::parse(read_text(dir_ / "first" / "stats.json"));
  EXPECT_EQ(first["config"]["threads"], 2);
  // The run's stats.json as the configuration of the next: the same settings.
  r = hrad("solve builtin:cornell --config first/stats.json -o again --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto again = nlohmann::json::parse(read_text(dir_ / "again" / "stats.json"));
  EXPECT_EQ(again["config"], first["config"]);
  // Without SCENE, the stats.json's own scene: the same run again.
  r = hrad("solve --config first/stats.json -o third --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto third = nlohmann::json::parse(read_text(dir_ / "third" / "stats.json"));
  EXPECT_EQ(third["scene"]["source"], "builtin:cornell");
  EXPECT_TRUE(third["scene"]["path"].is_null());
  EXPECT_EQ(third["config"], first["config"]);
  EXPECT_EQ(third["totals"]["links"], first["totals"]["links"]);
  // A config that is no stats.json does not name a scene.
  write("plain.json", R"({"eps": 1e-3})");
  r = hrad("solve --config plain.json -o none --quiet");
  EXPECT_NE(r.status, 0);
  EXPECT_TRUE(contains(r.err, "hrad: solve: SCENE is missing")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "none"));
  // One that cannot be read says why, not that SCENE is missing.
  refused("solve --config /dev/zero -o none --quiet",
          "/dev/zero: the config file is not a regular file");
  write("broken.json", "{\"totals\": ");
  refused("solve --config broken.json -o none --quiet", "broken.json:");

  // The automatic camera with only its up axis given.
  r = hrad("solve builtin:cornell --camera up=1,0,0 -o up --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto up = nlohmann::json::parse(read_text(dir_ / "up" / "stats.json"));
  EXPECT_EQ(up["camera"]["source"], "automatic");
  EXPECT_EQ(up["camera"]["up"], nlohmann::json::array({1.0, 0.0, 0.0}));
}

// `hrad solve --config RUN/stats.json` with no SCENE solves that run's scene again, from
// any folder: stats.json keeps the scene file's absolute path beside its name as given.
TEST_F(Cli, AStatsJsonAloneRunsItsSceneAgain) {
  fs::create_directories(dir_ / "scenes");
  fs::create_directories(dir_ / "elsewhere");
  write("scenes/box.obj",
        "mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\n"
        "v 0 1 1\nusemtl wall\nf 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\n"
        "usemtl light\nf 1 4 8 5\n");
  write("scenes/box.mtl", "newmtl wall\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0 0 0\nKe 1 1 1\n");
  Result r = hrad("solve scenes/box.obj -o first --set eps=1e-3 --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto first = nlohmann::json::parse(read_text(dir_ / "first" / "stats.json"));
  EXPECT_EQ(first["scene"]["source"], "scenes/box.obj");
  // (the same file, whatever symbolic links the temporary folder's path holds)
  EXPECT_EQ(fs::canonical(first["scene"]["path"].get<std::string>()),
            fs::canonical(dir_ / "scenes" / "box.obj"));
  r = hrad("solve --config ../first/stats.json -o again --quiet", "cd elsewhere && ");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto again = nlohmann::json::parse(read_text(dir_ / "elsewhere" / "again" / "stats.json"));
  EXPECT_EQ(again["scene"]["path"], first["scene"]["path"]);
  EXPECT_EQ(again["config"], first["config"]);
  EXPECT_EQ(again["totals"]["links"], first["totals"]["links"]);
}

// Command-line errors in hrad's words, naming the option, none of CLI11's wording
// ("The following arguments were not expected", "Value x not in range", "required ...
// missing", "A subcommand is required"); the exit statuses stay as they were.
TEST_F(Cli, ParseErrorsNameTheOptionInPlainWords) {
  const auto says = [](const Result& r, const std::string& text) {
    EXPECT_TRUE(contains(r.err, text)) << r.err;
    for (const char* cli11 :
         {"not expected", "not in range", "required", "subcommand", "Could not convert"})
      EXPECT_FALSE(contains(r.err, cli11)) << r.err;
  };
  Result r = hrad("solve builtin:cornell --bogus 1 --out run");
  EXPECT_EQ(r.status, 109);
  says(r, "hrad: solve: unknown option --bogus (see hrad solve --help)\n");
  r = hrad("solve builtin:cornell --thread 2 --out run");
  EXPECT_EQ(r.status, 109);
  says(r, "hrad: solve: unknown option --thread (did you mean --threads?) (see hrad solve --help)");
  r = hrad("solve builtin:cornell extra --out run");
  EXPECT_EQ(r.status, 109);
  says(r, "hrad: solve: unexpected argument 'extra' (see hrad solve --help)");
  r = hrad("solve builtin:cornell --out");
  EXPECT_NE(r.status, 0);
  says(r, "hrad: solve: --out needs a value (DIR) (see hrad solve --help)");
  r = hrad("solve");
  EXPECT_NE(r.status, 0);
  says(r, "hrad: solve: SCENE is missing (see hrad solve --help)");
  // An unknown option is named even where a positional is missing too.
  r = hrad("experiment --bogus");
  EXPECT_NE(r.status, 0);
  says(r, "hrad: experiment: unknown option --bogus (see hrad experiment --help)");
  r = hrad("reference --thread 2 --out ref");
  EXPECT_NE(r.status, 0);
  says(r, "hrad: reference: unknown option --thread (did you mean --threads?)");
  r = hrad("reference builtin:cornell --random-probes x --out ref");
  EXPECT_EQ(r.status, 1);
  says(r, "hrad: reference: --random-probes: 'x' is not an integer in 1..1048576");
  r = hrad("reference builtin:cornell --random-probes 0 --out ref");
  EXPECT_EQ(r.status, 1);
  says(r, "hrad: reference: --random-probes: 0 is outside 1..1048576");
  r = hrad("reference builtin:cornell --random-probes 2 --rel-error abc --out ref");
  EXPECT_EQ(r.status, 1);
  says(r, "hrad: reference: --rel-error: 'abc' is not a number in 1e-06..1");
  r = hrad("experiment e.json --rank-cores some");
  EXPECT_EQ(r.status, 1);
  says(r, "hrad: experiment: --rank-cores: 'some' is not one of share, inherit");
  r = hrad("--bogus");
  EXPECT_EQ(r.status, 106);
  says(r, "hrad: unknown option --bogus (see hrad --help)");
  EXPECT_EQ(entries(), 0);
}

TEST_F(Cli, MissingSceneFileNamesItAndCreatesNoFolder) {
  Result r = hrad("solve no_such_scene.obj --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "no_such_scene.obj")) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  // Neither the given folder nor a default results/ folder appears.
  r = hrad("solve no_such_scene.mgf");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "no_such_scene.mgf")) << r.err;
  EXPECT_EQ(entries(), 0);
}

TEST_F(Cli, BadOptionsAreNamedAndCreateNoFolder) {
  Result r = hrad("solve builtin:cornell --set colour=red --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "colour")) << r.err;
  r = hrad("solve builtin:cornell --threads 0 --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "threads")) << r.err;
  r = hrad("solve builtin:cornell --eps abc --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "--eps") && contains(r.err, "abc")) << r.err;
  r = hrad("solve builtin:cornell --scheduler no-such-scheduler --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "no-such-scheduler")) << r.err;
  EXPECT_EQ(entries(), 0);
  write("bad.json", R"({"thread": 2})");
  r = hrad("solve builtin:cornell --config bad.json --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "bad.json") && contains(r.err, "'thread'")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "run"));
  // A flag's value that the command line's own checks refuse is bad input too: status
  // 1 as above (it was CLI11's 105 or 104), in every command; a syntax error keeps
  // CLI11's code (109: an unexpected argument).
  r = hrad("reference builtin:cornell --threads 0 --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "--threads")) << r.err;
  r = hrad("reference builtin:cornell --seed nan --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "--seed")) << r.err;
  r = hrad("compare a.csv b.csv --floor -1");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "--floor")) << r.err;
  EXPECT_EQ(hrad("solve builtin:cornell extra --out run").status, 109);
  EXPECT_FALSE(fs::exists(dir_ / "run"));
}

TEST_F(Cli, SolveWritesStatsMeshAndImage) {
  const Result r = hrad("solve builtin:cornell --iterations 1 --out run");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "run")) << r.out;  // the summary says where results are
  EXPECT_TRUE(contains(r.out, "links")) << r.out;

  const nlohmann::json j = nlohmann::json::parse(read_text(dir_ / "run" / "stats.json"));
  for (const char* key : {"hrad", "command_line", "started_at", "config", "scene", "topology",
                          "iterations", "totals", "warnings", "outputs"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j["hrad"]["git_revision"].is_string());
  EXPECT_EQ(j["config"]["iterations"], 1);
  EXPECT_EQ(j["config"]["scheduler"], "blocked");
  EXPECT_EQ(j["scene"]["name"], "cornell");
  EXPECT_GT(j["scene"]["polygons"].get<int>(), 0);
  EXPECT_GE(j["scene"]["emitters"].get<int>(), 1);
  ASSERT_EQ(j["iterations"].size(), 1u);
  for (const char* key : {"refine_wall_s", "refine_cpu_s", "propagate_wall_s", "links_created",
                          "links", "elements", "bytes", "peak_rss_bytes", "tasks", "scheduler_ops",
                          "lock_wait_s", "idle_s", "rays_cast", "rays_skipped", "gather_sweeps"})
    EXPECT_TRUE(j["iterations"][0].contains(key)) << key;
  // The propagation's parts: its preparation's three (each measured, so above zero),
  // then the sweeps; the bookkeeping between them only adds.
  const nlohmann::json& first = j["iterations"][0];
  const double parts = first["open_s"].get<double>() + first["push_weights_s"].get<double>() +
                       first["row_sums_s"].get<double>();
  EXPECT_GT(first["open_s"].get<double>(), 0);
  EXPECT_GT(first["push_weights_s"].get<double>(), 0);
  EXPECT_GT(first["row_sums_s"].get<double>(), 0);
  EXPECT_LE(parts, first["prepare_s"].get<double>());
  EXPECT_LE(first["prepare_s"].get<double>() + first["sweeps_s"].get<double>(),
            first["propagate_wall_s"].get<double>());
  for (const char* key : {"wall_s", "refine_wall_s", "refine_cpu_s", "links", "elements",
                          "rays_cast", "rays_skipped", "peak_rss_bytes"})
    EXPECT_TRUE(j["totals"].contains(key)) << key;
  EXPECT_GT(j["totals"]["links"].get<long>(), 0);
  EXPECT_EQ(j["outputs"]["mesh"], "solution.ply");
  EXPECT_EQ(j["outputs"]["image"], "render.png");
  EXPECT_EQ(j["command_line"][1], "solve");

  EXPECT_EQ(read_text(dir_ / "run" / "solution.ply").substr(0, 4), "ply\n");
  EXPECT_EQ(read_text(dir_ / "run" / "render.png").substr(0, 8), "\x89PNG\r\n\x1a\n");
  // Nothing else: no temporaries, no probes.csv without --probes.
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_ / "run")) ++files;
  EXPECT_EQ(files, 3);
}

TEST_F(Cli, PrecedenceConfigFlagsSet) {
  write("c.json", R"({"iterations": 1, "eps": 0.5, "min_area": 0.01, "seed": 9})");
  const Result r = hrad(
      "solve builtin:cornell --config c.json --eps 0.25 --min-area 0.05 --set min_area=0.02 "
      "--quiet --out run");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;  // --quiet: no summary
  const nlohmann::json j = nlohmann::json::parse(read_text(dir_ / "run" / "stats.json"));
  EXPECT_EQ(j["config"]["iterations"], 1);  // config beats the default
  EXPECT_EQ(j["config"]["seed"], 9);
  EXPECT_EQ(j["config"]["eps"], 0.25);       // flag beats config
  EXPECT_EQ(j["config"]["min_area"], 0.02);  // --set beats flag
  EXPECT_EQ(j["config_file"], "c.json");
  EXPECT_EQ(j["iterations"].size(), 1u);
}

TEST_F(Cli, ProbesAndImageElsewhere) {
  write("p.txt", "# floor and ceiling\n2.78 0.01 2.79 0 1 0\n2.78 5.4 2.79 0 -1 0\n");
  const Result r = hrad(
      "solve builtin:cornell --iterations 1 --probes p.txt --image pics/cornell.png --out run "
      "--set image_width=64");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(read_text(dir_ / "pics" / "cornell.png").substr(0, 4), "\x89PNG");
  EXPECT_FALSE(fs::exists(dir_ / "run" / "render.png"));
  const std::string csv = read_text(dir_ / "run" / "probes.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "x,y,z,nx,ny,nz,E_r,E_g,E_b");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
  const nlohmann::json j = nlohmann::json::parse(read_text(dir_ / "run" / "stats.json"));
  EXPECT_EQ(j["outputs"]["image"], "pics/cornell.png");
  EXPECT_EQ(j["outputs"]["probes"], "probes.csv");
}

// --explain-probe N takes probe N's final gather apart: its total is probes.csv's value,
// its leaves come strongest first, and the strongest one's chain runs up to the root.
TEST_F(Cli, ExplainProbeTakesTheFinalGatherApart) {
  write("p.txt", "2.78 0.01 2.79 0 1 0\n2.78 5.4 2.79 0 -1 0\n");
  refused("solve builtin:cornell --explain-probe 0 --out run", "--explain-probe 0: needs --probes");
  refused("solve builtin:cornell --probes p.txt --explain-probe 2 --out run",
          "--explain-probe 2: p.txt holds probes 0..1");
  const Result r = hrad("solve builtin:cornell --probes p.txt --explain-probe 1 --out run --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json stats = nlohmann::json::parse(read_text(dir_ / "run" / "stats.json"));
  EXPECT_EQ(stats["outputs"]["explain"], nlohmann::json::array({"explain-probe-1.json"}));
  const nlohmann::json x = nlohmann::json::parse(read_text(dir_ / "run" / "explain-probe-1.json"));
  EXPECT_EQ(x["probe"], 1);
  EXPECT_FALSE(x["closed_in"].get<bool>());
  // The total is the probe's irradiance in probes.csv (written with 9 digits).
  std::istringstream csv(read_text(dir_ / "run" / "probes.csv"));
  std::string line;
  for (int k = 0; k < 3; ++k) std::getline(csv, line);  // header, probe 0, probe 1
  std::vector<double> fields;
  std::istringstream row(line);
  for (std::string f; std::getline(row, f, ',');) fields.push_back(std::stod(f));
  ASSERT_EQ(fields.size(), 9u);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(x["irradiance"][c].get<double>(), fields[6 + static_cast<std::size_t>(c)],
                1e-8 * fields[6 + static_cast<std::size_t>(c)]);
  // Leaves strongest first, each F x V x B of its own numbers.
  const auto& leaves = x["strongest_leaves"];
  ASSERT_GE(leaves.size(), 2u);
  double last = std::numeric_limits<double>::infinity();
  for (const auto& l : leaves) {
    double mean = 0;
    for (int c = 0; c < 3; ++c) {
      const double e = l["irradiance"][c].get<double>();
      EXPECT_NEAR(e,
                  l["form_factor"].get<double>() * l["visibility"].get<double>() *
                      l["radiosity"][c].get<double>(),
                  1e-12 + 1e-9 * e);
      mean += e / 3;
    }
    EXPECT_LE(mean, last);
    last = mean;
  }
  // The chain: the strongest leaf first, the root cluster last.
  const auto& chain = x["strongest_leaf_chain"];
  ASSERT_GE(chain.size(), 2u);
  EXPECT_EQ(chain.front()["area"], leaves.front()["area"]);
  EXPECT_EQ(chain.front()["kind"], "surface");
  EXPECT_EQ(chain.back()["kind"], "cluster");
  EXPECT_EQ(chain.back()["depth"], 0);
  // A point on the floor under the short block sees only the block's inside.
  write("under.txt", "1.855 0.001 1.69 0 1 0\n");
  ASSERT_EQ(
      hrad("solve builtin:cornell --probes under.txt --explain-probe 0 --out under --quiet").status,
      0);
  const nlohmann::json u =
      nlohmann::json::parse(read_text(dir_ / "under" / "explain-probe-0.json"));
  EXPECT_TRUE(u["closed_in"].get<bool>());
  EXPECT_EQ(u["irradiance"], nlohmann::json::array({0.0, 0.0, 0.0}));
  EXPECT_FALSE(u.contains("strongest_leaves"));
  // A later run into the same folder does not leave the explanation behind.
  ASSERT_EQ(hrad("solve builtin:cornell --probes p.txt --out run --quiet").status, 0);
  EXPECT_FALSE(fs::exists(dir_ / "run" / "explain-probe-1.json"));
  refused("solve builtin:cornell --probes p.txt --explain-probe 99999999999999999999 --out x",
          "--explain-probe: 99999999999999999999 is outside 0..4294967296");
}

TEST_F(Cli, FailedWriteIsReportedInStatsAndExitStatus) {
  write("blocker", "a file, not a folder");
  const Result r = hrad(
      "solve builtin:cornell --iterations 1 --image blocker/x.png --out run --set image_width=64");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "blocker")) << r.err;
  // What was written stays, complete; stats.json records the error; no temporaries.
  const nlohmann::json j = nlohmann::json::parse(read_text(dir_ / "run" / "stats.json"));
  EXPECT_TRUE(contains(j.at("error").get<std::string>(), "blocker"));
  EXPECT_EQ(j["outputs"]["mesh"], "solution.ply");
  EXPECT_FALSE(j["outputs"].contains("image"));
  for (const auto& e : fs::directory_iterator(dir_ / "run"))
    EXPECT_FALSE(contains(e.path().filename().string(), ".tmp")) << e.path();
}

TEST_F(Cli, BadProbeFileFailsBeforeAnyOutput) {
  write("p.txt", "1 2 3\n");
  const Result r = hrad("solve builtin:cornell --probes p.txt --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "p.txt:1")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "run"));
}

TEST_F(Cli, ScenesListsBuiltinsAndFormats) {
  const Result r = hrad("scenes");
  EXPECT_EQ(r.status, 0) << r.err;
  for (const char* s : {"builtin:cornell", "builtin:furnace", "builtin:office", "builtin:lab",
                        "builtin:cabin", "default", "range", ".obj", ".mgf", "pi * Ke",
                        "builtin:office,desks=40,lights=6", "'builtin:NAME?key=value&key=value'"})
    EXPECT_TRUE(contains(r.out, s)) << s;
}

// A built-in scene's parameters with commas: no quoting in the shell (the fixture runs
// the command through sh), the same scene as the quoted '?' and '&' form, and the
// spec kept as given in stats.json.
TEST_F(Cli, BuiltinParametersNeedNoQuoting) {
  Result r = hrad("solve builtin:cornell,blocks=0,light=2 --iterations 1 --out comma --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  r = hrad("solve 'builtin:cornell?blocks=0&light=2' --iterations 1 --out query --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto comma = nlohmann::json::parse(read_text(dir_ / "comma" / "stats.json"));
  const auto query = nlohmann::json::parse(read_text(dir_ / "query" / "stats.json"));
  EXPECT_EQ(comma["scene"]["source"], "builtin:cornell,blocks=0,light=2");
  EXPECT_EQ(comma["scene"]["name"], "cornell");
  EXPECT_EQ(comma["scene"]["polygons"], 6);
  EXPECT_EQ(comma["scene"]["polygons"], query["scene"]["polygons"]);
  EXPECT_EQ(comma["scene"]["emitted_power"], query["scene"]["emitted_power"]);
  r = hrad("solve builtin:cornell,blocks=0,nosuch=1 --out bad");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "unknown parameter 'nosuch'")) << r.err;
  r = hrad("solve cornell,blocks=0 --out bad");
  EXPECT_TRUE(contains(r.err, "did you mean builtin:cornell,blocks=0?")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

// What a person reads gives relative errors in percent, as `hrad compare` does; the
// files keep fractions.
TEST_F(Cli, ReferenceAndExperimentPrintPercent) {
  Result r = hrad("reference builtin:furnace --random-probes 3 --rel-error 0.05 --out ref");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "converged to 5 % relative error")) << r.out;
  EXPECT_FALSE(contains(r.out, "0.05")) << r.out;
  const auto j = nlohmann::json::parse(read_text(dir_ / "ref" / "reference.json"));
  EXPECT_EQ(j["options"]["rel_error"], 0.05);
  r = hrad(
      "reference builtin:furnace --random-probes 2 --rel-error 1e-6 --max-samples 1024 --out "
      "short");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "did not reach 0.0001 % relative error")) << r.err;

  write("p.txt", "0.5 0.01 0.5 0 1 0\n");
  write("e.json", R"({"name": "e", "scenes": ["builtin:furnace,objects=0"],
    "settings": {"iterations": 1},
    "accuracy": {"probes": "p.txt", "reference_rel_error": 0.05}})");
  r = hrad("experiment e.json --out x --no-plot");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out + r.err, "(1 probes, 5 % relative error)")) << r.out << r.err;
  EXPECT_FALSE(contains(r.out + r.err, "0.05 relative")) << r.out << r.err;
}

TEST_F(Cli, TopologyHonoursSyntheticMachines) {
  Result r = hrad("topology");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "NUMA node")) << r.out;
  r = hrad("topology", "HWLOC_SYNTHETIC='node:2 core:2 pu:1' ");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "2 NUMA nodes, 4 cores")) << r.out;
}

// The harness itself is tested in experiment_*_test.cpp; here only its bad input.
TEST_F(Cli, ExperimentRejectsBadConfigs) {
  Result r = hrad("experiment missing.json");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "missing.json")) << r.err;
  write("e.json", "{}");
  r = hrad("experiment e.json");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "e.json: missing key 'name'")) << r.err;
}

}  // namespace
