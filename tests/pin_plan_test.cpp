// Pinning plans (core/parallel/pin_plan.h) on topologies described by hand and on hwloc's
// synthetic topologies: each policy puts refiners where it promises.
#include "core/parallel/pin_plan.h"
#include "core/parallel/topology.h"
#include "tests/env_guard.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>

namespace hrad {
namespace {

// nodes[i] cores of `smt` PUs each, PUs numbered core by core from 0.
TopologyInfo by_hand(const std::vector<int>& cores_per_node, int smt = 1,
                     const std::vector<int>& package_of_node = {}) {
  TopologyInfo t;
  int pu = 0;
  for (std::size_t n = 0; n < cores_per_node.size(); ++n) {
    NumaNodeInfo info;
    info.os_index = static_cast<int>(n);
    info.package = n < package_of_node.size() ? package_of_node[n] : -1;
    for (int c = 0; c < cores_per_node[n]; ++c) {
      std::vector<int> pus;
      for (int k = 0; k < smt; ++k) pus.push_back(pu++);
      info.core_pus.push_back(pus);
    }
    info.cores = cores_per_node[n];
    info.pus = cores_per_node[n] * smt;
    t.cores += info.cores;
    t.pus += info.pus;
    t.nodes.push_back(info);
  }
  t.numa_nodes = static_cast<int>(t.nodes.size());
  return t;
}

std::vector<int> nodes_of(const PinPlan& p) { return p.worker_nodes(); }
std::vector<int> single_pus(const PinPlan& p) {
  std::vector<int> pus;
  for (const ThreadBinding& b : p.refiners) {
    EXPECT_EQ(b.pus.size(), 1u);
    pus.push_back(b.pus.empty() ? -1 : b.pus[0]);
  }
  return pus;
}

TEST(PinPlan, TwoNodesTwoCoresEachPolicy) {
  const TopologyInfo t = by_hand({2, 2});
  const PinPlan compact = make_pin_plan(t, PinPolicy::Compact, 4);
  EXPECT_EQ(single_pus(compact), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(nodes_of(compact), (std::vector<int>{0, 0, 1, 1}));
  const PinPlan scatter = make_pin_plan(t, PinPolicy::Scatter, 4);
  EXPECT_EQ(single_pus(scatter), (std::vector<int>{0, 2, 1, 3}));
  EXPECT_EQ(nodes_of(scatter), (std::vector<int>{0, 1, 0, 1}));
  const PinPlan rr = make_pin_plan(t, PinPolicy::NodeRoundRobin, 3);
  EXPECT_EQ(nodes_of(rr), (std::vector<int>{0, 1, 0}));
  EXPECT_EQ(rr.refiners[0].pus, (std::vector<int>{0, 1}));
  EXPECT_EQ(rr.refiners[1].pus, (std::vector<int>{2, 3}));
  for (const PinPlan* p : {&compact, &scatter, &rr}) {
    EXPECT_FALSE(p->wrapped);
    EXPECT_EQ(p->solver.node, p->refiners[0].node);
    EXPECT_EQ(p->solver.pus, (std::vector<int>{0, 1}));  // the whole node of refiner 0
  }
  const PinPlan none = make_pin_plan(t, PinPolicy::None, 2);
  EXPECT_EQ(nodes_of(none), (std::vector<int>{0, 0}));
  EXPECT_TRUE(none.refiners[1].pus.empty());
  EXPECT_TRUE(none.solver.pus.empty());
}

TEST(PinPlan, FourNodesOfEightCores) {
  const TopologyInfo t = by_hand({8, 8, 8, 8});
  const PinPlan compact = make_pin_plan(t, PinPolicy::Compact, 32);
  const PinPlan scatter = make_pin_plan(t, PinPolicy::Scatter, 32);
  std::set<int> seen_c, seen_s;
  for (int i = 0; i < 32; ++i) {
    const auto& c = compact.refiners[static_cast<std::size_t>(i)];
    const auto& s = scatter.refiners[static_cast<std::size_t>(i)];
    EXPECT_EQ(c.pus, (std::vector<int>{i}));
    EXPECT_EQ(c.node, i / 8);
    // scatter: consecutive refiners on consecutive nodes, core i/4 of that node.
    EXPECT_EQ(s.node, i % 4) << i;
    EXPECT_EQ(s.pus, (std::vector<int>{(i % 4) * 8 + i / 4})) << i;
    seen_c.insert(c.pus[0]);
    seen_s.insert(s.pus[0]);
  }
  EXPECT_EQ(seen_c.size(), 32u);  // no PU used twice while there are enough
  EXPECT_EQ(seen_s.size(), 32u);
  EXPECT_FALSE(compact.wrapped);
  // One more refiner than PUs: it wraps around onto the first slot, and says so.
  const PinPlan wrap = make_pin_plan(t, PinPolicy::Scatter, 33);
  EXPECT_TRUE(wrap.wrapped);
  EXPECT_EQ(wrap.refiners[32].pus, wrap.refiners[0].pus);
  const PinPlan rr = make_pin_plan(t, PinPolicy::NodeRoundRobin, 6);
  EXPECT_EQ(nodes_of(rr), (std::vector<int>{0, 1, 2, 3, 0, 1}));
  EXPECT_EQ(rr.refiners[3].pus.size(), 8u);
  EXPECT_EQ(rr.refiners[3].pus.front(), 24);
}

TEST(PinPlan, UnevenNodesFillCoresEvenly) {
  const TopologyInfo t = by_hand({3, 1});  // PUs 0,1,2 on node 0; PU 3 on node 1
  EXPECT_EQ(nodes_of(make_pin_plan(t, PinPolicy::Compact, 4)), (std::vector<int>{0, 0, 0, 1}));
  const PinPlan s = make_pin_plan(t, PinPolicy::Scatter, 4);
  // Round 0: core 0 of each node; then node 1 has no core left.
  EXPECT_EQ(single_pus(s), (std::vector<int>{0, 3, 1, 2}));
  EXPECT_EQ(nodes_of(s), (std::vector<int>{0, 1, 0, 0}));
  // A memory-only node (no PUs) is never chosen.
  TopologyInfo m = by_hand({2, 0, 2});
  EXPECT_EQ(nodes_of(make_pin_plan(m, PinPolicy::Scatter, 4)), (std::vector<int>{0, 2, 0, 2}));
  EXPECT_EQ(nodes_of(make_pin_plan(m, PinPolicy::NodeRoundRobin, 3)), (std::vector<int>{0, 2, 0}));
}

TEST(PinPlan, HyperthreadsCompactSharesCoresScatterDoesNot) {
  // One node, 2 cores x 2 PUs, numbered as Linux does: core 0 = {0, 2}, core 1 = {1, 3}.
  TopologyInfo t = by_hand({2}, 2);
  t.nodes[0].core_pus = {{0, 2}, {1, 3}};
  EXPECT_EQ(single_pus(make_pin_plan(t, PinPolicy::Compact, 4)), (std::vector<int>{0, 2, 1, 3}));
  EXPECT_EQ(single_pus(make_pin_plan(t, PinPolicy::Scatter, 4)), (std::vector<int>{0, 1, 2, 3}));
}

TEST(PinPlan, ScatterAlternatesPackagesFirst) {
  // Two packages with two nodes each (sub-NUMA clustering): nodes 0,1 on package 0.
  const TopologyInfo t = by_hand({1, 1, 1, 1}, 1, {0, 0, 1, 1});
  EXPECT_EQ(nodes_of(make_pin_plan(t, PinPolicy::Scatter, 4)), (std::vector<int>{0, 2, 1, 3}));
}

TEST(PinPlan, BadInputIsAnError) {
  EXPECT_THROW((void)parse_enum<PinPolicy>("spread", "pin"), std::invalid_argument);
  EXPECT_EQ(parse_enum<PinPolicy>("node-round-robin", "pin"), PinPolicy::NodeRoundRobin);
  EXPECT_STREQ(enum_name(parse_enum<PinPolicy>("scatter", "pin")), "scatter");
  EXPECT_THROW((void)make_pin_plan(by_hand({2}), PinPolicy::Compact, 0), std::invalid_argument);
  EXPECT_THROW((void)make_pin_plan(TopologyInfo{}, PinPolicy::Compact, 1), std::invalid_argument);
  EXPECT_EQ(format_pu_list({3, 0, 1, 2, 8, 10, 11}), "0-3,8,10-11");
  EXPECT_EQ(format_pu_list({}), "");
}

TEST(PinPlan, SyntheticTopologiesGiveTheHandBuiltPlans) {
  struct Case {
    const char* spec;
    std::vector<int> cores;
  };
  for (const Case& c :
       {Case{"node:2 core:2 pu:1", {2, 2}}, Case{"node:4 core:8 pu:1", {8, 8, 8, 8}}}) {
    TopologyInfo t;
    {
      EnvGuard env("HWLOC_SYNTHETIC", c.spec);
      t = discover_topology();
    }
    ASSERT_TRUE(t.synthetic) << c.spec;
    ASSERT_EQ(t.nodes.size(), c.cores.size()) << c.spec;
    const TopologyInfo h = by_hand(c.cores);
    for (std::size_t n = 0; n < t.nodes.size(); ++n)
      EXPECT_EQ(t.nodes[n].core_pus, h.nodes[n].core_pus) << c.spec << " node " << n;
    for (PinPolicy p : {PinPolicy::Compact, PinPolicy::Scatter, PinPolicy::NodeRoundRobin}) {
      const int threads = t.pus + 1;
      const PinPlan a = make_pin_plan(t, p, threads), b = make_pin_plan(h, p, threads);
      for (int i = 0; i < threads; ++i) {
        EXPECT_EQ(a.refiners[static_cast<std::size_t>(i)].pus,
                  b.refiners[static_cast<std::size_t>(i)].pus)
            << c.spec << " " << enum_name(p) << " refiner " << i;
        EXPECT_EQ(a.refiners[static_cast<std::size_t>(i)].node,
                  b.refiners[static_cast<std::size_t>(i)].node);
      }
    }
  }
}

TEST(PinPlan, SyntheticHyperthreadedPackages) {
  TopologyInfo t;
  {
    EnvGuard env("HWLOC_SYNTHETIC", "package:2 numa:2 core:2 pu:2");
    t = discover_topology();
  }
  ASSERT_EQ(t.numa_nodes, 4);
  ASSERT_EQ(t.pus, 16);
  EXPECT_EQ(t.nodes[0].core_pus, (std::vector<std::vector<int>>{{0, 1}, {2, 3}}));
  const PinPlan s = make_pin_plan(t, PinPolicy::Scatter, 8);
  // Packages alternate first, then the second node of each, core 0 then core 1.
  EXPECT_EQ(nodes_of(s), (std::vector<int>{0, 2, 1, 3, 0, 2, 1, 3}));
  EXPECT_EQ(single_pus(s), (std::vector<int>{0, 8, 4, 12, 2, 10, 6, 14}));
}

TEST(PinPlan, BindingOnASyntheticTopologyIsOnlyPlanned) {
  EnvGuard env("HWLOC_SYNTHETIC", "node:2 core:2 pu:1");
  const Topology topo;
  ASSERT_TRUE(topo.info().synthetic);
  const PinPlan p = make_pin_plan(topo.info(), PinPolicy::Scatter, 2);
  std::string warning;
  EXPECT_STREQ(bind_thread(&topo, p.refiners[1], &warning), "planned");
  EXPECT_STREQ(bind_thread(&topo, ThreadBinding{}, &warning), "none");
  EXPECT_STREQ(bind_thread(nullptr, p.refiners[1], &warning), "none");
  EXPECT_EQ(topo.node_of_address(&warning), -1);
}

TEST(PinPlan, BindingOnThisMachineIsApplied) {
  if (std::getenv("HWLOC_SYNTHETIC") || std::getenv("HWLOC_XMLFILE"))
    GTEST_SKIP() << "HWLOC_SYNTHETIC or HWLOC_XMLFILE is set";
  const Topology topo;
  // Bind a helper thread (not the test thread) to every PU of node 0: allowed here.
  const PinPlan p = make_pin_plan(topo.info(), PinPolicy::NodeRoundRobin, 1);
  std::string warning, outcome;
  std::thread([&] { outcome = bind_thread(&topo, p.refiners[0], &warning); }).join();
  EXPECT_EQ(outcome, "applied") << warning;
}

}  // namespace
}  // namespace hrad
