// Progress during a refinement stage (Refiner::set_progress) and through a whole run
// (the Solver's ProgressFn): the line must move while a stage runs, not only between
// stages.
#include "core/base/progress.h"
#include "core/hierarchy/hierarchy.h"
#include "core/parallel/lock_pool.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/builtin_scenes.h"
#include "core/solver/refiner.h"
#include "core/solver/solver.h"
#include "core/transport/transport.h"
#include "oracles/oracle.h"
#include "schedulers/scheduler.h"

#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <vector>

namespace hrad {
namespace {

TEST(Progress, FormatCount) {
  EXPECT_EQ(ProgressReporter::format_count(0), "0");
  EXPECT_EQ(ProgressReporter::format_count(999), "999");
  EXPECT_EQ(ProgressReporter::format_count(1000), "1.00k");
  EXPECT_EQ(ProgressReporter::format_count(12345), "12.3k");
  EXPECT_EQ(ProgressReporter::format_count(310000), "310k");
  EXPECT_EQ(ProgressReporter::format_count(999400), "999k");
  EXPECT_EQ(ProgressReporter::format_count(999950), "1.00M");  // not "1000k"
  EXPECT_EQ(ProgressReporter::format_count(1234567), "1.23M");
  EXPECT_EQ(ProgressReporter::format_count(4560000000ULL), "4.56G");
  for (std::uint64_t n = 1; n < (1ULL << 62); n = n * 3 + 7)
    EXPECT_LE(ProgressReporter::format_count(n).size(), 5u) << n;
}

// One refinement stage of the office from its root link, on 1 and 2 threads, with a
// progress interval of 1 ms: the callback runs during the stage (never after run()
// returns), its task and link counts never fall and stay within the stage's totals.
TEST(RefinerProgress, ReportsDuringTheStageAndStopsWithIt) {
  const Scene scene = make_builtin("builtin:office");
  const RayScene rays = RayScene::from_scene(scene);
  const double power = scene.max_channel_emitted_power();
  for (int threads : {1, 2}) {
    Hierarchy h(scene, threads);
    const Transport transport(h, rays, 4, 1);
    const auto oracle = make_oracle("bf");
    LockPool element_locks(8, threads), link_locks(8, threads);
    Refiner refiner(h, transport, *oracle, RefineLimits{1e-4 * power, 0}, element_locks,
                    link_locks);
    std::vector<RefineProgress> seen;
    std::atomic<bool> running{false};
    std::atomic<int> outside{0};
    refiner.set_progress(
        [&](const RefineProgress& p) {
          if (!running.load()) ++outside;
          seen.push_back(p);
        },
        1);
    auto scheduler = make_scheduler("blocked", SchedulerConfig{threads, 10});
    std::vector<Task> tasks{Task{&h.root(), &h.root()}};
    running = true;
    const RefineCounters c = refiner.run(*scheduler, tasks, threads, 10);
    running = false;
    ASSERT_GT(c.tasks, 100000u) << "the stage must be long enough to report on";
    ASSERT_GE(seen.size(), 3u) << "threads " << threads;
    EXPECT_EQ(outside.load(), 0);
    for (std::size_t i = 1; i < seen.size(); ++i) {
      EXPECT_GE(seen[i].tasks, seen[i - 1].tasks);
      EXPECT_GE(seen[i].links, seen[i - 1].links);
      EXPECT_GE(seen[i].elapsed_s, seen[i - 1].elapsed_s);
    }
    EXPECT_LE(seen.back().tasks, c.tasks);
    EXPECT_LE(seen.back().links, c.links_created + c.links_kept);
    // Some report saw the stage under way: tasks done and tasks still to come.
    bool midway = false;
    for (const RefineProgress& p : seen) midway |= p.tasks > 0 && p.pending > 0;
    EXPECT_TRUE(midway);
  }
}

// Without set_progress nothing is reported and the stage is the same.
TEST(RefinerProgress, SameLinksWithAndWithoutProgress) {
  const Scene scene = make_builtin("builtin:cornell");
  const RayScene rays = RayScene::from_scene(scene);
  const double power = scene.max_channel_emitted_power();
  std::uint64_t links[2] = {0, 0}, counted[2] = {0, 0};
  for (int with : {0, 1}) {
    Hierarchy h(scene, 2);
    const Transport transport(h, rays, 4, 1);
    const auto oracle = make_oracle("bf");
    LockPool element_locks(8, 2), link_locks(8, 2);
    Refiner refiner(h, transport, *oracle, RefineLimits{1e-4 * power, 0}, element_locks,
                    link_locks);
    if (with) refiner.set_progress([](const RefineProgress&) {}, 1);
    auto scheduler = make_scheduler("stealing", SchedulerConfig{2, 4});
    std::vector<Task> tasks{Task{&h.root(), &h.root()}};
    const RefineCounters c = refiner.run(*scheduler, tasks, 2, 4);
    links[with] = c.links_created;
    counted[with] = c.tasks;
  }
  EXPECT_EQ(links[0], links[1]);
  EXPECT_EQ(counted[0], counted[1]);
}

// Through the Solver: the phases name the stage's tasks and links and the
// propagation's sweeps, and the share done never leaves [0, 1].
TEST(SolverProgress, PhasesNameTasksLinksAndSweeps) {
  const Scene scene = make_builtin("builtin:cornell");
  SolverOptions o;
  o.iterations = 2;
  std::vector<std::string> phases;
  std::vector<double> shares;
  Solver solver(scene, o, [&](const std::string& phase, double share) {
    phases.push_back(phase);
    shares.push_back(share);
  });
  (void)solver.run();
  bool sweep = false, refine = false, open = false;
  for (const std::string& p : phases) {
    sweep |= p.find("iteration 2/2: propagate, sweep ") != std::string::npos;
    refine |= p == "iteration 1/2: refine";
    open |= p == "iteration 2/2: open fractions";
  }
  EXPECT_TRUE(sweep);
  EXPECT_TRUE(refine);
  EXPECT_TRUE(open);
  for (double s : shares) {
    EXPECT_GE(s, 0.0);
    EXPECT_LE(s, 1.0);
  }
  EXPECT_EQ(phases.back(), "done");
}

}  // namespace
}  // namespace hrad
