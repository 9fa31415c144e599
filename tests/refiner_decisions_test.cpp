// What a link keeps of the decision that accepted it (core/hierarchy/link_list.h,
// core/solver/refiner.cpp): with independent estimates, a link whose acceptance rested
// on its visibility holds the visibility it was decided on (the transport's draw 0, from
// the decision's rays) beside its own (draw 1). A later stage judges it again on the
// first without casting those rays again.
#include "core/hierarchy/hierarchy.h"
#include "core/parallel/lock_pool.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/builtin_scenes.h"
#include "core/solver/refiner.h"
#include "core/transport/transport.h"
#include "oracles/oracle.h"
#include "schedulers/scheduler.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace hrad {
namespace {

// The cluttered furnace refined once from its root link at eps 1e-3 with independent
// estimates and 16 decision rays; then the same stage again on its own links, nothing
// changed: every link is kept, none is made, and not one ray is cast (before links kept
// the decision's visibility, each such link cast its 16 + 4 rays again). The stored
// values are the transport's draws to within their 16-bit steps.
TEST(RefinerDecisions, ReloadedLinksAreJudgedOnTheVisibilityTheyWereDecidedOn) {
  const Scene scene = make_builtin("builtin:furnace?objects=2&rho=0.5");
  const RayScene rays = RayScene::from_scene(scene);
  Hierarchy h(scene, 1);
  const Transport transport(h, rays, 4, 1);
  const auto oracle = make_oracle("bf");
  LockPool element_locks(8, 1), link_locks(8, 1);
  RefineLimits limits{1e-3 * scene.max_channel_emitted_power(), 1e-3 * scene.total_area()};
  limits.independent_estimates = true;
  limits.decision_visibility_rays = 16;
  Refiner refiner(h, transport, *oracle, limits, element_locks, link_locks);
  const auto scheduler = make_scheduler("stack", SchedulerConfig{1, 1});
  std::vector<Task> tasks{Task{&h.root(), &h.root()}};
  const RefineCounters first = refiner.run(*scheduler, tasks, 1, 1);
  ASSERT_GT(first.links_created, 1000u);

  std::uint64_t decided = 0;
  for (const Element* e : h.elements())
    for (const Link& l : e->links) {
      if (!l.has_decided()) continue;
      ++decided;
      std::uint64_t cast = 0, skipped = 0;
      const double at_decision = transport.visibility(*e, *l.source, cast, skipped, 0, 16);
      const double own = transport.visibility(*e, *l.source, cast, skipped, 1);
      EXPECT_NEAR(l.decided(), at_decision, 1e-4);
      EXPECT_NEAR(l.visibility(), own, 1e-4);
    }
  EXPECT_GT(decided, 50u);  // 82 here

  TaskList again;
  Refiner::reload_links(h, h.elements(), 1, again);
  const RefineCounters second = refiner.run(*scheduler, again, 1, 1);
  EXPECT_EQ(second.links_kept, first.links_created);
  EXPECT_EQ(second.links_created, 0u);
  EXPECT_EQ(second.rays_cast, 0u);
}

}  // namespace
}  // namespace hrad
