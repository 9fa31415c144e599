// Sweep expansion (order, counts, options of each point) and the flat rows of
// runs.csv / iterations.csv made from RunStats.
#include "core/config/options_io.h"
#include "core/output/stat_fields.h"
#include "core/output/stats_json.h"
#include "experiments/harness/run_rows.h"
#include "experiments/harness/sweep.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <set>

namespace hrad::experiment {
namespace {

ExperimentConfig config() {
  return parse_experiment_config(nlohmann::ordered_json::parse(R"({
    "name": "s", "scenes": ["builtin:cornell", "builtin:furnace"],
    "settings": {"eps": 0.5},
    "sweep": {"scheduler": ["stack", "fifo", "blocked"], "threads": [1, 2]}})"),
                                 "cfg");
}

TEST(ExperimentSweep, CartesianProductInOrder) {
  const std::vector<SweepPoint> p = expand_sweep(config());
  ASSERT_EQ(p.size(), 2u * 3u * 2u);
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p[i].index, static_cast<int>(i));
  // Scenes slowest, then axes in file order, the last axis fastest.
  EXPECT_EQ(p[0].scene, "builtin:cornell");
  EXPECT_EQ(p[6].scene, "builtin:furnace");
  EXPECT_EQ(describe_point(p[0]), "scheduler=stack threads=1");
  EXPECT_EQ(describe_point(p[1]), "scheduler=stack threads=2");
  EXPECT_EQ(describe_point(p[2]), "scheduler=fifo threads=1");
  EXPECT_EQ(describe_point(p[11]), "scheduler=blocked threads=2");
  EXPECT_EQ(p[11].options.scheduler, "blocked");
  EXPECT_EQ(p[11].options.threads, 2);
  for (const SweepPoint& q : p) EXPECT_EQ(q.options.eps, 0.5);  // settings everywhere
  // Every (scheduler, threads) pair appears exactly once per scene.
  std::set<std::pair<std::string, int>> seen;
  for (int i = 0; i < 6; ++i) seen.insert({p[i].options.scheduler, p[i].options.threads});
  EXPECT_EQ(seen.size(), 6u);
}

TEST(ExperimentSweep, NoSweepIsOnePointPerScene) {
  ExperimentConfig c = config();
  c.sweep.clear();
  const std::vector<SweepPoint> p = expand_sweep(c);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(describe_point(p[0]), "");
}

TEST(ExperimentSweep, ThreeAxesCount) {
  ExperimentConfig c = config();
  c.sweep.push_back({"block_size", {1, 10, 100, 1000}});
  EXPECT_EQ(expand_sweep(c).size(), 2u * 3u * 2u * 4u);
}

RunStats two_iterations() {
  RunStats s;
  for (int i = 1; i <= 2; ++i) {
    IterationStats it;
    it.iteration = i;
    it.refine_wall_s = 1.0 * i;
    it.refine_cpu_s = 2.0 * i;
    it.propagate_wall_s = 0.25;
    it.links_created = 100;
    it.links = 100u * i;
    it.elements = 10u * i;
    it.bytes = {{"elements", 1000u * i}, {"links", 3000u * i}};
    it.tasks = 50;
    it.scheduler_ops = 20;
    it.lock_wait_s = {{"scheduler", 0.5}, {"element", 0.25}, {"link", 0.125}};
    it.idle_s = 0.75;
    it.peak_parallelism = i;
    it.steals = 3;
    it.rays_cast = 7;
    it.gather_sweeps = 4;
    s.iterations.push_back(it);
  }
  s.totals.wall_s = 4;
  s.totals.refine_wall_s = 3;
  s.totals.refine_cpu_s = 6;
  s.totals.links = 200;
  s.totals.elements = 20;
  s.totals.rays_cast = 14;
  s.totals.iterations_run = 2;
  return s;
}

