#include "core/parallel/topology.h"
#include "tests/env_guard.h"
#include "tests/error_text.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

namespace hrad {
namespace {

using test::contains;
using test::error_of;

bool user_set_topology() {
  return std::getenv("HWLOC_SYNTHETIC") != nullptr || std::getenv("HWLOC_XMLFILE") != nullptr;
}

TEST(Topology, ThisMachineIsConsistent) {
  if (user_set_topology()) GTEST_SKIP() << "HWLOC_SYNTHETIC or HWLOC_XMLFILE is set";
  const TopologyInfo t = discover_topology();
  EXPECT_FALSE(t.synthetic);
  EXPECT_GE(t.numa_nodes, 1);
  EXPECT_GE(t.cores, 1);
  EXPECT_GE(t.pus, t.cores);
  EXPECT_EQ(static_cast<int>(t.nodes.size()), t.numa_nodes);
  int pus = 0;
  for (const NumaNodeInfo& n : t.nodes) pus += n.pus;
  EXPECT_EQ(pus, t.pus);
  EXPECT_NE(t.description.find("this machine"), std::string::npos) << t.description;
}

// hwloc passes the CPU model on as the processor reports it, padded with blanks
// ("Oxide Virtual Turin-like Processor             "); manifests, rows and captions
// show it tidied.
TEST(Topology, CpuModelIsTidied) {
  EXPECT_EQ(tidy_cpu_model("Oxide Virtual Turin-like Processor             "),
            "Oxide Virtual Turin-like Processor");
  EXPECT_EQ(tidy_cpu_model("  Intel(R) Xeon(R) CPU           E5-2680 0 @ 2.70GHz\t"),
            "Intel(R) Xeon(R) CPU E5-2680 0 @ 2.70GHz");
  EXPECT_EQ(tidy_cpu_model("   "), "");
  EXPECT_EQ(tidy_cpu_model(""), "");
  const TopologyInfo t = discover_topology();
  EXPECT_EQ(t.cpu_model, tidy_cpu_model(t.cpu_model));
  EXPECT_EQ(t.description, tidy_cpu_model(t.description)) << "'" << t.description << "'";
}

TEST(Topology, SyntheticTwoNodes) {
  TopologyInfo t;
  {
    EnvGuard env("HWLOC_SYNTHETIC", "node:2 core:2 pu:1");
    t = discover_topology();
  }
  EXPECT_TRUE(t.synthetic);
  EXPECT_EQ(t.numa_nodes, 2);
  EXPECT_EQ(t.cores, 4);
  EXPECT_EQ(t.pus, 4);
  ASSERT_EQ(t.nodes.size(), 2u);
  EXPECT_EQ(t.nodes[0].cores, 2);
  EXPECT_EQ(t.nodes[1].cores, 2);
  EXPECT_EQ(t.nodes[0].cpus, "0-1");
  EXPECT_EQ(t.nodes[1].cpus, "2-3");
  EXPECT_NE(t.description.find("node:2 core:2 pu:1"), std::string::npos) << t.description;
  // The variable is gone again: back to this machine.
  if (!user_set_topology()) {
    EXPECT_FALSE(discover_topology().synthetic);
  }
}

// hwloc rejected these and described this machine instead, without a word.
TEST(Topology, ARejectedSyntheticOrXmlTopologyIsAnError) {
  const auto error = [] { return error_of<std::runtime_error>([] { (void)discover_topology(); }); };
  {
    EnvGuard env("HWLOC_SYNTHETIC", "bogus:3");
    const std::string e = error();
    EXPECT_TRUE(contains(e, "HWLOC_SYNTHETIC=\"bogus:3\": hwloc does not accept")) << e;
  }
  {
    // hwloc took minutes to build this one (262,144 PUs) before anything was said.
    EnvGuard env("HWLOC_SYNTHETIC", "pack:64 node:16(memory=1GB) core:64 pu:4");
    const std::string e = error();
    EXPECT_TRUE(contains(e, "describes 262144 PUs; at most 65536 are taken")) << e;
  }
  if (user_set_topology()) return;  // the other variable may be the user's
  EnvGuard env("HWLOC_XMLFILE", "/nonexistent/topology.xml");
  const std::string e = error();
  EXPECT_TRUE(contains(e, "HWLOC_XMLFILE=/nonexistent/topology.xml: hwloc cannot")) << e;
}

// Each node's cores and PUs come from one walk over the PUs: a synthetic machine of
// 16,384 PUs took 41 s to describe (per-core lookups among all objects), now about 2 s,
// most of it hwloc's own build.
TEST(Topology, ALargeSyntheticMachineIsDescribedQuickly) {
  EnvGuard env("HWLOC_SYNTHETIC", "pack:4 node:4 core:64 pu:4");
  const TopologyInfo t = discover_topology();
  EXPECT_EQ(t.pus, 4096);
  ASSERT_EQ(t.nodes.size(), 16u);
  for (const NumaNodeInfo& n : t.nodes) {
    EXPECT_EQ(n.cores, 64);
    EXPECT_EQ(n.pus, 256);
    ASSERT_EQ(n.core_pus.size(), 64u);
    EXPECT_EQ(n.core_pus[1], (std::vector<int>{n.core_pus[0][0] + 4, n.core_pus[0][0] + 5,
                                               n.core_pus[0][0] + 6, n.core_pus[0][0] + 7}));
  }
  EXPECT_EQ(t.nodes[15].core_pus.back().back(), 4095);
}

TEST(Topology, SyntheticPackagesWithHyperthreads) {
  EnvGuard env("HWLOC_SYNTHETIC", "pack:2 node:2 core:4 pu:2");
  const TopologyInfo t = discover_topology();
  EXPECT_EQ(t.packages, 2);
  EXPECT_EQ(t.numa_nodes, 4);
  EXPECT_EQ(t.cores, 16);
  EXPECT_EQ(t.pus, 32);
  ASSERT_EQ(t.nodes.size(), 4u);
  EXPECT_EQ(t.nodes[0].package, 0);
  EXPECT_EQ(t.nodes[3].package, 1);
  EXPECT_EQ(t.nodes[2].pus, 8);
}

TEST(Topology, FormatListsPackagesAndNodes) {
  EnvGuard env("HWLOC_SYNTHETIC", "pack:2 node:1 core:2 pu:2");
  const std::string s = format_topology(discover_topology());
  EXPECT_NE(s.find("2 packages, 2 NUMA nodes, 4 cores, 8 PUs"), std::string::npos) << s;
  EXPECT_NE(s.find("  Package 1\n"), std::string::npos) << s;
  EXPECT_NE(s.find("    NUMA node 1: 2 cores, 4 PUs (cpus 4-7)"), std::string::npos) << s;
}

TEST(Topology, FormatWithoutPackageLevel) {
  TopologyInfo t;
  t.description = "test";
  t.numa_nodes = 1;
  t.cores = t.pus = 1;
  t.nodes.push_back({0, -1, 1, 1, "0", 0});
  const std::string s = format_topology(t);
  EXPECT_NE(s.find("0 packages, 1 NUMA node, 1 core, 1 PU "), std::string::npos) << s;
  EXPECT_NE(s.find("  NUMA node 0: 1 core, 1 PU (cpus 0), memory unknown"), std::string::npos) << s;
}

}  // namespace
}  // namespace hrad
