#include "core/config/options_io.h"
#include "oracles/oracle.h"
#include "schedulers/scheduler.h"
#include "tests/error_text.h"
#include "tests/read_text.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>

namespace hrad {
namespace {

using test::contains;
using test::error_of;

SolverOptions non_default_options() {
  SolverOptions o;
  o.scheduler = "stealing";
  o.block_size = 25;
  o.threads = 7;
  o.oracle = "error";
  o.eps = 2.5e-3;
  o.min_area = 0.125;
  o.iterations = 3;
  o.visibility_rays = 0;
  o.pin = PinPolicy::Scatter;
  o.placement = MemBind::Interleave;
  o.pool_order = PoolOrder::Subtree;
  o.seed = 18446744073709551615ull;  // largest uint64: must survive JSON
  o.gather_tolerance = 1e-9;
  o.max_gather_sweeps = 12;
  o.cluster_model = ClusterModel::Isotropic;
  o.cluster_receiver = ClusterReceiver::Isotropic;
  o.cluster_members = ClusterMembers::Exposed;
  o.row_sums = RowSumMode::Normalize;
  o.row_sum_rays = 5;
  o.locks_pool = 64;
  o.trace = "trace.bin";
  o.image_width = 320;
  o.image_samples = 3;
  o.effects = EffectsMode::All;
  o.shaft_culling = ShaftCulling::On;
  o.max_memory_gb = 2.5;
  o.camera = "eye=1,2,3:look=0,0.5,-1e-3:fov=30";
  o.sides = Sides::One;
  o.emitter_sides = EmitterSides::Both;
  o.segments = 24;
  o.shading = Shading::Flat;
  o.exposure = -2.5;
  o.decision_rays = DecisionRays::Independent;
  o.decision_visibility_rays = 16;
  o.push_visibility = PushVisibility::Child;
  // The selected plug-ins' own parameters (every one they declare).
  o.plugin_params = {{"scheduler.stealing.victims", "3"},
                     {"oracle.error.occluded_cluster_weight", "2.5"},
                     {"oracle.error.dark_floor", "0.5"},
                     {"oracle.error.shadow_contrast", "0.125"}};
  return o;
}

// Every field of SolverOptions, compared exactly (doubles too: the JSON text must keep
// them to the last bit).
void expect_equal(const SolverOptions& a, const SolverOptions& b) {
  EXPECT_EQ(a.camera, b.camera);
  EXPECT_EQ(a.sides, b.sides);
  EXPECT_EQ(a.emitter_sides, b.emitter_sides);
  EXPECT_EQ(a.segments, b.segments);
  EXPECT_EQ(a.scheduler, b.scheduler);
  EXPECT_EQ(a.block_size, b.block_size);
  EXPECT_EQ(a.threads, b.threads);
  EXPECT_EQ(a.oracle, b.oracle);
  EXPECT_EQ(a.eps, b.eps);
  EXPECT_EQ(a.min_area, b.min_area);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.visibility_rays, b.visibility_rays);
  EXPECT_EQ(a.pin, b.pin);
  EXPECT_EQ(a.placement, b.placement);
  EXPECT_EQ(a.pool_order, b.pool_order);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.gather_tolerance, b.gather_tolerance);
  EXPECT_EQ(a.max_gather_sweeps, b.max_gather_sweeps);
  EXPECT_EQ(a.cluster_model, b.cluster_model);
  EXPECT_EQ(a.cluster_receiver, b.cluster_receiver);
  EXPECT_EQ(a.cluster_members, b.cluster_members);
  EXPECT_EQ(a.row_sums, b.row_sums);
  EXPECT_EQ(a.row_sum_rays, b.row_sum_rays);
  EXPECT_EQ(a.locks_pool, b.locks_pool);
  EXPECT_EQ(a.trace, b.trace);
  EXPECT_EQ(a.image_width, b.image_width);
  EXPECT_EQ(a.image_samples, b.image_samples);
  EXPECT_EQ(a.effects, b.effects);
  EXPECT_EQ(a.shaft_culling, b.shaft_culling);
  EXPECT_EQ(a.max_memory_gb, b.max_memory_gb);
  EXPECT_EQ(a.shading, b.shading);
  EXPECT_EQ(a.exposure, b.exposure);
  EXPECT_EQ(a.decision_rays, b.decision_rays);
  EXPECT_EQ(a.decision_visibility_rays, b.decision_visibility_rays);
  EXPECT_EQ(a.push_visibility, b.push_visibility);
  EXPECT_EQ(a.plugin_params, b.plugin_params);
}

