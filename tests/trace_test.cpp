#include "core/parallel/trace.h"
#include "core/scene/builtin_scenes.h"
#include "core/solver/solver.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unordered_map>
#include <unordered_set>

namespace hrad {
namespace {

// A trace must describe the refinement exactly: one record per task, unique ids,
// every created task recorded once as the child of the task that created it, the
// initial tasks of each iteration being the previous iteration's links, and one
// block start per scheduler take.
TEST(Trace, RecordsEveryTaskAndItsChildrenExactlyOnce) {
  const auto path = std::filesystem::temp_directory_path() / "hrad-trace-test.bin";
  const Scene scene = make_builtin("builtin:cornell");
  SolverOptions o;
  o.threads = 2;
  o.scheduler = "blocked";
  o.block_size = 10;
  o.iterations = 3;
  o.eps = 1e-3;
  o.trace = path.string();
  Solver s(scene, o);
  const RunStats st = s.run();
  std::string header;
  const std::vector<TraceRecord> records = read_trace(path, &header);
  std::filesystem::remove(path);
  EXPECT_NE(header.find("\"records\":" + std::to_string(records.size())), std::string::npos);

  std::uint64_t tasks = 0, takes = 0;
  for (const IterationStats& it : st.iterations) {
    tasks += it.tasks;
    for (const RefinerStats& r : it.refiners) takes += r.takes;
  }
  ASSERT_EQ(records.size(), tasks);

  std::unordered_map<std::uint64_t, const TraceRecord*> by_id;
  std::vector<std::uint64_t> initial(o.iterations + 1, 0);
  std::uint64_t block_starts = 0;
  for (const TraceRecord& r : records) {
    ASSERT_TRUE(by_id.emplace(r.id, &r).second) << "duplicate id " << r.id;
    if ((r.id >> 48) == 0) {
      ASSERT_EQ(r.id >> 40, r.iteration) << "initial task ids carry their iteration";
      ++initial[r.iteration];
    } else {
      ASSERT_EQ((r.id >> 40) & 0xFF, r.iteration) << "created task ids carry their iteration";
    }
    if (r.duration_ns & TraceRecord::kBlockStart) ++block_starts;
  }
  EXPECT_EQ(block_starts, takes);
  EXPECT_EQ(initial[1], 1u) << "iteration 1 starts from the root-root link";
  for (int it = 2; it <= o.iterations; ++it)
    EXPECT_EQ(initial[static_cast<std::size_t>(it)],
              st.iterations[static_cast<std::size_t>(it - 2)].links);

  std::unordered_set<std::uint64_t> children;
  for (const TraceRecord& r : records) {
    for (std::uint64_t c = r.first_child; c < r.first_child + r.children; ++c) {
      ASSERT_TRUE(children.insert(c).second) << "task created twice";
      const auto found = by_id.find(c);
      ASSERT_NE(found, by_id.end()) << "a created task was never executed";
      EXPECT_EQ(found->second->iteration, r.iteration);
    }
  }
  for (const TraceRecord& r : records) {
    if ((r.id >> 48) != 0) {
      EXPECT_TRUE(children.count(r.id)) << "orphan task " << r.id;
    }
  }
}

TEST(Trace, RejectsFilesThatAreNotTraces) {
  const auto path = std::filesystem::temp_directory_path() / "hrad-not-a-trace.bin";
  { std::ofstream(path) << "hello\n"; }
  EXPECT_THROW(read_trace(path, nullptr), std::runtime_error);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace hrad
