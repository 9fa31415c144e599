// The trace simulator (experiments/sim/) on hand-made traces with known answers: a
// chain gains nothing from processors, n equal independent tasks take ceil(n/p) rounds,
// a central lock held c ns per take caps throughput at 1/c, every task runs exactly
// once, one processor with free scheduling takes exactly the summed durations, and
// work stealing scales on a balanced tree. Plus the trace file round trip, the DAG's
// critical path, bad input, and `hrad simulate` end to end.
#include "core/parallel/trace.h"
#include "experiments/sim/simulator.h"
#include "schedulers/scheduler.h"
#include "tests/sim_config.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace hrad::sim {
namespace {

namespace fs = std::filesystem;

const Policy kAllPolicies[] = {Policy::kStack, Policy::kFifo, Policy::kPriority, Policy::kBlocked,
                               Policy::kStealing};

/// Builds trace records the way the stage driver (core/stage/run_stage.h) numbers tasks.
class TraceBuilder {
 public:
  explicit TraceBuilder(int iteration = 1) : iteration_(static_cast<std::uint8_t>(iteration)) {}
  /// An initial task; returns its record index.
  std::size_t root(std::uint32_t duration_ns) {
    TraceRecord r;
    r.id = (std::uint64_t{iteration_} << 40) | roots_++;
    r.duration_ns = duration_ns;
    r.iteration = iteration_;
    records.push_back(r);
    return records.size() - 1;
  }
  /// Gives record `parent` `n` children of `duration_ns`; returns the first child's index.
  std::size_t children(std::size_t parent, int n, std::uint32_t duration_ns) {
    records[parent].first_child = next_id();
    records[parent].children = static_cast<std::uint16_t>(n);
    const std::size_t first = records.size();
    for (int i = 0; i < n; ++i) {
      TraceRecord r;
      r.id = next_id();
      ++seq_;
      r.duration_ns = duration_ns;
      r.iteration = iteration_;
      records.push_back(r);
    }
    return first;
  }
  std::vector<TraceRecord> records;

