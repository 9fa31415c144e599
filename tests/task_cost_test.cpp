// The experiment summary's per-task cost warning (experiments/harness/task_cost.h).
#include "experiments/harness/task_cost.h"

#include <gtest/gtest.h>

namespace hrad::experiment {
namespace {

SolverOptions with(int threads, int block = 10, const char* scheduler = "blocked") {
  SolverOptions o;
  o.threads = threads;
  o.block_size = block;
  o.scheduler = scheduler;
  return o;
}

TEST(TaskCost, WarnsWhenTheMedianAtPThreadsExceedsTheRatio) {
  TaskCostTable t;
  for (double ns : {100.0, 104.0, 96.0}) t.add("builtin:office", with(1), ns);
  for (double ns : {130.0, 125.0, 200.0}) t.add("builtin:office", with(2), ns);  // median 130
  for (double ns : {110.0, 115.0}) t.add("builtin:office", with(4), ns);         // 1.125x: quiet
  const std::vector<std::string> w = t.warnings(1.2);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("builtin:office"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("at 2 threads is 1.30x"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("blocked block 10"), std::string::npos) << w[0];
  EXPECT_TRUE(t.warnings(1.31).empty());
}

TEST(TaskCost, ComparesOnlyRunsThatDifferInThreadsAlone) {
  TaskCostTable t;
  t.add("builtin:office", with(1, 10), 100);
  t.add("builtin:office", with(2, 100), 500);             // other block size: no 1-thread run
  t.add("builtin:lab", with(2, 10), 500);                 // other scene: no 1-thread run
  t.add("builtin:office", with(2, 10, "stealing"), 500);  // other scheduler
  t.add("builtin:office", with(2, 10), 0);                // no tasks: ignored
  EXPECT_TRUE(t.warnings(1.2).empty());
  t.add("builtin:lab", with(1, 10), 100);
  EXPECT_EQ(t.warnings(1.2).size(), 1u);
}

}  // namespace
}  // namespace hrad::experiment