// One key per field, then one per declared plug-in parameter (KIND.NAME.KEY); the JSON of
// a configuration has every field and the selected plug-ins' parameters, no others.
TEST(OptionsIo, TableHasEveryFieldOnceAndJsonHasEveryKey) {
  const SolverOptions defaults;
  const nlohmann::json j = options_to_json(defaults);
  std::set<std::string> names;
  std::size_t fields = 0, selected = 0;
  for (const OptionInfo& i : option_table()) {
    EXPECT_TRUE(names.insert(i.name).second) << "duplicate key " << i.name;
    EXPECT_FALSE(i.help.empty()) << i.name;
    const bool plugin = i.name.find('.') != std::string::npos;
    if (!plugin) {
      ++fields;
      EXPECT_TRUE(j.contains(i.name)) << i.name;
    } else {
      const bool chosen = i.name.rfind("scheduler." + defaults.scheduler + ".", 0) == 0 ||
                          i.name.rfind("oracle." + defaults.oracle + ".", 0) == 0;
      EXPECT_EQ(j.contains(i.name), chosen) << i.name;
      selected += chosen;
    }
  }
  EXPECT_EQ(fields, 35u);  // one per field of SolverOptions but plugin_params
  std::size_t declared = 0;
  for (const std::string& n : scheduler_names()) declared += scheduler_params(n).size();
  for (const std::string& n : oracle_names()) declared += oracle_params(n).size();
  EXPECT_EQ(names.size(), fields + declared);
  EXPECT_EQ(selected, oracle_params("bf").size() + scheduler_params("blocked").size());
  EXPECT_EQ(j.size(), fields + selected);
  EXPECT_EQ(j["oracle.bf.dark_floor"], 0.25);
  EXPECT_EQ(j["scheduler"], "blocked");
  EXPECT_EQ(j["iterations"], 4);
  EXPECT_EQ(j["eps"], 1e-4);
}

TEST(OptionsIo, JsonRoundTripThroughText) {
  const SolverOptions in = non_default_options();
  const nlohmann::json parsed = nlohmann::json::parse(options_to_json(in).dump());
  SolverOptions out;
  apply_options_json(out, parsed, "roundtrip.json");
  expect_equal(in, out);
  EXPECT_EQ(options_to_json(out), options_to_json(in));
}

// The round trip above proves something about a key only if its value there is not the
// default: non_default_options changes every key of the table (35, one per field of
// SolverOptions, TableHasEveryFieldOnceAndJsonHasEveryKey), and --set restores each.
TEST(OptionsIo, RoundTripValuesDifferFromEveryDefault) {
  const SolverOptions d, o = non_default_options();
  std::size_t plugin_keys = 0;
  for (const OptionInfo& i : option_table()) {
    const std::string value = option_value_string(o, i.name);
    // A parameter of a plug-in `o` does not select has no value there ("").
    if (i.name.find('.') != std::string::npos && value.empty()) continue;
    plugin_keys += i.name.find('.') != std::string::npos;
    EXPECT_NE(value, option_value_string(d, i.name)) << i.name << " keeps its default";
  }
  EXPECT_EQ(plugin_keys, o.plugin_params.size());
  SolverOptions set;
  const nlohmann::json j = options_to_json(o);
  for (const auto& [key, value] : j.items())
    apply_option_assignment(
        set, key + "=" + (value.is_string() ? value.get<std::string>() : value.dump()));
  expect_equal(o, set);
}

