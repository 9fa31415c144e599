// Plug-in parameters (core/base/plugin_params.h): a scheduler or oracle declares its
// own, the option keys KIND.NAME.KEY reach it, and nothing given is silently ignored.
#include "core/base/plugin_params.h"
#include "core/config/options_io.h"
#include "core/scene/builtin_scenes.h"
#include "core/solver/solver.h"
#include "oracles/oracle.h"
#include "schedulers/scheduler.h"
#include "tests/error_text.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace hrad {
namespace {

using test::contains;
using test::error_of;

const ParamSpec kSpecs[] = {
    {"count", ParamSpec::Type::Int, 3, 0, 10, "how many"},
    {"scale", ParamSpec::Type::Double, 0.5, 0.1, 2, "how much"},
};

TEST(PluginParams, DefaultsValuesAndRanges) {
  const PluginParams none("test plug", kSpecs, {});
  EXPECT_EQ(none.get_int("count"), 3);
  EXPECT_EQ(none.get_double("scale"), 0.5);
  EXPECT_NO_THROW(none.report_unused());

  const PluginParams given("test plug", kSpecs, {{"count", "7"}, {"scale", "1.25"}});
  EXPECT_EQ(given.get_int("count"), 7);
  EXPECT_EQ(given.get_double("scale"), 1.25);
  EXPECT_NO_THROW(given.report_unused());

  const PluginParams bad("test plug", kSpecs, {{"count", "11"}});
  EXPECT_TRUE(contains(error_of([&] { (void)bad.get_int("count"); }), "between 0 and 10"));
  const PluginParams frac("test plug", kSpecs, {{"count", "2.5"}});
  EXPECT_TRUE(contains(error_of([&] { (void)frac.get_int("count"); }), "expected an integer"));
  // Reading a parameter the plug-in did not declare (or as another type) is its bug.
  EXPECT_THROW((void)none.get_int("other"), std::logic_error);
  EXPECT_THROW((void)none.get_double("count"), std::logic_error);

  EXPECT_EQ(check_param_value(kSpecs[0], "4", "x"), "4");
  EXPECT_EQ(check_param_value(kSpecs[1], "0.250", "x"), "0.25");
  EXPECT_TRUE(contains(error_of([] { (void)check_param_value(kSpecs[1], "2e9", "key"); }),
                       "key = 2e9 is out of range"));
}

TEST(PluginParams, WhatNobodyReadIsAnError) {
  const PluginParams p("test plug", kSpecs, {{"count", "1"}, {"scale", "1"}});
  (void)p.get_int("count");
  const std::string unread = error_of([&] { p.report_unused(); });
  EXPECT_TRUE(contains(unread, "test plug: parameter 'scale' = 1 was given but never read"))
      << unread;
  const PluginParams typo("test plug", kSpecs, {{"cont", "1"}});
  const std::string unknown = error_of([&] { typo.report_unused(); });
  EXPECT_TRUE(contains(unknown, "unknown parameter 'cont' (parameters: count, scale)")) << unknown;
}

// The registries build a plug-in with its parameters and report what it did not read.
TEST(PluginParams, RegistriesPassAndCheckParameters) {
  SchedulerConfig c{3, 4};
  c.params = {{"victims", "1"}};
  EXPECT_NO_THROW((void)make_scheduler("stealing", c));
  c.params = {{"victim", "1"}};
  EXPECT_TRUE(contains(error_of([&] { (void)make_scheduler("stealing", c); }),
                       "scheduler stealing: unknown parameter 'victim' (parameters: victims)"));
  c.params = {{"victims", "1"}};
  EXPECT_TRUE(contains(error_of([&] { (void)make_scheduler("stack", c); }),
                       "scheduler stack: unknown parameter 'victims' (parameters: none)"));
  EXPECT_TRUE(contains(error_of([] {
                         (void)make_oracle("bf", {{"dark_floor", "2"}});
                       }),
                       "between 0.001 and 1"));
  EXPECT_NO_THROW((void)make_oracle("error", {{"occluded_cluster_weight", "4"}}));
}

// scheduler.stealing.victims reaches the scheduler: with three workers and only worker 2
// holding tasks, a thief that looks at every other worker always finds them; one that
// looks at one victim (from its random start) sometimes looks at the empty worker 1.
TEST(PluginParams, StealingVictimsReachesTheScheduler) {
  auto failed_steals = [](const char* victims) {
    SchedulerConfig c{3, 1};
    c.params = {{"victims", victims}};
    auto s = make_scheduler("stealing", c);
    std::vector<Task> out(1);
    s->submit(2, std::vector<Task>(1));
    EXPECT_EQ(s->take(2, out), 1u);  // worker 2 owns deque 2
    s->submit(2, std::vector<Task>(40));
    int failed = 0;
    for (int i = 0; i < 20; ++i) failed += s->take(0, out) == 0;
    return failed;
  };
  EXPECT_EQ(failed_steals("0"), 0);
  EXPECT_EQ(failed_steals("2"), 0);
  EXPECT_GT(failed_steals("1"), 0);
}

TEST(PluginParams, OptionKeysAreCheckedAndReachTheOracle) {
  SolverOptions o;
  apply_option_assignment(o, "oracle.bf.dark-floor=1");  // '-' for '_'
  EXPECT_EQ(o.plugin_params.at("oracle.bf.dark_floor"), "1");
  EXPECT_EQ(plugin_params_of(o, "oracle"), (ParamValues{{"dark_floor", "1"}}));
  EXPECT_TRUE(plugin_params_of(o, "scheduler").empty());
  EXPECT_NO_THROW(validate_options(o));
  EXPECT_EQ(option_value_string(o, "oracle.bf.dark_floor"), "1");
  EXPECT_EQ(option_value_string(o, "oracle.bf.occluded_cluster_weight"), "8");  // default
  EXPECT_EQ(option_value_string(o, "scheduler.stealing.victims"), "");          // not the scheduler

  // Only the selected plug-in's parameters: nothing would read the others.
  SolverOptions other;
  apply_option_assignment(other, "scheduler.stealing.victims=2");
  const std::string e = error_of([&] { validate_options(other); });
  EXPECT_TRUE(contains(e, "the scheduler is blocked, which does not read it")) << e;
  EXPECT_THROW(apply_option_assignment(other, "scheduler.stealing.victims=-1"),
               std::invalid_argument);
  EXPECT_THROW(apply_option_assignment(other, "scheduler.stealing.thieves=1"),
               std::invalid_argument);
  EXPECT_THROW(apply_options_json(other, {{"oracle.bf.dark_floor", true}}, "c.json"),
               std::invalid_argument);

  // The parameter changes the solve: a threshold never tightened refines less.
  const Scene scene = make_builtin("builtin:cornell");
  SolverOptions fast;
  fast.eps = 1e-3;
  fast.iterations = 2;
  SolverOptions loose = fast;
  apply_option_assignment(loose, "oracle.bf.dark_floor=1");
  const auto links = [&](const SolverOptions& opts) {
    Solver s(scene, opts);
    return s.run().iterations.back().links;
  };
  EXPECT_LT(links(loose), links(fast));
}

}  // namespace
}  // namespace hrad
