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

// A header that does not describe its body (another run's, or edited) was accepted.
TEST(Trace, TheHeaderMustDescribeItsBody) {
  const auto path = std::filesystem::temp_directory_path() / "hrad-header-test.trace";
  std::vector<TraceRecord> records(3);
  records[2].worker = 1;
  const auto fails = [&](const std::string& header, const std::string& what) {
    write_trace(path, header, records);
    try {
      (void)read_trace(path, nullptr);
      ADD_FAILURE() << header << ": accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const std::string good =
      R"({"format":"hrad-trace","version":1,"record_bytes":32,"records":3,"threads":2})";
  write_trace(path, good, records);
  EXPECT_EQ(read_trace(path, nullptr).size(), 3u);
  fails(R"({"format":"hrad-trace","version":1,"records":3,"threads":1})",
        "record 2 ran on refiner 1, but the run had 1 thread");
  fails(R"({"format":"hrad-trace","version":1,"records":4})",
        "it says 4 records, the body holds 3");
  fails(R"({"format":"hrad-trace","version":1,"record_bytes":16})", "records of 16 bytes");
  fails(R"({"format":"hrad-trace","version":2})", "version 2");
  std::filesystem::remove(path);
}

TEST(Trace, RejectsFilesThatAreNotTraces) {
  const auto path = std::filesystem::temp_directory_path() / "hrad-not-a-trace.bin";
  { std::ofstream(path) << "hello\n"; }
  EXPECT_THROW(read_trace(path, nullptr), std::runtime_error);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace hrad