TEST(OptionsIo, PartialJsonLeavesOtherKeysAlone) {
  SolverOptions o;
  apply_options_json(o, nlohmann::json::parse(R"({"threads": 3, "eps": 0.5})"), "c.json");
  EXPECT_EQ(o.threads, 3);
  EXPECT_EQ(o.eps, 0.5);
  EXPECT_EQ(o.scheduler, "blocked");
  EXPECT_EQ(o.iterations, 4);
  apply_options_json(o, nlohmann::json::object(), "empty.json");
  EXPECT_EQ(o.threads, 3);
}

TEST(OptionsIo, JsonUnknownKeyNamesKeySourceAndValidKeys) {
  SolverOptions o;
  const std::string e = error_of(
      [&] { apply_options_json(o, nlohmann::json::parse(R"({"thread": 2})"), "my.json"); });
  EXPECT_TRUE(contains(e, "my.json")) << e;
  EXPECT_TRUE(contains(e, "'thread'")) << e;
  EXPECT_TRUE(contains(e, "threads")) << e;
  EXPECT_TRUE(contains(e, "block_size")) << e;
  EXPECT_EQ(o.threads, 1);
  // Dotted aliases are for --set only; the JSON error suggests the canonical name.
  const std::string a = error_of(
      [&] { apply_options_json(o, nlohmann::json::parse(R"({"locks.pool": 2})"), "a.json"); });
  EXPECT_TRUE(contains(a, "did you mean 'locks_pool'")) << a;
}

TEST(OptionsIo, JsonWrongTypeNamesKeyAndExpectedType) {
  const auto err = [](const char* text) {
    SolverOptions o;
    return error_of([&] { apply_options_json(o, nlohmann::json::parse(text), "t.json"); });
  };
  std::string e = err(R"({"threads": "4"})");
  EXPECT_TRUE(contains(e, "t.json")) << e;
  EXPECT_TRUE(contains(e, "'threads'")) << e;
  EXPECT_TRUE(contains(e, "integer")) << e;
  e = err(R"({"threads": 4.5})");
  EXPECT_TRUE(contains(e, "integer")) << e;
  e = err(R"({"threads": 4294967296})");
  EXPECT_TRUE(contains(e, "t.json: option threads = 4294967296 is out of range")) << e;
  e = err(R"({"eps": "small"})");
  EXPECT_TRUE(contains(e, "'eps'") && contains(e, "number")) << e;
  e = err(R"({"scheduler": 3})");
  EXPECT_TRUE(contains(e, "'scheduler'") && contains(e, "string")) << e;
  e = err(R"({"seed": -1})");
  EXPECT_TRUE(contains(e, "t.json: option seed = -1 is out of range")) << e;
  e = err(R"([1, 2])");
  EXPECT_TRUE(contains(e, "t.json") && contains(e, "object")) << e;
  // An integer is a valid number.
  EXPECT_EQ(err(R"({"eps": 1})"), "");
}

TEST(OptionsIo, SetAssignmentParsesEachType) {
  SolverOptions o;
  apply_option_assignment(o, "threads=8");
  apply_option_assignment(o, "eps=2e-3");
  apply_option_assignment(o, "scheduler=fifo");
  apply_option_assignment(o, "seed=12345678901234");
  apply_option_assignment(o, "trace=");      // empty string is a valid string value
  apply_option_assignment(o, "oracle=a=b");  // split at the first '='
  EXPECT_EQ(o.threads, 8);
  EXPECT_EQ(o.eps, 2e-3);
  EXPECT_EQ(o.scheduler, "fifo");
  EXPECT_EQ(o.seed, 12345678901234ull);
  EXPECT_EQ(o.trace, "");
  EXPECT_EQ(o.oracle, "a=b");
}

