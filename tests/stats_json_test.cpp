#include "core/output/stats_json.h"

#include "core/scene/scene_builder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace hrad {
namespace {

RunStats sample_stats() {
  RunStats s;
  for (int i = 1; i <= 2; ++i) {
    IterationStats it;
    it.iteration = i;
    it.refine_wall_s = 0.5 * i;
    it.refine_cpu_s = 0.9 * i;
    it.propagate_wall_s = 0.1;
    it.links_created = 100u * i;
    it.links = 150u * i;
    it.elements = 40u * i;
    it.bytes = {{"elements", 4096}, {"links", 8192}};
    it.peak_rss_bytes = 1u << 20;
    it.tasks = 300;
    it.scheduler_ops = 60;
    it.lock_wait_s = {{"scheduler", 0.01}, {"element", 0.002}, {"link", 0.0}};
    it.idle_s = 0.05;
    it.rays_cast = 1000;
    it.rays_skipped = 250;
    it.gather_sweeps = 7;
    it.max_change = 1e-7;
    it.contraction = 0.7;
    it.refiners = {RefinerStats{150, 15, 12, 0.4, 0.01, 0.001, 500},
                   RefinerStats{150, 16, 11, 0.5, 0.04, 0.002, 500}};
    it.refiners[1].cpu_s = 0.45;
    it.refiners[1].link_bytes = 4096;
    it.refine_thread_cpu_s = 0.85 * i;
    it.task_cpu_ns = 1e9 * it.refine_thread_cpu_s / 300;
    s.iterations.push_back(it);
  }
  s.totals.wall_s = 2.0;
  s.totals.refine_wall_s = 1.5;
  s.totals.refine_cpu_s = 2.7;
  s.totals.links = 300;
  s.totals.elements = 80;
  s.totals.rays_cast = 2000;
  s.totals.rays_skipped = 500;
  s.totals.peak_rss_bytes = 1u << 20;
  s.warnings = {"scene has no emitter"};
  return s;
}

// The keys issue 2 (item 6) requires, with their JSON types.
enum class Kind { Integer, Number, Object, Array, ObjectOrNull };

bool has_kind(const nlohmann::json& v, Kind k) {
  switch (k) {
    case Kind::Integer: return v.is_number_integer();
    case Kind::Number: return v.is_number();
    case Kind::Object: return v.is_object();
    case Kind::Array: return v.is_array();
    case Kind::ObjectOrNull: return v.is_object() || v.is_null();
  }
  return false;
}

TEST(StatsJson, EveryIterationHasTheDocumentedKeysWithTypes) {
  const nlohmann::json j = stats_to_json(sample_stats());
  const std::pair<const char*, Kind> keys[] = {
      {"iteration", Kind::Integer},
      {"refine_wall_s", Kind::Number},
      {"refine_cpu_s", Kind::Number},
      {"propagate_wall_s", Kind::Number},
      {"links_created", Kind::Integer},
      {"links", Kind::Integer},
      {"elements", Kind::Integer},
      {"bytes", Kind::Object},
      {"peak_rss_bytes", Kind::Integer},
      {"tasks", Kind::Integer},
      {"scheduler_ops", Kind::Integer},
      {"lock_wait_s", Kind::Object},
      {"idle_s", Kind::Number},
      {"rays_cast", Kind::Integer},
      {"rays_skipped", Kind::Integer},
      {"gather_sweeps", Kind::Integer},
      {"max_change", Kind::Number},
      {"contraction", Kind::Number},
      {"peak_parallelism", Kind::Integer},
      {"bytes_per_link", Kind::Number},
      {"bytes_per_element", Kind::Number},
      {"row_sums", Kind::Object},
      {"steals", Kind::Integer},
      {"open", Kind::Object},
      {"exposure", Kind::Object},
      {"gather_rows_kept", Kind::Integer},
      {"min_area_held", Kind::Object},
      {"refiners", Kind::Array},
      {"load_s", Kind::Number},
      {"bytes_per_node", Kind::Array},
      {"local_access_ratio", Kind::Number},
      {"element_bytes_per_node", Kind::Array},
      {"link_bytes_per_node", Kind::Array},
      {"link_compact_s", Kind::Number},
      {"placement_check", Kind::ObjectOrNull},
      {"refine_thread_cpu_s", Kind::Number},
      {"task_cpu_ns", Kind::Number},
      {"prepare_s", Kind::Number},
      {"open_s", Kind::Number},
      {"push_weights_s", Kind::Number},
      {"row_sums_s", Kind::Number},
      {"sweeps_s", Kind::Number},
      {"stage_start_s", Kind::Number},
      {"stage_end_s", Kind::Number},
  };
  ASSERT_TRUE(j.at("iterations").is_array());
  ASSERT_EQ(j["iterations"].size(), 2u);
  for (const nlohmann::json& it : j["iterations"]) {
    for (const auto& [key, kind] : keys) {
      ASSERT_TRUE(it.contains(key)) << key;
      EXPECT_TRUE(has_kind(it[key], kind)) << key << " = " << it[key].dump();
    }
    EXPECT_EQ(it.size(), std::size(keys));
  }
  const nlohmann::json& second = j["iterations"][1];
  EXPECT_EQ(second["iteration"], 2);
  EXPECT_EQ(second["links_created"], 200);
  EXPECT_DOUBLE_EQ(second["bytes_per_link"].get<double>(), 8192.0 / 300.0);
  ASSERT_EQ(second["refiners"].size(), 2u);
  EXPECT_EQ(second["refiners"][1]["takes"], 16);
  EXPECT_DOUBLE_EQ(second["refiners"][1]["idle_s"].get<double>(), 0.04);
  EXPECT_DOUBLE_EQ(second["refiners"][1]["cpu_s"].get<double>(), 0.45);
  EXPECT_EQ(second["refiners"][1]["link_bytes"], 4096);
  EXPECT_DOUBLE_EQ(second["refine_thread_cpu_s"].get<double>(), 1.7);
  EXPECT_DOUBLE_EQ(second["task_cpu_ns"].get<double>(), 1.7e9 / 300);
  EXPECT_EQ(second["refiners"][1]["bound"], "none");  // NUMA fields (docs/numa.md)
  EXPECT_EQ(second["refiners"][1]["node"], 0);
  EXPECT_EQ(second["refiners"][1]["tasks_local"], 0);
  EXPECT_DOUBLE_EQ(second["bytes_per_element"].get<double>(), 4096.0 / 80.0);
  EXPECT_DOUBLE_EQ(second["refine_cpu_s"].get<double>(), 1.8);
  EXPECT_EQ(second["bytes"]["links"], 8192);
  EXPECT_DOUBLE_EQ(second["lock_wait_s"]["scheduler"].get<double>(), 0.01);
  EXPECT_TRUE(second["lock_wait_s"]["link"].is_number());
}

TEST(StatsJson, TotalsHaveTheDocumentedKeysWithTypes) {
  const nlohmann::json t = stats_to_json(sample_stats()).at("totals");
  const std::pair<const char*, Kind> keys[] = {
      {"wall_s", Kind::Number},          {"refine_wall_s", Kind::Number},
      {"refine_cpu_s", Kind::Number},    {"links", Kind::Integer},
      {"elements", Kind::Integer},       {"rays_cast", Kind::Integer},
      {"rays_skipped", Kind::Integer},   {"peak_rss_bytes", Kind::Integer},
      {"iterations_run", Kind::Integer}, {"refine_thread_cpu_s", Kind::Number},
      {"task_cpu_ns", Kind::Number},     {"propagate_wall_s", Kind::Number},
      {"prepare_s", Kind::Number},       {"sweeps_s", Kind::Number},
      {"open_s", Kind::Number},          {"push_weights_s", Kind::Number},
      {"row_sums_s", Kind::Number},      {"load_s", Kind::Number},
      {"link_compact_s", Kind::Number},  {"stage_start_s", Kind::Number},
      {"stage_end_s", Kind::Number},     {"setup_s", Kind::Number},
      {"scene_load_s", Kind::Number},
  };
  for (const auto& [key, kind] : keys) {
    ASSERT_TRUE(t.contains(key)) << key;
    EXPECT_TRUE(has_kind(t[key], kind)) << key;
  }
  EXPECT_EQ(t.size(), std::size(keys));
  EXPECT_EQ(t["links"], 300);
  EXPECT_DOUBLE_EQ(t["wall_s"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(t["propagate_wall_s"].get<double>(), 0.2);  // the iterations' sum
}

TEST(StatsJson, WarningsAndEmptyRun) {
  const nlohmann::json j = stats_to_json(sample_stats());
  ASSERT_TRUE(j.at("warnings").is_array());
  EXPECT_EQ(j["warnings"][0], "scene has no emitter");
  const nlohmann::json empty = stats_to_json(RunStats{});
  EXPECT_TRUE(empty.at("iterations").is_array());
  EXPECT_TRUE(empty["iterations"].empty());
  EXPECT_EQ(empty["totals"]["links"], 0);
}

TEST(StatsJson, NonFiniteNumbersBecomeNull) {
  RunStats s;
  s.iterations.emplace_back();
  s.iterations[0].max_change = std::nan("");
  s.totals.wall_s = INFINITY;
  const nlohmann::json j = stats_to_json(s);
  EXPECT_TRUE(j["iterations"][0]["max_change"].is_null());
  EXPECT_TRUE(j["totals"]["wall_s"].is_null());
  EXPECT_TRUE(nlohmann::json::parse(j.dump()).is_object());
}

Scene two_quads() {
  SceneBuilder b("box", "test.obj");
  const SourceLoc at{"test.obj", 1};
  Material light;
  light.name = "light";
  light.reflectance = Rgb(0.2, 0.2, 0.2);
  light.emission = Rgb(2.0, 1.0, 0.5);
  Material wall;
  wall.name = "wall";
  const auto l = b.add_material(light, at);
  const auto w = b.add_material(wall, at);
  const std::vector<Vec3> floor = {{0, 0, 0}, {2, 0, 0}, {2, 0, 3}, {0, 0, 3}};
  const std::vector<Vec3> lamp = {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}};
  b.add_polygon(floor, w, at);
  b.add_polygon(lamp, l, at);
  return b.finish("test.obj");
}

TEST(StatsJson, SceneSummary) {
  const nlohmann::json j = scene_summary_json(two_quads());
  EXPECT_EQ(j.at("name"), "box");
  EXPECT_EQ(j.at("source"), "test.obj");
  EXPECT_EQ(j.at("polygons"), 2);
  EXPECT_EQ(j.at("emitters"), 1);
  EXPECT_EQ(j.at("materials"), 2);
  EXPECT_TRUE(j.at("vertices").is_number_integer());
  EXPECT_DOUBLE_EQ(j.at("total_area").get<double>(), 7.0);
  ASSERT_EQ(j.at("emitted_power").size(), 3u);
  EXPECT_DOUBLE_EQ(j["emitted_power"][0].get<double>(), 2.0);  // exitance 2 x area 1
  EXPECT_DOUBLE_EQ(j["emitted_power"][2].get<double>(), 0.5);
  EXPECT_EQ(j.at("bounds").at("lo"), nlohmann::json({0.0, 0.0, 0.0}));
  EXPECT_EQ(j.at("bounds").at("hi"), nlohmann::json({2.0, 1.0, 3.0}));
  EXPECT_EQ(j.at("grey"), false);  // the light's emission is coloured
  EXPECT_TRUE(j.at("warnings").is_array());
}

TEST(StatsJson, WriteJsonAtomicallyLeavesOnlyTheFinalFile) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("hrad-stats-json-test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / "stats.json";
  nlohmann::json j = stats_to_json(sample_stats());
  j["note"] = std::string("bad utf-8: \xff");  // replaced, not an exception
  write_json_atomically(path, j);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json back = nlohmann::json::parse(text.str());
  EXPECT_EQ(back["totals"], j["totals"]);
  EXPECT_EQ(text.str().back(), '\n');
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);  // no temporary left behind
  EXPECT_THROW(write_json_atomically(dir / "missing" / "x.json", j), std::runtime_error);
  std::filesystem::remove_all(dir);
}

TEST(RunStats, DescheduledRefinerWarning) {
  IterationStats is;
  is.iteration = 3;
  is.refiners.resize(2);
  is.refiners[0].busy_s = 1.0;
  is.refiners[0].cpu_s = 0.99;
  is.refiners[1].busy_s = 1.0;
  is.refiners[1].cpu_s = 0.95;
  is.refiners[1].idle_s = 5.0;  // idle time is sleep: it does not count
  EXPECT_EQ(descheduled_refiner_warning(is), "");
  is.refiners[1].cpu_s = 0.5;  // half the refining time off a CPU: a shared core
  const std::string w = descheduled_refiner_warning(is);
  EXPECT_NE(w.find("iteration 3: refiner 1 ran on a CPU for 50%"), std::string::npos) << w;
  is.refiners[1].busy_s = 0.04;  // too short to tell
  is.refiners[1].cpu_s = 0.0;
  EXPECT_EQ(descheduled_refiner_warning(is), "");
  is.refiners.resize(1);  // one refiner: nothing to compare
  is.refiners[0].cpu_s = 0.1;
  EXPECT_EQ(descheduled_refiner_warning(is), "");
}

}  // namespace
}  // namespace hrad
