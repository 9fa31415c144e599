// The experiment harness's `accuracy` block (issue 7): strict parsing of the block,
// probe files per scene, the probe error columns of runs.csv, the path-traced
// reference computed once per scene and cached in the result folder (read back on
// resume), and bad probe files reported before anything is created.
#include "experiments/harness/accuracy.h"
#include "experiments/harness/csv.h"
#include "experiments/harness/experiment_runner.h"
#include "experiments/harness/run_rows.h"
#include "tests/experiment_test_util.h"
#include "tests/read_text.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hrad::experiment {
namespace {

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

const std::string kCornellProbes = HRAD_SOURCE_DIR "/tests/data/cornell_probes.txt";

std::string error_of(const std::string& text) {
  try {
    (void)parse_experiment_config(ojson::parse(text), "cfg.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

using test::read_text;
using Folder = test::ScratchFolder;

ManifestInputs inputs_for(const ExperimentConfig& c, std::size_t points) {
  return test::manifest_inputs_for(c, points, "acc-test.json");
}

TEST(ExperimentAccuracy, BlockParsesBothForms) {
  const ExperimentConfig one = parse_experiment_config(ojson::parse(R"({
    "name": "a", "scenes": ["builtin:cornell"],
    "accuracy": {"probes": "p.txt", "reference_rel_error": 0.02, "floor": 0.001,
                 "reference_max_samples": 1000}})"),
                                                       "cfg.json");
  EXPECT_TRUE(one.accuracy.enabled);
  EXPECT_EQ(one.accuracy.reference_rel_error, 0.02);
  EXPECT_EQ(one.accuracy.floor, 0.001);
  EXPECT_EQ(one.accuracy.reference_max_samples, 1000);
  EXPECT_EQ(accuracy_probe_file(one.accuracy, "builtin:cornell"), fs::path("p.txt"));

  ExperimentConfig map = parse_experiment_config(ojson::parse(R"({
    "name": "a", "scenes": ["builtin:cornell", "builtin:office?desks=2", "builtin:furnace"],
    "accuracy": {"probes": {"builtin:cornell": "c.txt", "builtin:office": "o.txt",
                            "builtin:furnace?rho=0.9": "f9.txt",
                            "builtin:furnace": "f.txt"}}})"),
                                                 "cfg.json");
  EXPECT_EQ(map.accuracy.reference_rel_error, 0.005);  // default
  EXPECT_EQ(accuracy_probe_file(map.accuracy, "builtin:office?desks=2"), fs::path("o.txt"));
  EXPECT_EQ(accuracy_probe_file(map.accuracy, "builtin:furnace?rho=0.9"), fs::path("f9.txt"));
  EXPECT_EQ(accuracy_probe_file(map.accuracy, "builtin:furnace"), fs::path("f.txt"));
  EXPECT_TRUE(accuracy_probe_file(map.accuracy, "builtin:lab").empty());
  // A scene's parameters in the comma form find the entry written with '?' and '&'.
  EXPECT_EQ(accuracy_probe_file(map.accuracy, "builtin:office,desks=2"), fs::path("o.txt"));
  EXPECT_EQ(accuracy_probe_file(map.accuracy, "builtin:furnace,rho=0.9"), fs::path("f9.txt"));
  EXPECT_EQ(accuracy_probe_file(map.accuracy, "builtin:furnace,rho=0.5"), fs::path("f.txt"));
  // Relative paths are relative to the config file's folder.
  map.accuracy.base_dir = "/some/dir";
  EXPECT_EQ(accuracy_probe_file(map.accuracy, "builtin:cornell"), fs::path("/some/dir/c.txt"));

  // Round trip through the manifest's JSON.
  const ExperimentConfig back =
      parse_experiment_config(experiment_config_to_json(map), "manifest.json");
  EXPECT_EQ(experiment_config_to_json(back), experiment_config_to_json(map));
  // No block: nothing in the JSON, accuracy off.
  const ExperimentConfig none = parse_experiment_config(
      ojson::parse(R"({"name": "a", "scenes": ["builtin:cornell"]})"), "cfg.json");
  EXPECT_FALSE(none.accuracy.enabled);
  EXPECT_FALSE(experiment_config_to_json(none).contains("accuracy"));
}

TEST(ExperimentAccuracy, BadBlocksAreNamedErrors) {
  const std::string head = R"({"name": "a", "scenes": ["builtin:cornell"], "accuracy": )";
  std::string e = error_of(head + R"({"probes": "p.txt", "refrence": "path"}})");
  EXPECT_NE(e.find("cfg.json"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key 'refrence' in 'accuracy'"), std::string::npos) << e;
  EXPECT_NE(e.find("reference_rel_error"), std::string::npos) << e;  // the valid keys
  e = error_of(head + R"("p.txt"})");
  EXPECT_NE(e.find("'accuracy' must be an object"), std::string::npos) << e;
  e = error_of(head + R"({"reference_rel_error": 0.01}})");
  EXPECT_NE(e.find("needs 'probes'"), std::string::npos) << e;
  for (const char* bad : {R"({"probes": ""})", R"({"probes": 3})", R"({"probes": {}})"}) {
    e = error_of(head + bad + "}");
    EXPECT_NE(e.find("'accuracy.probes' must be"), std::string::npos) << bad << ": " << e;
  }
  e = error_of(head + R"({"probes": {"builtin:cornell": 1}}})");
  EXPECT_NE(e.find("'accuracy.probes.builtin:cornell' must be a file name"), std::string::npos)
      << e;
  for (const char* bad :
       {R"({"probes": "p", "reference_rel_error": 0})",
        R"({"probes": "p", "reference_rel_error": "1"})", R"({"probes": "p", "floor": -1})"}) {
    e = error_of(head + bad + "}");
    EXPECT_NE(e.find("must be a number"), std::string::npos) << bad << ": " << e;
  }
  e = error_of(head + R"({"probes": "p", "reference_max_samples": 0.5}})");
  EXPECT_NE(e.find("'accuracy.reference_max_samples' must be an integer"), std::string::npos) << e;
  // Every scene, the quick ones included, needs a probe file.
  e = error_of(R"({"name": "a", "scenes": ["builtin:cornell", "builtin:lab"],
                   "accuracy": {"probes": {"builtin:cornell": "c.txt"}}})");
  EXPECT_NE(e.find("no probe file for scene 'builtin:lab'"), std::string::npos) << e;
  e = error_of(R"({"name": "a", "scenes": ["builtin:cornell"],
                   "quick": {"scenes": ["builtin:furnace"]},
                   "accuracy": {"probes": {"builtin:cornell": "c.txt"}}})");
  EXPECT_NE(e.find("'builtin:furnace' (in 'quick.scenes')"), std::string::npos) << e;
}

TEST(ExperimentAccuracy, ColumnsAreAppendedAndEmptyWithoutTheBlock) {
  const auto& rc = run_columns();
  const std::vector<std::string> tail(rc.end() - 11, rc.end());
  EXPECT_EQ(tail, (std::vector<std::string>{"started_at", "probe_err_mean", "probe_err_max",
                                            "probe_err_rms", "probe_s", "warnings", "host",
                                            "hrad_revision", "cpu_model", "cores", "load_avg"}));
  SweepPoint p;
  p.scene = "builtin:cornell";
  RunStats stats;
  stats.iterations.resize(1);
  const RunRows none = make_run_rows("c", p, 0, stats, "t");
  ASSERT_EQ(none.run.size(), rc.size());
  EXPECT_EQ(none.run[column_index(rc, "probe_err_mean")], "");
  EXPECT_EQ(none.run[column_index(rc, "probe_s")], "");
  const AccuracyFigures f{0.25, 0.5, 0.375, 0.125};
  const RunRows some = make_run_rows("c", p, 0, stats, "t", &f);
  EXPECT_EQ(some.run[column_index(rc, "probe_err_mean")], "0.25");
  EXPECT_EQ(some.run[column_index(rc, "probe_err_max")], "0.5");
  EXPECT_EQ(some.run[column_index(rc, "probe_err_rms")], "0.375");
  EXPECT_EQ(some.run[column_index(rc, "probe_s")], "0.125");
  EXPECT_EQ(reference_file_name("builtin:office?desks=4&lights=2"),
            "reference-builtin_office_desks_4_lights_2.csv");
  EXPECT_EQ(reference_file_name("builtin:office,desks=4,lights=2"),
            "reference-builtin_office_desks_4_lights_2.csv");
}

ExperimentConfig cornell_config(const std::string& probes) {
  return parse_experiment_config(ojson::parse(R"({
    "name": "acc-test", "scenes": ["builtin:cornell"],
    "settings": {"iterations": 2, "image_width": 8, "min_area": 0.001},
    "sweep": {"eps": [0.01, 0.001]},
    "accuracy": {"probes": ")" + probes + R"(", "reference_rel_error": 0.03}})"),
                                 "acc-test.json");
}

std::vector<Row> data_rows(const fs::path& file) {
  const CsvText t = parse_csv(read_text(file));
  return {t.rows.begin() + 1, t.rows.end()};
}

TEST(ExperimentAccuracy, RunsGetProbeErrorsAndTheReferenceIsCached) {
  Folder out("hrad_accuracy_runs");
  const ExperimentConfig c = cornell_config(kCornellProbes);
  const auto points = expand_sweep(c);
  RunnerSettings s{out.path, /*quiet=*/true, stderr};
  (void)run_experiment(inputs_for(c, points.size()), points, s);

  const fs::path ref = out.path / "reference-builtin_cornell.csv";
  ASSERT_TRUE(fs::is_regular_file(ref));
  ASSERT_TRUE(fs::is_regular_file(out.path / "reference-builtin_cornell.json"));
  const ProbeTable table = read_probe_table(ref);
  EXPECT_EQ(table.probes.size(), 20u);
  EXPECT_EQ(table.std_error.size(), 20u);

  const auto& rc = run_columns();
  auto runs = data_rows(out.path / "runs.csv");
  ASSERT_EQ(runs.size(), 2u);
  for (const Row& r : runs) {
    const double mean = std::stod(r[column_index(rc, "probe_err_mean")]);
    const double max = std::stod(r[column_index(rc, "probe_err_max")]);
    const double rms = std::stod(r[column_index(rc, "probe_err_rms")]);
    // The solver is within ~10% of the path tracer on the Cornell box at these settings.
    EXPECT_GT(mean, 0);
    EXPECT_LT(mean, 0.15);
    EXPECT_LE(mean, rms);
    EXPECT_LE(rms, max);
    EXPECT_GE(std::stod(r[column_index(rc, "probe_s")]), 0);
  }
  const double first_mean = std::stod(runs[0][column_index(rc, "probe_err_mean")]);

  // Interrupt after the first run and double the cached reference: the resumed run
  // must read the cache (its error becomes ~50%) instead of tracing again.
  {
    const CsvText all = parse_csv(read_text(out.path / "runs.csv"));
    std::ofstream(out.path / "runs.csv") << csv_line(all.rows[0]) << csv_line(all.rows[1]);
    const CsvText it = parse_csv(read_text(out.path / "iterations.csv"));
    std::ofstream its(out.path / "iterations.csv");
    for (const Row& r : it.rows)
      if (&r == &it.rows[0] || r[column_index(iteration_columns(), "point")] == "0")
        its << csv_line(r);
    std::string doubled = "x,y,z,nx,ny,nz,E_r,E_g,E_b,SE_r,SE_g,SE_b,samples\n";
    for (std::size_t i = 0; i < table.probes.size(); ++i) {
      const Probe& p = table.probes[i];
      const Rgb e = 2 * table.irradiance[i];
      doubled += fmt::format(
          "{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},"
          "1,1,1,64\n",
          p.p.x(), p.p.y(), p.p.z(), p.n.x(), p.n.y(), p.n.z(), e[0], e[1], e[2]);
    }
    std::ofstream(ref) << doubled;
  }
  const ExperimentSummary again = run_experiment(inputs_for(c, points.size()), points, s);
  EXPECT_EQ(again.ran, 1);
  runs = data_rows(out.path / "runs.csv");
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(std::stod(runs[0][column_index(rc, "probe_err_mean")]), first_mean);
  const double resumed = std::stod(runs[1][column_index(rc, "probe_err_mean")]);
  EXPECT_GT(resumed, 0.4);
  EXPECT_LT(resumed, 0.6);
}

TEST(ExperimentAccuracy, BadProbeFileCreatesNothing) {
  Folder out("hrad_accuracy_bad");
  const fs::path probes = out.path.string() + "-probes.txt";
  std::ofstream(probes) << "1 2 3 0 0\n";  // five numbers
  const ExperimentConfig c = cornell_config(probes.string());
  const auto points = expand_sweep(c);
  RunnerSettings s{out.path, /*quiet=*/true, stderr};
  try {
    (void)run_experiment(inputs_for(c, points.size()), points, s);
    ADD_FAILURE() << "a bad probe file was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find(probes.filename().string()), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(out.path));
  fs::remove(probes);
  // A missing one too.
  const ExperimentConfig missing = cornell_config((out.path / "none.txt").string());
  EXPECT_ANY_THROW((void)run_experiment(inputs_for(missing, points.size()), points, s));
  EXPECT_FALSE(fs::exists(out.path));
}

}  // namespace
}  // namespace hrad::experiment