// An integer key takes a whole number in any form a number is written in, and one
// beyond what its type holds is out of range, with the key's own bounds.
TEST(OptionsIo, IntegerKeysTakeWholeNumbersInExponentForm) {
  SolverOptions o;
  apply_option_assignment(o, "threads=2e0");
  apply_option_assignment(o, "seed=1.5e3");
  EXPECT_EQ(o.threads, 2);
  EXPECT_EQ(o.seed, 1500u);
  apply_options_json(o, nlohmann::json::parse(R"({"iterations": 3e0, "seed": 1e19})"), "t.json");
  EXPECT_EQ(o.iterations, 3);
  EXPECT_EQ(o.seed, 10000000000000000000ull);
  std::string e = error_of([&] { apply_option_assignment(o, "threads=1e10"); });
  EXPECT_TRUE(contains(e, "option threads = 1e10 is out of range: it must be between 1 and 1024"))
      << e;
  e = error_of([&] { apply_option_assignment(o, "seed=-2"); });
  EXPECT_TRUE(contains(e,
                       "option seed = -2 is out of range: it must be an integer between 0 and "
                       "18446744073709551615"))
      << e;
  e = error_of(
      [&] { apply_options_json(o, nlohmann::json::parse(R"({"seed": 1e20})"), "t.json"); });
  EXPECT_TRUE(contains(e, "t.json: option seed = ") && contains(e, "is out of range")) << e;
  e = error_of([&] { apply_option_assignment(o, "threads=2.5"); });
  EXPECT_TRUE(contains(e, "expects an integer")) << e;
}

TEST(OptionsIo, SetAcceptsDottedAndDashedAliases) {
  SolverOptions o;
  apply_option_assignment(o, "locks.pool=16");
  apply_option_assignment(o, "cluster.receiver=isotropic");
  apply_option_assignment(o, "block-size=100");
  EXPECT_EQ(o.locks_pool, 16);
  EXPECT_EQ(o.cluster_receiver, ClusterReceiver::Isotropic);
  EXPECT_EQ(o.block_size, 100);
  ASSERT_NE(find_option("locks.pool"), nullptr);
  EXPECT_EQ(find_option("locks.pool")->name, "locks_pool");
  EXPECT_EQ(find_option("nope"), nullptr);
}

TEST(OptionsIo, SetRejectsBadInputNamingIt) {
  SolverOptions o;
  std::string e = error_of([&] { apply_option_assignment(o, "colour=red"); });
  EXPECT_TRUE(contains(e, "'colour'")) << e;
  EXPECT_TRUE(contains(e, "image_width")) << e;  // lists the valid keys
  e = error_of([&] { apply_option_assignment(o, "threads=four"); });
  EXPECT_TRUE(contains(e, "threads") && contains(e, "'four'") && contains(e, "integer")) << e;
  e = error_of([&] { apply_option_assignment(o, "threads=4.5"); });
  EXPECT_TRUE(contains(e, "threads")) << e;
  e = error_of([&] { apply_option_assignment(o, "threads=99999999999"); });
  EXPECT_TRUE(contains(e, "threads")) << e;
  e = error_of([&] { apply_option_assignment(o, "eps=nan"); });
  EXPECT_TRUE(contains(e, "eps")) << e;
  e = error_of([&] { apply_option_assignment(o, "eps="); });
  EXPECT_TRUE(contains(e, "eps")) << e;
  e = error_of([&] { apply_option_assignment(o, "seed=-3"); });
  EXPECT_TRUE(contains(e, "seed")) << e;
  e = error_of([&] { apply_option_assignment(o, "threads"); });
  EXPECT_TRUE(contains(e, "key=value")) << e;
  e = error_of([&] { apply_option_assignment(o, "=4"); });
  EXPECT_TRUE(contains(e, "key=value")) << e;
  expect_equal(o, SolverOptions{});  // nothing was half-applied
}

TEST(OptionsIo, ValueStringFormatsCurrentValue) {
  SolverOptions o;
  EXPECT_EQ(option_value_string(o, "threads"), "1");
  EXPECT_EQ(option_value_string(o, "scheduler"), "blocked");
  EXPECT_EQ(option_value_string(o, "eps"), "0.0001");
  EXPECT_EQ(option_value_string(o, "locks.pool"), "0");
}

TEST(OptionsIo, DefaultsAndRoundTripValuesAreValid) {
  EXPECT_NO_THROW(validate_options(SolverOptions{}));
  SolverOptions o = non_default_options();
  o.cluster_receiver = ClusterReceiver::Cosine;
  EXPECT_NO_THROW(validate_options(o));
}

