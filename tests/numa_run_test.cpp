// NUMA placement end to end: the `locality` scheduler on two nodes (own node first,
// exactly once), and solves on hwloc's synthetic two-node topology that report the
// planned bindings, bytes per node and local-access ratios, with the links of the
// sequential run.
#include "core/config/options_io.h"
#include "core/hierarchy/element.h"
#include "core/output/stats_json.h"
#include "core/parallel/topology.h"
#include "core/scene/builtin_scenes.h"
#include "core/solver/solver.h"
#include "core/stage/run_stage.h"
#include "schedulers/pool_order.h"
#include "schedulers/scheduler.h"
#include "tests/env_guard.h"

#include <gtest/gtest.h>
#include <omp.h>
#include <sys/wait.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace hrad {
namespace {

Task task_on(Element& receiver, std::uint64_t id) {
  Task t;
  t.receiver = &receiver;
  t.source = &receiver;
  t.id = id;
  return t;
}

TEST(SchedLocality, ServesTheRefinersOwnNodeFirst) {
  Element e0, e1;
  e0.home_node = 0;
  e1.home_node = 1;
  auto s = make_scheduler("locality", SchedulerConfig{2, 4, 2, {0, 1}});
  std::vector<Task> batch;
  for (std::uint64_t i = 0; i < 6; ++i) batch.push_back(task_on(i % 2 ? e1 : e0, i));
  s->submit(0, batch);
  std::vector<Task> out(8);
  ASSERT_EQ(s->take(1, out), 3u);  // only node 1's tasks, though the block allows 4
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(out[i].receiver, &e1);
  EXPECT_EQ(out[0].id, 5u);  // newest first, as `blocked`
  ASSERT_EQ(s->take(0, out), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(out[i].receiver, &e0);
  EXPECT_EQ(s->counters().steals, 0u);
  // Node 0's refiner finds its pool empty and takes node 1's tasks: counted as steals.
  s->submit(1, std::vector<Task>{task_on(e1, 10), task_on(e1, 11)});
  ASSERT_EQ(s->take(0, out), 2u);
  EXPECT_EQ(out[0].receiver, &e1);
  EXPECT_EQ(s->counters().steals, 2u);
  EXPECT_EQ(s->take(0, out), 0u);
  EXPECT_EQ(s->take(1, out), 0u);
  const SchedulerCounters c = s->counters();
  EXPECT_EQ(c.takes, 3u);
  EXPECT_EQ(c.empty_takes, 2u);
  EXPECT_EQ(c.submits, 2u);
}

// Exactly once on three nodes: a task tree (task i creates children 3i+1..3i+3 below
// kTasks; its number rides in `priority`, as the driver sets the ids), receivers spread
// over the nodes, four workers on the stage driver refinement runs on.
struct ThreeNodeTree {
  static constexpr std::uint64_t kTasks = 30000;
  std::vector<Element>& elements;
  std::vector<std::atomic<int>> seen = std::vector<std::atomic<int>>(kTasks);
  Task task(std::uint64_t k) {
    Task t = task_on(elements[k % 3], 0);
    t.priority = static_cast<float>(k);
    return t;
  }
  void begin(int, int) {}
  void process(int, const Task& t, std::vector<Task>& out) {
    const auto id = static_cast<std::uint64_t>(t.priority);
    seen[id].fetch_add(1, std::memory_order_relaxed);
    for (std::uint64_t k = 3 * id + 1; k <= 3 * id + 3 && k < kTasks; ++k) out.push_back(task(k));
  }
  std::uint64_t end_block(int, std::size_t) { return 0; }
  std::uint64_t bytes_held(int) { return 0; }
  void end_loop(int) {}
  void finish(int) {}
};

TEST(SchedLocality, EveryTaskExactlyOnceOnThreeNodes) {
  std::vector<Element> elements(3);
  for (std::size_t n = 0; n < 3; ++n) elements[n].home_node = static_cast<std::uint16_t>(n);
  for (int block : {1, 7}) {
    auto s = make_scheduler("locality", SchedulerConfig{4, block, 3, {0, 1, 2, 0}});
    ThreeNodeTree body{elements};
    std::vector<Task> initial{body.task(0)};
    StageConfig cfg;
    cfg.threads = 4;
    cfg.block_size = block;
    cfg.time_limit_s = 60;  // a lost task: fail, not hang
    EXPECT_FALSE(run_stage(*s, initial, cfg, body).timed_out);
    for (std::uint64_t i = 0; i < ThreeNodeTree::kTasks; ++i)
      ASSERT_EQ(body.seen[i].load(), 1) << "task " << i;
  }
}

// pool_order sorts each batch: a LIFO pool then hands out descending keys, a FIFO
// pool ascending ones; `subtree` groups by input polygon first.
TEST(SchedPoolOrder, CentralPoolsSortEachBatch) {
  std::vector<Element> e(6);
  const std::uint32_t faces[] = {2, 1, 2, 0, 1, 0};
  for (std::size_t i = 0; i < e.size(); ++i) e[i].face = faces[i];
  const std::vector<std::size_t> scrambled = {3, 0, 5, 1, 4, 2};
  auto ids_after = [&](const std::string& name, PoolOrder order) {
    SchedulerConfig c{1, 16};
    c.pool_order = order;
    auto s = make_scheduler(name, c);
    std::vector<Task> batch;
    for (std::size_t i : scrambled) batch.push_back(task_on(e[i], i));
    s->submit(0, batch);
    std::vector<Task> out(16);
    const std::size_t n = s->take(0, out);
    std::vector<std::uint64_t> ids;
    for (std::size_t i = 0; i < n; ++i) ids.push_back(out[i].id);
    return ids;
  };
  using V = std::vector<std::uint64_t>;
  for (const char* lifo : {"stack", "blocked", "locality"}) {
    EXPECT_EQ(ids_after(lifo, PoolOrder::Submitted), (V{2, 4, 1, 5, 0, 3})) << lifo;
    EXPECT_EQ(ids_after(lifo, PoolOrder::Address), (V{5, 4, 3, 2, 1, 0})) << lifo;
    // faces 0: {3, 5}, 1: {1, 4}, 2: {0, 2}; by address inside a face.
    EXPECT_EQ(ids_after(lifo, PoolOrder::Subtree), (V{2, 0, 4, 1, 5, 3})) << lifo;
  }
  EXPECT_EQ(ids_after("fifo", PoolOrder::Address), (V{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(ids_after("fifo", PoolOrder::Subtree), (V{3, 5, 1, 4, 0, 2}));
  EXPECT_THROW((void)parse_enum<PoolOrder>("random", "pool_order"), std::invalid_argument);
}

struct NumaSolve {
  RunStats stats;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> links;
};

NumaSolve solve_cornell(const std::string& scheduler, int threads, const std::string& pin,
                        const std::string& placement, const std::string& pool_order = "submitted") {
  static const Scene scene = make_builtin("builtin:cornell");
  SolverOptions o;
  o.scheduler = scheduler;
  o.threads = threads;
  o.block_size = 4;
  apply_option_value(o, "pin", pin, "test");
  apply_option_value(o, "placement", placement, "test");
  apply_option_value(o, "pool_order", pool_order, "test");
  o.eps = 3e-4;
  o.iterations = 2;
  Solver s(scene, o);
  NumaSolve r;
  r.stats = s.run();
  r.links = s.link_ids();
  return r;
}

void expect_consistent_numa_stats(const RunStats& stats, const std::string& what) {
  ASSERT_FALSE(stats.iterations.empty()) << what;
  for (const IterationStats& it : stats.iterations) {
    ASSERT_EQ(it.bytes_per_node.size(), 2u) << what;
    ASSERT_EQ(it.element_bytes_per_node.size(), 2u) << what;
    ASSERT_EQ(it.link_bytes_per_node.size(), 2u) << what;
    EXPECT_EQ(it.element_bytes_per_node[0] + it.element_bytes_per_node[1],
              it.elements * sizeof(Element))
        << what;
    // Every link byte is in an arena: the per-node counts add up to the link memory.
    EXPECT_EQ(it.link_bytes_per_node[0] + it.link_bytes_per_node[1], it.bytes.at("links")) << what;
    EXPECT_GE(it.bytes.at("links"), it.links * sizeof(Link)) << what;
    for (std::size_t n = 0; n < 2; ++n)
      EXPECT_EQ(it.bytes_per_node[n], it.element_bytes_per_node[n] + it.link_bytes_per_node[n])
          << what;
    std::uint64_t local = 0, remote = 0, tasks = 0;
    for (const RefinerStats& r : it.refiners) {
      local += r.tasks_local;
      remote += r.tasks_remote;
      tasks += r.tasks;
      EXPECT_EQ(r.tasks_local + r.tasks_remote, r.tasks) << what;
    }
    EXPECT_EQ(tasks, it.tasks) << what;
    EXPECT_EQ(local + remote, tasks) << what;
    ASSERT_GT(tasks, 0u) << what;
    EXPECT_GE(it.local_access_ratio, 0.0) << what;
    EXPECT_LE(it.local_access_ratio, 1.0) << what;
    EXPECT_NEAR(it.local_access_ratio, static_cast<double>(local) / static_cast<double>(tasks),
                1e-12)
        << what;
  }
}

TEST(SolverNuma, SyntheticTwoNodesScatterLocality) {
  const NumaSolve ref = solve_cornell("stack", 1, "none", "first-touch");
  EnvGuard env("HWLOC_SYNTHETIC", "node:2 core:2 pu:1");
  const NumaSolve got = solve_cornell("locality", 4, "scatter", "first-touch");
  EXPECT_TRUE(got.links == ref.links) << "links differ from the sequential run";
  expect_consistent_numa_stats(got.stats, "scatter/first-touch/locality");
  for (const IterationStats& it : got.stats.iterations) {
    ASSERT_EQ(it.refiners.size(), 4u);
    // scatter on 2 nodes x 2 cores: PUs 0, 2, 1, 3 on nodes 0, 1, 0, 1; only planned.
    const char* pus[] = {"0", "2", "1", "3"};
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(it.refiners[i].node, static_cast<int>(i % 2));
      EXPECT_EQ(it.refiners[i].pus, pus[i]);
      EXPECT_EQ(it.refiners[i].bound, "planned");
    }
  }
  // First touch: a refiner compacts the lists it started into its own link arena, on
  // its planned node. Which refiner starts which list depends on timing (with 4
  // refiners on 2 cores a node's refiners may start none in an iteration), so what is
  // guaranteed is the bookkeeping: each node holds exactly the link bytes of the
  // refiners planned on it, and the cluster tree (refiner 0's arena) is on node 0.
  for (const IterationStats& it : got.stats.iterations) {
    std::vector<std::uint64_t> by_plan(2, 0);
    std::uint64_t total = 0;
    for (const RefinerStats& r : it.refiners) {
      by_plan[static_cast<std::size_t>(r.node)] += r.link_bytes;
      total += r.link_bytes;
    }
    EXPECT_EQ(it.link_bytes_per_node, by_plan) << "iteration " << it.iteration;
    EXPECT_GT(total, 0u);
    EXPECT_GT(it.element_bytes_per_node[0], 0u);
  }
  const nlohmann::json j = stats_to_json(got.stats);
  const nlohmann::json& it = j["iterations"][0];
  EXPECT_EQ(it["bytes_per_node"].size(), 2u);
  EXPECT_EQ(it["link_bytes_per_node"].size(), 2u);
  EXPECT_EQ(it["element_bytes_per_node"].size(), 2u);
  EXPECT_TRUE(it["local_access_ratio"].is_number());
  EXPECT_EQ(it["refiners"][1]["bound"], "planned");
  EXPECT_EQ(it["refiners"][1]["node"], 1);
  EXPECT_EQ(it["refiners"][1]["pus"], "2");
  EXPECT_TRUE(it["refiners"][1].contains("tasks_local"));
  EXPECT_TRUE(it["placement_check"].is_null());  // not this machine's pages: no check
  EXPECT_FALSE(got.stats.iterations[0].placement_check.checked);
  bool planned_warning = false;
  for (const std::string& w : got.stats.warnings)
    planned_warning |= w.find("planned") != std::string::npos;
  EXPECT_TRUE(planned_warning);
}

TEST(SolverNuma, SyntheticTwoNodesInterleaveAndNode0) {
  EnvGuard env("HWLOC_SYNTHETIC", "node:2 core:2 pu:1");
  const NumaSolve inter = solve_cornell("blocked", 2, "node-round-robin", "interleave");
  expect_consistent_numa_stats(inter.stats, "node-round-robin/interleave");
  const IterationStats& a = inter.stats.iterations.back();
  EXPECT_EQ(a.refiners[1].node, 1);
  EXPECT_EQ(a.refiners[1].pus, "2-3");
  // Interleaved pages: the two nodes' shares differ by at most a page per chunk,
  // for elements and for links.
  const double total = static_cast<double>(a.bytes_per_node[0] + a.bytes_per_node[1]);
  EXPECT_NEAR(static_cast<double>(a.bytes_per_node[0]) / total, 0.5, 0.05);
  const double links = static_cast<double>(a.link_bytes_per_node[0] + a.link_bytes_per_node[1]);
  EXPECT_NEAR(static_cast<double>(a.link_bytes_per_node[0]) / links, 0.5, 0.05);
  const NumaSolve zero = solve_cornell("locality", 2, "scatter", "node0");
  expect_consistent_numa_stats(zero.stats, "scatter/node0");
  const IterationStats& z = zero.stats.iterations.back();
  EXPECT_EQ(z.bytes_per_node[1], 0u);  // elements and links
  EXPECT_GT(z.link_bytes_per_node[0], 0u);
  // Every receiver is on node 0: refiner 0 (node 0) only has local tasks, refiner 1
  // (node 1) only remote ones.
  EXPECT_EQ(z.refiners[0].tasks_remote, 0u);
  EXPECT_EQ(z.refiners[1].tasks_local, 0u);
}

TEST(SolverNuma, PoolOrdersKeepTheSequentialLinks) {
  const NumaSolve ref = solve_cornell("stack", 1, "none", "first-touch");
  for (const char* order : {"address", "subtree"}) {
    EXPECT_TRUE(solve_cornell("blocked", 2, "none", "first-touch", order).links == ref.links)
        << order;
    EXPECT_TRUE(solve_cornell("fifo", 2, "none", "first-touch", order).links == ref.links) << order;
  }
}

TEST(SolverNuma, UnpinnedOnThisMachineIsAllLocal) {
  if (std::getenv("HWLOC_SYNTHETIC") || std::getenv("HWLOC_XMLFILE"))
    GTEST_SKIP() << "HWLOC_SYNTHETIC or HWLOC_XMLFILE is set";
  const NumaSolve r = solve_cornell("locality", 2, "none", "first-touch");
  for (const IterationStats& it : r.stats.iterations) {
    EXPECT_DOUBLE_EQ(it.local_access_ratio, 1.0);  // one node here (or unpinned: node 0)
    for (const RefinerStats& rs : it.refiners) EXPECT_EQ(rs.bound, "none");
  }
}

// OpenMP keeps its threads between runs: after a pinned run, the caller's thread and
// the team's other thread may again run wherever they could before (the experiment
// harness runs pinned and unpinned configurations in one process).
TEST(SolverNuma, PinnedRunGivesTheThreadsTheirCpusBack) {
  if (std::getenv("HWLOC_SYNTHETIC") || std::getenv("HWLOC_XMLFILE"))
    GTEST_SKIP() << "HWLOC_SYNTHETIC or HWLOC_XMLFILE is set";
  const Topology topo;
  const std::vector<int> before = topo.current_thread_pus();
  ASSERT_FALSE(before.empty());
  if (before.size() < 2) GTEST_SKIP() << "this thread may only run on one PU";
  const NumaSolve r = solve_cornell("blocked", 2, "compact", "first-touch");
  ASSERT_EQ(r.stats.iterations.back().refiners.size(), 2u);
  EXPECT_EQ(r.stats.iterations.back().refiners[1].pus, std::to_string(before[1]));
  for (const RefinerStats& rs : r.stats.iterations.back().refiners) EXPECT_EQ(rs.bound, "applied");
  // The OS agrees with the arenas' bookkeeping on every sampled page (one node here).
  for (const IterationStats& it : r.stats.iterations) {
    EXPECT_TRUE(it.placement_check.checked);
    EXPECT_GT(it.placement_check.pages, 0u);
    EXPECT_EQ(it.placement_check.agree + it.placement_check.unknown, it.placement_check.pages);
    EXPECT_GT(it.placement_check.agree, 0u);
  }
  EXPECT_EQ(topo.current_thread_pus(), before);
  std::vector<std::vector<int>> team(2);
#pragma omp parallel num_threads(2)
  team[static_cast<std::size_t>(omp_get_thread_num())] = topo.current_thread_pus();
  EXPECT_EQ(team[0], before);
  EXPECT_EQ(team[1], before);
}

std::string run_hrad(const std::string& args, int* status) {
  std::string out;
  FILE* p = ::popen((std::string(HRAD_BINARY) + " " + args + " 2>&1").c_str(), "r");
  if (!p) return out;
  char buf[512];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  const int st = ::pclose(p);
  *status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return out;
}

TEST(NumaCli, TopologyPrintsThePinPlan) {
  EnvGuard env("HWLOC_SYNTHETIC", "node:2 core:2 pu:1");
  int status = -1;
  const std::string out = run_hrad("topology --pin scatter --threads 5", &status);
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("pin scatter, 5 refiners (planned only"), std::string::npos) << out;
  EXPECT_NE(out.find("refiner 1: node 1, PUs 2\n"), std::string::npos) << out;
  EXPECT_NE(out.find("refiner 2: node 0, PUs 1\n"), std::string::npos) << out;
  EXPECT_NE(out.find("solver thread: node 0, PUs 0-1\n"), std::string::npos) << out;
  EXPECT_NE(out.find("wraps around"), std::string::npos) << out;
  const std::string bad = run_hrad("topology --pin spread", &status);
  EXPECT_NE(status, 0) << bad;
  EXPECT_NE(bad.find("spread"), std::string::npos) << bad;
}

}  // namespace
}  // namespace hrad