TEST(ExperimentRows, ColumnsAndValues) {
  const std::vector<SweepPoint> p = expand_sweep(config());
  RunStats stats = two_iterations();
  stats.warnings = {"iteration 1: refiner 1 ran on a CPU for 40% of the time", "another"};
  const RunRows r = make_run_rows("s", p[3], 1, stats, "2026-01-01T00:00:00+0000", nullptr,
                                  RunOrigin{"node7", "abc1234", "AMD EPYC 9R14", 96, 1.5});
  const auto& rc = run_columns();
  ASSERT_EQ(r.run.size(), rc.size());
  const auto at = [&](const char* c) { return r.run[column_index(rc, c)]; };
  EXPECT_EQ(at("config"), "s");
  EXPECT_EQ(at("point"), "3");
  EXPECT_EQ(at("repetition"), "1");
  EXPECT_EQ(at("scene"), "builtin:cornell");
  EXPECT_EQ(at("swept"), "scheduler=fifo threads=2");
  EXPECT_EQ(at("scheduler"), "fifo");  // every option is a column
  EXPECT_EQ(at("threads"), "2");
  EXPECT_EQ(at("eps"), option_value_string(p[3].options, "eps"));
  EXPECT_EQ(at("refine_cpu_s"), "6");
  EXPECT_EQ(at("propagate_wall_s"), "0.5");     // summed
  EXPECT_EQ(at("tasks"), "100");                // summed
  EXPECT_EQ(at("lock_wait_scheduler_s"), "1");  // summed
  EXPECT_EQ(at("lock_wait_total_s"), "1.75");   // all classes, all iterations
  EXPECT_EQ(at("bytes_total"), "8000");         // at the end
  EXPECT_EQ(at("peak_parallelism"), "2");       // max
  EXPECT_EQ(at("steals"), "6");
  EXPECT_EQ(at("iterations_run"), "2");
  EXPECT_EQ(at("warnings"), "iteration 1: refiner 1 ran on a CPU for 40% of the time | another");
  EXPECT_EQ(at("host"), "node7");
  EXPECT_EQ(at("hrad_revision"), "abc1234");
  EXPECT_EQ(at("cpu_model"), "AMD EPYC 9R14");
  EXPECT_EQ(at("cores"), "96");
  EXPECT_EQ(at("load_avg"), "1.5");
  ASSERT_EQ(r.iterations.size(), 2u);
  const auto& ic = iteration_columns();
  for (const Row& row : r.iterations) ASSERT_EQ(row.size(), ic.size());
  EXPECT_EQ(r.iterations[1][column_index(ic, "iteration")], "2");
  EXPECT_EQ(r.iterations[1][column_index(ic, "links")], "200");
  EXPECT_EQ(r.iterations[1][column_index(ic, "refine_cpu_s")], "4");
  EXPECT_EQ(r.iterations[0][column_index(ic, "bytes_links")], "3000");
  EXPECT_EQ(r.iterations[0][column_index(ic, "lock_wait_total_s")], "0.875");
  // Each iteration row says where it ran too.
  for (const Row& row : r.iterations) {
    EXPECT_EQ(row[column_index(ic, "host")], "node7");
    EXPECT_EQ(row[column_index(ic, "hrad_revision")], "abc1234");
  }
  // Unknown model, cores and load: empty cells.
  const RunRows unknown = make_run_rows("s", p[3], 1, stats, "t", nullptr, RunOrigin{"h", "r"});
  EXPECT_EQ(unknown.run[column_index(rc, "cpu_model")], "");
  EXPECT_EQ(unknown.run[column_index(rc, "cores")], "");
  EXPECT_EQ(unknown.run[column_index(rc, "load_avg")], "");
}