TEST(OptionsIo, ValidationNamesTheOffendingOption) {
  // A range error comes from validate_options; a mode's unknown value already from
  // the assignment, which parses it by its enum's table.
  const auto err = [](const std::string& assignment) {
    return error_of([&] {
      SolverOptions o;
      apply_option_assignment(o, assignment);
      validate_options(o);
    });
  };
  const std::pair<const char*, const char*> cases[] = {
      {"threads=0", "threads"},
      {"block_size=-1", "block_size"},
      {"eps=0", "eps"},
      {"eps=-1", "eps"},
      {"iterations=0", "iterations"},
      {"visibility_rays=-1", "visibility_rays"},
      {"min_area=-0.5", "min_area"},
      {"gather_tolerance=0", "gather_tolerance"},
      {"max_gather_sweeps=0", "max_gather_sweeps"},
      {"locks_pool=-2", "locks_pool"},
      {"decision_rays=fresh", "decision_rays"},
      {"decision_visibility_rays=-1", "decision_visibility_rays"},
      {"decision_visibility_rays=1025", "decision_visibility_rays"},
      {"push_visibility=rays", "push_visibility"},
      {"image_width=0", "image_width"},
      {"image_samples=17", "image_samples"},
      {"shading=phong", "shading"},
      {"exposure=65", "exposure"},
      {"pin=sideways", "pin"},
      {"placement=node7", "placement"},
      {"scheduler=", "scheduler"},
      {"oracle=", "oracle"},
      {"sides=both", "sides"},
      {"sides=", "sides"},
      {"emitter_sides=back", "emitter_sides"},
      {"segments=2", "segments"},
      {"segments=-1", "segments"},
      {"segments=4097", "segments"},
  };
  for (const auto& [assignment, key] : cases) {
    const std::string e = err(assignment);
    EXPECT_TRUE(contains(e, std::string("option ") + key) ||
                contains(e, std::string("option '") + key + "'"))
        << assignment << ": " << e;
  }
  EXPECT_TRUE(contains(err("pin=sideways"), "one of none, compact, scatter, node-round-robin"))
      << err("pin=sideways");
  EXPECT_TRUE(contains(err("sides="), "one of auto, one, two")) << err("sides=");
  EXPECT_TRUE(contains(err("threads=0"), "between 1 and 1024")) << err("threads=0");
  EXPECT_EQ(err("threads=1024"), "");
  EXPECT_EQ(err("min_area=0"), "");
  EXPECT_EQ(err("visibility_rays=0"), "");
  EXPECT_EQ(err("segments=0"), "");  // automatic
  EXPECT_EQ(err("segments=3"), "");
  EXPECT_EQ(err("sides=two"), "");
  EXPECT_TRUE(contains(err("sides=both"), "one of auto, one, two")) << err("sides=both");
}

// Every numeric key at 1e9, infinity, NaN and a negative value is refused by
// validate_options with the key named (or by the parser, for an integer key given a
// number it cannot hold), before anything is made: --threads 100000 crashed the OpenMP
// runtime, and threads = 1e9 in a config ran out of memory.
TEST(OptionsIo, EveryNumberHasBoundsOnBothSides) {
  for (const OptionInfo& info : option_table()) {
    if (info.type == OptionType::String || !info.choices.empty()) continue;
    if (info.name.find('.') != std::string::npos) continue;  // plug-in keys: plugin_params
    for (const char* v : {"1000000000", "1e9", "inf", "nan", "-1", "-1e300"}) {
      SolverOptions o;
      std::string e;
      try {
        apply_option_value(o, info.name, v, "--set");
        validate_options(o);
      } catch (const std::invalid_argument& x) {
        e = x.what();
      }
      // Meaningful values among these: any 64-bit seed; eps and max_memory_gb as large
      // as you like (nothing refined, no limit); exposure -1 (a stop darker).
      const std::string value = v;
      const bool large = value == "1000000000" || value == "1e9";
      const bool allowed = (info.name == "seed" && large) ||
                           ((info.name == "eps" || info.name == "max_memory_gb") && large) ||
                           (info.name == "exposure" && value == "-1");
      if (allowed) continue;
      EXPECT_TRUE(contains(e, info.name)) << info.name << " = " << v << ": '" << e << "'";
    }
  }
}

