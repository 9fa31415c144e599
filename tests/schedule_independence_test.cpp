// The link set after refinement depends only on the oracle (radiosities are frozen
// while refining), so every scheduler at every thread count must produce exactly
// the links and elements of the sequential run, and the same radiosity up to
// summation order.
#include "core/scene/builtin_scenes.h"
#include "core/solver/solver.h"
#include "schedulers/scheduler.h"

#include <gtest/gtest.h>

namespace hrad {
namespace {

struct Reference {
  std::vector<std::pair<std::uint64_t, std::uint64_t>> links;
  std::vector<Solver::Leaf> leaves;
};

Reference solve(const Scene& scene, const std::string& scheduler, int threads, int block) {
  SolverOptions o;
  o.scheduler = scheduler;
  o.threads = threads;
  o.block_size = block;
  o.eps = 3e-4;
  o.iterations = 3;
  Solver s(scene, o);
  s.run();
  return {s.link_ids(), s.leaves()};
}

TEST(ScheduleIndependence, EverySchedulerAndThreadCountGivesTheSequentialLinks) {
  const Scene scene = make_builtin("builtin:cornell");
  const Reference ref = solve(scene, "stack", 1, 1);
  ASSERT_GT(ref.links.size(), 1000u);
  for (const std::string& name : scheduler_names()) {
    for (int threads : {1, 2, 4}) {
      for (int block : {1, 10}) {
        const Reference got = solve(scene, name, threads, block);
        const std::string what =
            name + " threads=" + std::to_string(threads) + " block=" + std::to_string(block);
        ASSERT_EQ(got.links.size(), ref.links.size()) << what;
        EXPECT_TRUE(got.links == ref.links) << what;
        ASSERT_EQ(got.leaves.size(), ref.leaves.size()) << what;
        for (std::size_t i = 0; i < ref.leaves.size(); ++i) {
          ASSERT_EQ(got.leaves[i].id, ref.leaves[i].id) << what;
          const Rgb& a = ref.leaves[i].radiosity;
          const Rgb& b = got.leaves[i].radiosity;
          ASSERT_LE((a - b).abs().maxCoeff(), 1e-6 * std::max(1e-12, a.abs().maxCoeff())) << what;
        }
      }
    }
  }
}

TEST(ScheduleIndependence, RefinersRunConcurrently) {
  // Peak parallelism above 1 at 2 threads shows the refiners really overlapped.
  const Scene scene = make_builtin("builtin:office");
  SolverOptions o;
  o.threads = 2;
  o.block_size = 10;
  o.iterations = 1;
  o.eps = 1e-3;
  int best = 0;
  for (int attempt = 0; attempt < 3 && best < 2; ++attempt) {
    Solver s(scene, o);
    const RunStats st = s.run();
    const IterationStats& it = st.iterations.front();
    best = std::max(best, it.peak_parallelism);
    // The per-refiner figures add up to the iteration's.
    ASSERT_EQ(it.refiners.size(), 2u);
    std::uint64_t tasks = 0, rays = 0;
    for (const RefinerStats& r : it.refiners) {
      tasks += r.tasks;
      rays += r.rays_cast;
    }
    EXPECT_EQ(tasks, it.tasks);
    EXPECT_LE(rays, it.rays_cast);  // the iteration also counts row-sum rays
  }
  EXPECT_EQ(best, 2);
}

}  // namespace
}  // namespace hrad