 private:
  std::uint64_t next_id() const {
    return (std::uint64_t{1} << 48) | (std::uint64_t{iteration_} << 40) | seq_;
  }
  std::uint8_t iteration_;
  std::uint64_t roots_ = 0, seq_ = 0;
};

using test::config;

std::vector<TraceRecord> chain(int n, std::uint32_t d) {
  TraceBuilder b;
  std::size_t t = b.root(d);
  for (int i = 1; i < n; ++i) t = b.children(t, 1, d);
  return b.records;
}

std::vector<TraceRecord> binary_tree(int depth, std::uint32_t d) {
  TraceBuilder b;
  std::vector<std::size_t> level = {b.root(d)};
  for (int k = 1; k < depth; ++k) {
    std::vector<std::size_t> next;
    for (std::size_t t : level) {
      const std::size_t c = b.children(t, 2, d);
      next.push_back(c);
      next.push_back(c + 1);
    }
    level = next;
  }
  return b.records;
}

/// Three iterations of random forests with random durations (deterministic).
std::vector<TraceRecord> random_trace(unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<TraceRecord> all;
  for (int it = 1; it <= 3; ++it) {
    TraceBuilder b(it);
    std::vector<std::size_t> open;
    const int roots = 1 + static_cast<int>(rng() % 20);
    for (int i = 0; i < roots; ++i) open.push_back(b.root(100 + rng() % 5000));
    while (!open.empty() && b.records.size() < 600) {
      const std::size_t t = open.back();
      open.pop_back();
      const int n = static_cast<int>(rng() % 5);  // 0..4 children: sometimes a leaf
      if (n == 0) continue;
      const std::size_t c = b.children(t, n, 0);
      for (int i = 0; i < n; ++i) {
        b.records[c + static_cast<std::size_t>(i)].duration_ns = 100 + rng() % 5000;
        open.push_back(c + static_cast<std::size_t>(i));
      }
    }
    all.insert(all.end(), b.records.begin(), b.records.end());
  }
  std::shuffle(all.begin(), all.end(), rng);  // files hold records in any order
  return all;
}

TEST(Simulate, ChainGivesNoSpeedup) {
  const TaskGraph g = build_task_graph(chain(50, 1000));
  EXPECT_EQ(g.iterations.at(0).critical_path_ns, 50000u);
  for (Policy policy : kAllPolicies)
    for (int p : {1, 2, 4, 8})
      EXPECT_DOUBLE_EQ(simulate(g, config(policy, p)).time_ns(), 50000.0)
          << policy_name(policy) << " at " << p << " procs";
}

TEST(Simulate, IndependentTasksTakeCeilNOverPRounds) {
  TraceBuilder b;
  const int n = 10;
  for (int i = 0; i < n; ++i) b.root(1000);
  const TaskGraph g = build_task_graph(b.records);
  for (Policy policy : kAllPolicies)
    for (int p = 1; p <= 12; ++p)
      EXPECT_DOUBLE_EQ(simulate(g, config(policy, p)).time_ns(), 1000.0 * ((n + p - 1) / p))
          << policy_name(policy) << " at " << p << " procs";
  // Blocks of 3: the n tasks form ceil(n/3) = 4 blocks of up to 3 rounds each.
  EXPECT_DOUBLE_EQ(simulate(g, config(Policy::kStack, 2, 3)).time_ns(), 6000.0);  // 3+3 | 3+1
  EXPECT_DOUBLE_EQ(simulate(g, config(Policy::kStack, 4, 3)).time_ns(), 3000.0);
}

TEST(Simulate, CentralLockCostCapsThroughput) {
  // n zero-duration tasks, the lock held c per take: at most one take per c ns, so
  // time >= n c whatever p; each processor's empty take before it loads the (one)
  // chunk of initial tasks or goes idle, and its final empty take, add at most 2 p c.
  TraceBuilder b;
  const int n = 1000;
  const double c = 100;
  for (int i = 0; i < n; ++i) b.root(0);
  const TaskGraph g = build_task_graph(b.records);
  CostModel costs;
  costs.take_op_ns = c;
  for (Policy policy : {Policy::kStack, Policy::kFifo, Policy::kBlocked}) {
    for (int p : {1, 2, 8, 64}) {
      const SimResult r = simulate(g, config(policy, p, 1, costs));
      EXPECT_GE(r.time_ns(), n * c) << policy_name(policy) << " at " << p;
      EXPECT_LE(r.time_ns(), (n + 2 * p) * c) << policy_name(policy) << " at " << p;
      if (p > 1) {
        EXPECT_GT(r.totals().lock_wait_ns, 0) << "contention must show as lock wait";
      }
    }
  }
  // Larger blocks amortise the lock: 1000 tasks in 100 takes of 10 at 1 processor,
  // after the empty take that makes it load them and before the final empty one.
  EXPECT_DOUBLE_EQ(simulate(g, config(Policy::kStack, 1, 10, costs)).time_ns(), (100 + 2) * c);
}

TEST(Simulate, EveryTaskRunsExactlyOnceAndTimeIsAccountedFor) {
  const std::vector<TraceRecord> records = random_trace(7);
  const TaskGraph g = build_task_graph(records);
  ASSERT_EQ(g.tasks(), records.size());
  for (Policy policy : kAllPolicies) {
    for (int p : {1, 3, 8}) {
      for (int block : {1, 4}) {
        SimConfig c = config(policy, p, block, default_costs(policy));
        c.costs.block_ns = 50;
        c.costs.task_ns = 7;
        c.keep_executions = true;
        const SimResult r = simulate(g, c);
        ASSERT_EQ(r.iterations.size(), 3u);
        for (std::size_t k = 0; k < 3; ++k) {
          const IterationResult& it = r.iterations[k];
          ASSERT_EQ(it.executions.size(), g.iterations[k].tasks.size());
          for (std::uint32_t e : it.executions)
            ASSERT_EQ(e, 1u) << policy_name(policy) << " p=" << p;
          const double sum = it.busy_ns + it.overhead_ns + it.lock_wait_ns + it.idle_ns;
          EXPECT_NEAR(sum, it.time_ns * p, 1e-6 * it.time_ns * p)
              << policy_name(policy) << " p=" << p;
          EXPECT_GE(it.time_ns * (1 + 1e-12),
                    static_cast<double>(g.iterations[k].critical_path_ns));
          EXPECT_GE(it.time_ns * p * (1 + 1e-12), static_cast<double>(g.iterations[k].work_ns));
        }
        EXPECT_EQ(r.totals().tasks, records.size());
        if (policy == Policy::kStealing && p > 1) {
          EXPECT_GT(r.totals().steals, 0u);
        }
      }
    }
  }
}

TEST(Simulate, OneProcessorWithFreeSchedulingTakesTheSummedDurations) {
  const TaskGraph g = build_task_graph(random_trace(11));
  for (Policy policy : kAllPolicies)
    for (int block : {1, 5})
      EXPECT_EQ(simulate(g, config(policy, 1, block)).time_ns(), static_cast<double>(g.work_ns()))
          << policy_name(policy);
  // The slowdown factor applies from 2 processors on only.
  CostModel slow;
  slow.slowdown = 2;
  EXPECT_EQ(simulate(g, config(Policy::kStack, 1, 1, slow)).time_ns(),
            static_cast<double>(g.work_ns()));
  EXPECT_DOUBLE_EQ(simulate(g, config(Policy::kStack, 2, 1, slow)).totals().busy_ns,
                   2.0 * static_cast<double>(g.work_ns()));
}

TEST(Simulate, TraceRoundTripKeepsTheGraph) {
  const std::vector<TraceRecord> records = random_trace(3);
  const fs::path path =
      fs::temp_directory_path() / ("hrad-simulate-test-" + std::to_string(::getpid()) + ".bin");
  write_trace(path, R"({"format":"hrad-trace","version":1})", records);
  std::string header;
  const std::vector<TraceRecord> back = read_trace(path, &header);
  fs::remove(path);
  EXPECT_EQ(header, R"({"format":"hrad-trace","version":1})");
  ASSERT_EQ(back.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    EXPECT_EQ(back[i].id, records[i].id);
    EXPECT_EQ(back[i].first_child, records[i].first_child);
    EXPECT_EQ(back[i].duration_ns, records[i].duration_ns);
    EXPECT_EQ(back[i].children, records[i].children);
    EXPECT_EQ(back[i].iteration, records[i].iteration);
  }
  const TaskGraph a = build_task_graph(records), b = build_task_graph(back);
  EXPECT_EQ(a.work_ns(), b.work_ns());
  for (std::size_t k = 0; k < a.iterations.size(); ++k)
    EXPECT_EQ(a.iterations[k].critical_path_ns, b.iterations[k].critical_path_ns);
}

TEST(Simulate, GraphOfABinaryTree) {
  const TaskGraph g = build_task_graph(binary_tree(6, 10));
  const IterationGraph& it = g.iterations.at(0);
  EXPECT_EQ(it.tasks.size(), 63u);
  EXPECT_EQ(it.roots, 1u);
  EXPECT_EQ(it.work_ns, 630u);
  EXPECT_EQ(it.critical_path_ns, 60u);
  for (std::size_t i = 0; i < it.tasks.size(); ++i)  // breadth-first: children follow parents
    if (it.tasks[i].children) {
      EXPECT_GT(it.tasks[i].first_child, i);
    }
}

TEST(Simulate, StealingScalesOnABalancedTree) {
  // 4095 tasks of 1 us, critical path 12 us: at p <= 16 the ideal time is within 5% of
  // work / p; stealing with the measured costs must reach 85% of p.
  const TaskGraph g = build_task_graph(binary_tree(12, 1000));
  const double t1 =
      simulate(g, config(Policy::kStealing, 1, 1, default_costs(Policy::kStealing))).time_ns();
  for (int p : {2, 4, 8, 16}) {
    const SimResult r =
        simulate(g, config(Policy::kStealing, p, 1, default_costs(Policy::kStealing)));
    EXPECT_GE(t1 / r.time_ns(), 0.85 * p) << p << " procs";
    EXPECT_LE(t1 / r.time_ns(), p * (1 + 1e-9)) << p << " procs";
    EXPECT_GT(r.totals().steals, 0u);
  }
}

TEST(Simulate, MedianBlockGap) {
  // One worker, blocks starting at 0, 1000, 2500: task ends at 400 and 1900.
  std::vector<TraceRecord> r(3);
  for (std::size_t i = 0; i < 3; ++i) {
    r[i].iteration = 1;
    r[i].duration_ns = 400 | TraceRecord::kBlockStart;
  }
  r[1].start_ns = 1000;
  r[2].start_ns = 2500;
  r[2].duration_ns = 400;  // not a block start: no gap counted before it
  EXPECT_DOUBLE_EQ(median_block_gap_ns(r), 600.0);
  const GapStats g = gap_stats(r);
  EXPECT_DOUBLE_EQ(g.block_mean, 600.0);
  EXPECT_DOUBLE_EQ(g.task_median, 1100.0);  // 2500 - (1000 + 400), inside the second block
  EXPECT_DOUBLE_EQ(g.task_mean, 1100.0);
}

TEST(Simulate, BadInputIsReported) {
  TraceBuilder b;
  const std::size_t t = b.root(5);
  b.children(t, 2, 5);
  std::vector<TraceRecord> missing = b.records;
  missing.pop_back();
  try {
    build_task_graph(missing, "x.bin");
    FAIL() << "a child missing from the trace must be an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("x.bin: iteration 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not in the trace"), std::string::npos) << e.what();
  }
  std::vector<TraceRecord> twice = b.records;
  twice.push_back(b.records.back());
  EXPECT_THROW(build_task_graph(twice), std::runtime_error);
  EXPECT_THROW(policy_from_name("lifo"), std::invalid_argument);
  EXPECT_THROW(simulate(build_task_graph(b.records), config(Policy::kStack, 0)),
               std::invalid_argument);

  const fs::path costs =
      fs::temp_directory_path() / ("hrad-costs-" + std::to_string(::getpid()) + ".json");
  std::ofstream(costs) << R"({"take_op_ns": 5, "tak_task_ns": 1})";
  CostModel c;
  EXPECT_THROW(load_costs(costs, c), std::runtime_error);
  std::ofstream(costs) << R"({"outside_serial_share": 1.5})";  // a share: 0..1
  EXPECT_THROW(load_costs(costs, c), std::runtime_error);
  std::ofstream(costs) << R"({"take_op_ns": 5, "slowdown": 1.5, "outside_serial_share": 0.25})";
  load_costs(costs, c);
  EXPECT_DOUBLE_EQ(c.outside_serial_share, 0.25);
  fs::remove(costs);
  EXPECT_EQ(c.take_op_ns, 5);
  EXPECT_EQ(c.slowdown, 1.5);
}

// Each registered scheduler is simulated or deliberately not (kNotModelled in
// cost_model.cpp, with why): a new scheduler fails here until someone decides which.
// Neither list may name a scheduler that is not registered.
TEST(Simulate, EveryRegisteredSchedulerIsModelledOrListedAsNot) {
  const std::vector<std::string> modelled = policy_names(), unmodelled = unmodelled_schedulers();
  const auto in = [](const std::vector<std::string>& v, const std::string& n) {
    return std::find(v.begin(), v.end(), n) != v.end();
  };
  const std::vector<std::string> registered = scheduler_names();
  for (const std::string& n : registered) {
    EXPECT_NE(in(modelled, n), in(unmodelled, n))
        << "scheduler '" << n << "': give it a simulated Policy or add it to kNotModelled "
        << "(experiments/sim/cost_model.cpp), not both";
  }
  for (const std::string& n : modelled) EXPECT_TRUE(in(registered, n)) << n << " is not registered";
  for (const std::string& n : unmodelled) {
    EXPECT_TRUE(in(registered, n)) << n << " is not registered";
    try {
      (void)policy_from_name(n);
      ADD_FAILURE() << n << " has no model but was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(
          std::string(e.what()).rfind("the simulator has no model of scheduler '" + n + "'", 0), 0u)
          << e.what();
    }
  }
}