TEST(OptionsIo, CameraKeyIsCheckedWhereItIsRead) {
  SolverOptions o;
  apply_options_json(o, nlohmann::json::parse(R"({"camera": "eye=1,2,3:look=0,0,0"})"), "c.json");
  EXPECT_EQ(o.camera, "eye=1,2,3:look=0,0,0");
  apply_option_assignment(o, "camera=auto");
  EXPECT_EQ(o.camera, "auto");
  apply_option_value(o, "camera", "", "--camera");  // "": the scene's own, else automatic
  EXPECT_NO_THROW(validate_options(o));

  // In a config file: the file, the key, the text and the bad part.
  std::string e = error_of([&] {
    apply_options_json(o, nlohmann::json::parse(R"({"camera": "eye=1,2:look=0,0,0"})"), "c.json");
  });
  EXPECT_EQ(e,
            "c.json: option 'camera' = 'eye=1,2:look=0,0,0': 'eye=1,2' needs three numbers "
            "eye=X,Y,Z, got 2")
      << e;
  e = error_of([&] {
    apply_options_json(o, nlohmann::json::parse(R"({"camera": {"eye": [1, 2, 3]}})"), "c.json");
  });
  EXPECT_TRUE(contains(e, "c.json: option 'camera' expects a string, got object")) << e;
  e = error_of([&] { apply_option_assignment(o, "camera=eye=1,2,3"); });
  EXPECT_TRUE(
      contains(e, "--set camera=eye=1,2,3: option 'camera' = 'eye=1,2,3': no look=X,Y,Z part"))
      << e;
  e = error_of([&] { apply_option_value(o, "camera", "eye=1,2,3:look=1,2,3", "--camera"); });
  EXPECT_TRUE(contains(e,
                       "--camera: option 'camera' = 'eye=1,2,3:look=1,2,3': look is the same "
                       "point as eye"))
      << e;
  EXPECT_EQ(o.camera, "");  // nothing was half-applied
  // Options built in code are checked by validate_options.
  o.camera = "eye=0,0,0:look=1,0,0:fov=200";
  e = error_of([&] { validate_options(o); });
  EXPECT_TRUE(contains(e, "option camera = 'eye=0,0,0:look=1,0,0:fov=200': fov 200 is outside"))
      << e;
}

}  // namespace
}  // namespace hrad

namespace hrad {
namespace {

// docs/configuration.md's table is the option table's: one row per key, in table order,
// and for every mode the "allowed" column is its enum's names, in the enum table's
// order. A value added to an enum table fails here until docs/configuration.md says it.
TEST(OptionsIo, ReadmeTableListsEveryKeyAndEveryModeValue) {
  const std::string readme =
      test::read_text(std::filesystem::path(HRAD_SOURCE_DIR) / "docs" / "configuration.md");
  ASSERT_FALSE(readme.empty());
  std::size_t last = 0;
  for (const OptionInfo& info : option_table()) {
    const std::string start = "\n| `" + info.name + "` | ";
    const std::size_t at = readme.find(start);
    ASSERT_NE(at, std::string::npos) << "docs/configuration.md has no row for " << info.name;
    EXPECT_GT(at, last) << info.name << " is out of the table's order in docs/configuration.md";
    last = at;
    if (info.choices.empty()) continue;
    const std::string row = readme.substr(at + 1, readme.find('\n', at + 1) - at - 1);
    std::string allowed;
    for (const std::string& c : info.choices) allowed += (allowed.empty() ? "`" : ", `") + c + "`";
    EXPECT_TRUE(row.size() > allowed.size() + 2 &&
                row.compare(row.size() - allowed.size() - 2, allowed.size(), allowed) == 0)
        << info.name << ": docs/configuration.md's allowed column should be " << allowed
        << "\n  row: " << row;
  }
}

}  // namespace
}  // namespace hrad
