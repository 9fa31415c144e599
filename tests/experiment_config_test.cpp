// Experiment configurations: strict parsing (unknown keys, types, empty lists, option
// ranges and names), --quick, --set, the JSON round trip, and every shipped config.
#include "experiments/harness/experiment_config.h"
#include "core/base/input_error.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <thread>

#include <filesystem>
#include <fstream>
#include <string>

namespace hrad::experiment {
namespace {

using ojson = nlohmann::ordered_json;

ojson minimal() { return ojson::parse(R"({"name": "t", "scenes": ["builtin:cornell"]})"); }

ojson full() {
  return ojson::parse(R"({
    "name": "fig", "description": "d", "scenes": ["builtin:cornell", "builtin:furnace"],
    "settings": {"eps": 0.01, "iterations": 2},
    "sweep": {"threads": [1, 2, 4], "scheduler": ["stack", "blocked"]},
    "repetitions": 3,
    "quick": {"scenes": ["builtin:cornell"], "settings": {"eps": 0.1},
              "sweep": {"threads": [1, 2]}, "repetitions": 1},
    "plot": "speedup"})");
}

// The error message of parsing `j`, or "" when it parses.
std::string error_of(const ojson& j) {
  try {
    (void)parse_experiment_config(j, "cfg.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ExperimentConfig, MinimalHasDefaults) {
  const ExperimentConfig c = parse_experiment_config(minimal(), "cfg.json");
  EXPECT_EQ(c.name, "t");
  EXPECT_EQ(c.scenes, std::vector<std::string>{"builtin:cornell"});
  EXPECT_EQ(c.repetitions, 1);
  EXPECT_TRUE(c.sweep.empty());
  EXPECT_TRUE(c.plots.empty());
}

TEST(ExperimentConfig, FullKeepsSweepOrder) {
  const ExperimentConfig c = parse_experiment_config(full(), "cfg.json");
  ASSERT_EQ(c.sweep.size(), 2u);
  EXPECT_EQ(c.sweep[0].key, "threads");  // file order, not alphabetical
  EXPECT_EQ(c.sweep[1].key, "scheduler");
  EXPECT_EQ(c.sweep[0].values.size(), 3u);
  EXPECT_EQ(c.repetitions, 3);
  EXPECT_EQ(c.plots, std::vector<std::string>{"speedup"});
  EXPECT_EQ(base_options(c).eps, 0.01);
  EXPECT_EQ(base_options(c).iterations, 2);
}

TEST(ExperimentConfig, UnknownKeysAreNamed) {
  ojson j = minimal();
  j["repetition"] = 2;
  const std::string e = error_of(j);
  EXPECT_NE(e.find("cfg.json"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key 'repetition'"), std::string::npos) << e;
  EXPECT_NE(e.find("repetitions"), std::string::npos) << e;  // lists the valid keys

  j = minimal();
  j["settings"] = {{"thread", 2}};
  EXPECT_NE(error_of(j).find("'thread'"), std::string::npos) << error_of(j);

  j = minimal();
  j["sweep"] = {{"blocksize", {1, 10}}};
  EXPECT_NE(error_of(j).find("'blocksize'"), std::string::npos) << error_of(j);

  j = full();
  j["quick"]["eps"] = 0.1;
  EXPECT_NE(error_of(j).find("unknown key 'eps' in 'quick'"), std::string::npos) << error_of(j);
}

TEST(ExperimentConfig, BadTypesAreErrors) {
  const auto with = [](const char* key, ojson v) {
    ojson j = minimal();
    j[key] = v;
    return error_of(j);
  };
  EXPECT_NE(with("name", 3).find("'name' must be a string"), std::string::npos);
  EXPECT_NE(with("name", "a/b").find("folder name"), std::string::npos);
  EXPECT_NE(with("scenes", "builtin:cornell").find("list of scene specs"), std::string::npos);
  EXPECT_NE(with("repetitions", 2.5).find("'repetitions' must be an integer"), std::string::npos);
  EXPECT_NE(with("repetitions", 0).find("'repetitions' must be an integer between 1 and 1000000"),
            std::string::npos);
  EXPECT_NE(with("repetitions", 1000001).find("between 1 and 1000000, got 1000001"),
            std::string::npos);
  EXPECT_NE(with("settings", ojson::array()).find("'settings' must be an object"),
            std::string::npos);
  EXPECT_NE(with("sweep", ojson::parse(R"({"threads": 2})")).find("must be a list"),
            std::string::npos);
  EXPECT_NE(with("plot", 1).find("'plot'"), std::string::npos);
  EXPECT_NE(with("plot", "speedup.py").find("without '.py'"), std::string::npos);
  // Option values: checked against the key's type, naming key and type.
  const std::string e = with("settings", ojson::parse(R"({"threads": "4"})"));
  EXPECT_NE(e.find("'threads' expects an integer"), std::string::npos) << e;
  const std::string s = with("sweep", ojson::parse(R"({"eps": [0.1, "x"]})"));
  EXPECT_NE(s.find("'eps' expects a number"), std::string::npos) << s;
}

TEST(ExperimentConfig, EmptyListsAreErrors) {
  ojson j = minimal();
  j["scenes"] = ojson::array();
  EXPECT_NE(error_of(j).find("'scenes' is empty"), std::string::npos) << error_of(j);
  j = minimal();
  j["sweep"] = ojson::parse(R"({"threads": []})");
  EXPECT_NE(error_of(j).find("'sweep.threads' is an empty list"), std::string::npos) << error_of(j);
  j = minimal();
  j["name"] = "";
  EXPECT_NE(error_of(j).find("'name'"), std::string::npos);
}

TEST(ExperimentConfig, MissingRequiredKeys) {
  EXPECT_NE(error_of(ojson::parse(R"({"scenes": ["builtin:cornell"]})")).find("missing key 'name'"),
            std::string::npos);
  EXPECT_NE(error_of(ojson::parse(R"({"name": "x"})")).find("missing key 'scenes'"),
            std::string::npos);
  EXPECT_NE(error_of(ojson::array()).find("must be a JSON object"), std::string::npos);
}

TEST(ExperimentConfig, RangesNamesAndConflicts) {
  ojson j = minimal();
  j["sweep"] = ojson::parse(R"({"threads": [1, 0]})");
  EXPECT_NE(error_of(j).find("threads = 0 is out of range"), std::string::npos) << error_of(j);
  j = minimal();
  j["sweep"] = ojson::parse(R"({"scheduler": ["stack", "lifo"]})");
  EXPECT_NE(error_of(j).find("unknown scheduler 'lifo'"), std::string::npos) << error_of(j);
  j = minimal();
  j["settings"] = ojson::parse(R"({"oracle": "nope"})");
  EXPECT_NE(error_of(j).find("unknown oracle 'nope'"), std::string::npos) << error_of(j);
  j = minimal();
  j["settings"] = ojson::parse(R"({"threads": 2})");
  j["sweep"] = ojson::parse(R"({"threads": [1, 2]})");
  EXPECT_NE(error_of(j).find("both in settings and in the sweep"), std::string::npos);
  j = minimal();
  j["sweep"] = ojson::parse(R"({"threads": [1, 1]})");
  EXPECT_NE(error_of(j).find("twice"), std::string::npos);
  j = minimal();
  j["sweep"] = ojson::parse(R"({"eps": [1e-3, 2e-3, 0.001]})");
  EXPECT_NE(error_of(j).find("lists 0.001 twice"), std::string::npos) << error_of(j);
  // quick may only narrow axes the sweep has, and its values are checked too.
  j = full();
  j["quick"]["sweep"] = ojson::parse(R"({"block_size": [1]})");
  EXPECT_NE(error_of(j).find("not swept"), std::string::npos) << error_of(j);
  j = full();
  j["quick"]["settings"] = ojson::parse(R"({"eps": -1})");
  EXPECT_NE(error_of(j).find("eps"), std::string::npos) << error_of(j);
}

TEST(ExperimentConfig, QuickOverrides) {
  const ExperimentConfig q = apply_quick(parse_experiment_config(full(), "cfg.json"));
  EXPECT_EQ(q.scenes, std::vector<std::string>{"builtin:cornell"});
  EXPECT_EQ(base_options(q).eps, 0.1);       // merged over settings
  EXPECT_EQ(base_options(q).iterations, 2);  // kept
  ASSERT_EQ(q.sweep.size(), 2u);
  EXPECT_EQ(q.sweep[0].values.size(), 2u);  // threads narrowed
  EXPECT_EQ(q.sweep[1].values.size(), 2u);  // scheduler unchanged
  EXPECT_EQ(q.repetitions, 1);
  // Without a quick part, apply_quick changes nothing.
  const ExperimentConfig m = parse_experiment_config(minimal(), "cfg.json");
  EXPECT_EQ(experiment_config_to_json(apply_quick(m)), experiment_config_to_json(m));
}

TEST(ExperimentConfig, SetOverrides) {
  ExperimentConfig c = parse_experiment_config(full(), "cfg.json");
  apply_experiment_set(c, "threads=8");  // fixes threads, drops the axis
  ASSERT_EQ(c.sweep.size(), 1u);
  EXPECT_EQ(c.sweep[0].key, "scheduler");
  EXPECT_EQ(base_options(c).threads, 8);
  apply_experiment_set(c, "block-size=10");  // aliases as in hrad solve --set
  EXPECT_EQ(base_options(c).block_size, 10);
  apply_experiment_set(c, "repetitions=5");
  EXPECT_EQ(c.repetitions, 5);
  apply_experiment_set(c, "scenes=builtin:furnace,builtin:cornell");
  EXPECT_EQ(c.scenes.size(), 2u);
  // A builtin scene's comma-form parameters stay with it.
  apply_experiment_set(c, "scenes=builtin:furnace,rho=0.5,objects=0,builtin:cornell,blocks=0");
  EXPECT_EQ(c.scenes, (std::vector<std::string>{"builtin:furnace,rho=0.5,objects=0",
                                                "builtin:cornell,blocks=0"}));
  apply_experiment_set(c, "sweep.threads=1,2");
  ASSERT_EQ(c.sweep.size(), 2u);
  EXPECT_EQ(c.sweep[1].key, "threads");
  EXPECT_EQ(c.sweep[1].values, (std::vector<nlohmann::json>{1, 2}));
  EXPECT_FALSE(c.settings.contains("threads"));

  const auto error = [&](const std::string& s) {
    try {
      apply_experiment_set(c, s);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("thread=2").find("unknown key 'thread'"), std::string::npos);
  EXPECT_NE(error("threads=two").find("expects an integer"), std::string::npos);
  EXPECT_NE(error("threads=0").find("out of range"), std::string::npos);
  EXPECT_NE(error("scheduler=lifo").find("unknown scheduler"), std::string::npos);
  EXPECT_NE(error("repetitions=0").find("repetitions"), std::string::npos);
  // Past the configuration file's bound (it had none here: 2e9 repetitions were taken).
  EXPECT_NE(error("repetitions=2000000000").find("between 1 and 1000000"), std::string::npos);
  EXPECT_NE(error("repetitions=4294967297").find("between 1 and 1000000"), std::string::npos);
  EXPECT_NE(error("sweep.threads=").find("at least one value"), std::string::npos);
  EXPECT_NE(error("novalue").find("expected key=value"), std::string::npos);
}

// "threads": "cores" runs 1, 2, 4, ... up to the machine's logical CPUs (and that count).
TEST(ExperimentConfig, ThreadsUpToTheCores) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<nlohmann::json> expected;
  for (int t = 1; t < cores; t *= 2) expected.emplace_back(t);
  expected.emplace_back(cores);
  ojson j = minimal();
  j["sweep"] = ojson::parse(R"({"threads": "cores"})");
  const ExperimentConfig c = parse_experiment_config(j, "cfg.json");
  ASSERT_EQ(c.sweep.size(), 1u);
  EXPECT_EQ(c.sweep[0].values, expected);
  EXPECT_EQ(c.sweep[0].values.back(), cores);
  ExperimentConfig d = parse_experiment_config(minimal(), "cfg.json");
  apply_experiment_set(d, "sweep.threads=cores");
  ASSERT_EQ(d.sweep.size(), 1u);
  EXPECT_EQ(d.sweep[0].values, expected);
  j["sweep"] = ojson::parse(R"({"eps": "cores"})");  // only threads knows "cores"
  EXPECT_NE(error_of(j).find("must be a list of values"), std::string::npos) << error_of(j);
}

TEST(ExperimentConfig, JsonRoundTrip) {
  const ExperimentConfig c = parse_experiment_config(full(), "cfg.json");
  const ojson j = experiment_config_to_json(c);
  const ExperimentConfig back = parse_experiment_config(j, "manifest");
  EXPECT_EQ(experiment_config_to_json(back), j);
}

TEST(ExperimentConfig, FilesWithCommentsAndErrors) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("hrad_experiment_config_test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    std::ofstream(dir / "ok.json") << "// comment\n{\"name\": \"x\", /* c */ \"scenes\": "
                                      "[\"builtin:cornell\"]}\n";
    std::ofstream(dir / "bad.json") << "{\"name\": \"x\",\n \"scenes\": [}\n";
  }
  EXPECT_EQ(load_experiment_config(dir / "ok.json").name, "x");
  try {
    (void)load_experiment_config(dir / "bad.json");
    ADD_FAILURE() << "bad JSON accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bad.json: not valid JSON"), std::string::npos) << m;
    EXPECT_NE(m.find("line 2"), std::string::npos) << m;
  }
  EXPECT_THROW((void)load_experiment_config(dir / "missing.json"), InputError);
  std::filesystem::remove_all(dir);
}

// Every shipped configuration parses, with and without --quick.
TEST(ExperimentConfig, ShippedConfigsParse) {
  const std::filesystem::path configs =
      std::filesystem::path(HRAD_SOURCE_DIR) / "experiments/configs";
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(configs)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    ExperimentConfig c;
    ASSERT_NO_THROW(c = load_experiment_config(entry.path()));
    EXPECT_EQ(c.name + ".json", entry.path().filename().string());
    EXPECT_FALSE(c.plots.empty());
    EXPECT_NO_THROW((void)apply_quick(c));
    ++n;
  }
  EXPECT_GE(n, 6);
}

}  // namespace
}  // namespace hrad::experiment