// stats.json and iterations.csv are written from one table (core/output/stat_fields.h):
// every scalar of an iteration in stats.json is a CSV column with the same value, and
// every CSV figure column is in the table.
TEST(ExperimentRows, EveryIterationScalarOfStatsJsonIsACsvColumn) {
  RunStats s = two_iterations();
  IterationStats& it = s.iterations[1];
  it.load_s = 0.0625;
  it.link_compact_s = 0.03125;
  it.row_sum_min = 0.5;
  it.row_sum_max = 1.25;
  it.row_sum_mean = 0.96875;
  it.row_sum_within_band = 0.75;
  it.row_sum_corrected = 9;
  it.open_rays = 11;
  it.open_area_fraction = 0.875;
  it.local_access_ratio = std::nan("");  // null in JSON, empty in CSV
  const nlohmann::json j = stats_to_json(s)["iterations"][1];
  const std::vector<SweepPoint> p = expand_sweep(config());
  const RunRows r = make_run_rows("s", p[0], 0, s, "2026-01-01T00:00:00+0000");
  const auto& ic = iteration_columns();
  const Row& row = r.iterations[1];
  // The parts of an iteration that are not scalars, written by stats_json.cpp alone.
  const std::set<std::string> whole = {"bytes",
                                       "lock_wait_s",
                                       "refiners",
                                       "bytes_per_node",
                                       "element_bytes_per_node",
                                       "link_bytes_per_node",
                                       "placement_check"};
  int scalars = 0;
  const nlohmann::json flat = j.flatten();
  for (const auto& item : flat.items()) {
    const std::string path = item.key().substr(1);  // "/row_sums/min" -> "row_sums/min"
    if (whole.count(path.substr(0, path.find('/')))) continue;
    std::string column = path;
    std::replace(column.begin(), column.end(), '/', '_');
    const std::size_t at = column_index(ic, column);  // throws if there is none
    const nlohmann::json& v = item.value();
    const std::string expected = v.is_null()           ? ""
                                 : v.is_number_float() ? fmt::format("{}", v.get<double>())
                                                       : v.dump();
    EXPECT_EQ(row[at], expected) << column;
    ++scalars;
  }
  // ... and every field of the table with a path is one of them.
  EXPECT_EQ(scalars, std::count_if(iteration_fields().begin(), iteration_fields().end(),
                                   [](const IterationField& f) { return f.path != nullptr; }));
  EXPECT_EQ(row[column_index(ic, "row_sums_area_mean")], "0.96875");
  EXPECT_EQ(row[column_index(ic, "load_s")], "0.0625");
  EXPECT_EQ(row[column_index(ic, "open_rays")], "11");
  EXPECT_EQ(row[column_index(ic, "local_access_ratio")], "");
  // Identity, options, the table, then the host and the revision: nothing else.
  EXPECT_EQ(ic.size(), 5 + option_table().size() + iteration_fields().size() + 2);
}

// The same for a run: stats.json's totals and runs.csv come from run_fields().
TEST(ExperimentRows, EveryTotalOfStatsJsonIsARunsCsvColumn) {
  RunStats s = two_iterations();
  s.totals.task_cpu_ns = 12.5;
  s.totals.peak_rss_bytes = 4096;
  const nlohmann::json j = stats_to_json(s)["totals"];
  const std::vector<SweepPoint> p = expand_sweep(config());
  const RunRows r = make_run_rows("s", p[0], 0, s, "2026-01-01T00:00:00+0000");
  const auto& rc = run_columns();
  int totals = 0;
  for (const auto& [key, v] : j.items()) {
    const std::string expected = v.is_null()           ? ""
                                 : v.is_number_float() ? fmt::format("{}", v.get<double>())
                                                       : v.dump();
    EXPECT_EQ(r.run[column_index(rc, key)], expected) << key;
    ++totals;
  }
  EXPECT_EQ(totals, std::count_if(run_fields().begin(), run_fields().end(),
                                  [](const RunField& f) { return f.path != nullptr; }));
  EXPECT_EQ(j["iterations_run"], 2);
  EXPECT_EQ(j["task_cpu_ns"], 12.5);
  // Identity, options, the table, then the start time, the four probe columns, the
  // warnings, the host, the revision, the CPU model, the cores and the load.
  EXPECT_EQ(rc.size(), 5 + option_table().size() + run_fields().size() + 5 + 6);
}

TEST(ExperimentRows, HeaderStartsWithIdentityThenOptions) {
  const auto& rc = run_columns();
  const std::vector<std::string> head(rc.begin(), rc.begin() + 5);
  EXPECT_EQ(head, (std::vector<std::string>{"config", "point", "repetition", "scene", "swept"}));
  for (std::size_t i = 0; i < option_table().size(); ++i)
    EXPECT_EQ(rc[5 + i], option_table()[i].name);
  // No duplicate column names in either file.
  for (const auto* cols : {&run_columns(), &iteration_columns()}) {
    std::set<std::string> s(cols->begin(), cols->end());
    EXPECT_EQ(s.size(), cols->size());
  }
}

}  // namespace
}  // namespace hrad::experiment