// `hrad simulate` end to end: a table and a CSV marked "simulated"; bad input exits 1
// with a message and writes nothing.
TEST(Simulate, CommandLine) {
  const fs::path dir =
      fs::temp_directory_path() / ("hrad-simulate-cli-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_trace(
      dir / "t.bin",
      R"({"format":"hrad-trace","version":1,"threads":1,"scheduler":"blocked","block_size":2})",
      binary_tree(8, 2000));
  std::ofstream(dir / "junk.bin") << "hello\n";
  std::ofstream(dir / "zero.json") << R"({"take_op_ns": 0, "take_task_ns": 0, "submit_op_ns": 0,
      "copy_task_ns": 0, "start_ns": 0})";
  auto run = [&](const std::string& args) {
    const std::string cmd = "cd '" + dir.string() + "' && '" HRAD_BINARY "' simulate " + args +
                            " > out.txt 2> err.txt < /dev/null";
    const int rc = std::system(cmd.c_str());
    return (rc != -1 && WIFEXITED(rc)) ? WEXITSTATUS(rc) : -1;
  };
  auto text = [&](const char* name) {
    std::ifstream in(dir / name);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  ASSERT_EQ(run("t.bin --procs 1,2,4 --out sim.csv --quiet"), 0) << text("err.txt");
  const std::string csv = text("sim.csv");
  EXPECT_EQ(csv.rfind("kind,scheduler,block_size,procs,iteration,time_s,speedup", 0), 0u) << csv;
  EXPECT_NE(csv.find("simulated,blocked,2,4,all,"), std::string::npos) << csv;
  // The trace was recorded with 1 thread: its own span is the measured row at 1 proc.
  EXPECT_NE(csv.find("\nmeasured-trace,blocked,2,1,all,"), std::string::npos) << csv;
  EXPECT_EQ(csv.find("\nmeasured,"), std::string::npos) << "no --measured file was given";
  std::istringstream rows(csv);
  std::string row;
  std::getline(rows, row);
  int simulated = 0;
  while (std::getline(rows, row)) {
    EXPECT_TRUE(row.rfind("simulated,", 0) == 0 || row.rfind("measured-trace,", 0) == 0) << row;
    simulated += row.rfind("simulated,", 0) == 0;
  }
  EXPECT_EQ(simulated, 3 * 2) << "procs 1, 2, 4: one iteration and the total each";
  EXPECT_NE(text("out.txt").find("simulated"), std::string::npos);
  // Eight levels of 2 us tasks: the critical path in the unit that shows it (it was
  // printed as "0.000 s").
  EXPECT_NE(text("out.txt").find("critical path 16.000 us"), std::string::npos) << text("out.txt");

  // Cutting every 2000 ns task to 1000 ns halves the 1-processor time (zero costs).
  ASSERT_EQ(
      run("t.bin --procs 1 --max-task-ns 1000 --costs zero.json --overheads typical --block-ns 0 "
          "--quiet --out cut.csv"),
      0)
      << text("err.txt");
  EXPECT_NE(text("out.txt").find("cut 255 task(s) by 0.000255 s in all"), std::string::npos)
      << text("out.txt");
  EXPECT_NE(text("cut.csv").find("simulated,blocked,2,1,all,0.000255,"), std::string::npos)
      << text("cut.csv");

  // --stage-stats: the traced run's time outside the task loop (1 thread, one iteration
  // here: 0.001 + 0.0005 + 0.0002 + 0.0003 s) is added to the 1-processor prediction.
  std::ofstream(dir / "stage.json") << R"({"config": {"threads": 1}, "iterations": [
      {"load_s": 0.001, "link_compact_s": 0.0005, "stage_start_s": 0.0002, "stage_end_s": 0.0003}]})";
  ASSERT_EQ(run("t.bin --procs 1 --costs zero.json --block-ns 0 --stage-stats stage.json --quiet "
                "--out stage.csv"),
            0)
      << text("err.txt");
  EXPECT_NE(text("stage.csv").find("simulated,blocked,2,1,all,0.00251,"), std::string::npos)
      << text("stage.csv");
  std::ofstream(dir / "two.json") << R"({"config": {"threads": 2}, "iterations": []})";
  EXPECT_EQ(run("t.bin --stage-stats two.json --out bad.csv"), 1);
  EXPECT_NE(text("err.txt").find("a 1-thread run"), std::string::npos) << text("err.txt");
  std::ofstream(dir / "old.json") << R"({"config": {"threads": 1}, "iterations": [{"load_s": 1}]})";
  EXPECT_EQ(run("t.bin --stage-stats old.json --out bad.csv"), 1);
  EXPECT_NE(text("err.txt").find("old.json: not an hrad stats.json with the stage's costs"),
            std::string::npos)
      << text("err.txt");

  EXPECT_EQ(run("junk.bin --out bad.csv"), 1);
  EXPECT_NE(text("err.txt").find("junk.bin: not an hrad trace"), std::string::npos)
      << text("err.txt");
  EXPECT_EQ(run("t.bin --scheduler lifo --out bad.csv"), 1);
  EXPECT_NE(text("err.txt").find("unknown scheduler 'lifo'"), std::string::npos) << text("err.txt");
  // A registered scheduler without a model, asked for or the trace's own, is named as such.
  EXPECT_EQ(run("t.bin --scheduler locality --out bad.csv"), 1);
  EXPECT_NE(text("err.txt").find("no model of scheduler 'locality'"), std::string::npos)
      << text("err.txt");
  write_trace(
      dir / "locality.bin",
      R"({"format":"hrad-trace","version":1,"threads":1,"scheduler":"locality","block_size":2})",
      binary_tree(8, 2000));
  EXPECT_EQ(run("locality.bin --out bad.csv"), 1);
  EXPECT_NE(
      text("err.txt").find("locality.bin (the trace's scheduler): the simulator has no model of "
                           "scheduler 'locality'"),
      std::string::npos)
      << text("err.txt");
  EXPECT_EQ(run("t.bin --procs 1,x,4 --out bad.csv"), 1);
  EXPECT_NE(text("err.txt").find("--procs: 'x'"), std::string::npos) << text("err.txt");
  EXPECT_EQ(run("t.bin --procs 0 --out bad.csv"), 1);
  EXPECT_FALSE(fs::exists(dir / "bad.csv"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hrad::sim
