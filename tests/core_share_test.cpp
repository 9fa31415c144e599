// How worker ranks on one host split its CPUs (experiments/harness/core_share.h).
#include "experiments/harness/core_share.h"
#include "core/parallel/pin_plan.h"

#include <gtest/gtest.h>

#include <set>

namespace hrad::experiment {
namespace {

TEST(CoreShare, SlicesAreDisjointContiguousAndCoverEveryCpu) {
  const std::vector<int> cpus = {0, 1, 2, 3, 4, 5, 6};
  for (int m = 1; m <= 7; ++m) {
    std::set<int> seen;
    for (int k = 0; k < m; ++k) {
      const auto s = cpu_slice(cpus, k, m);
      EXPECT_GE(s.size(), 7u / m) << k << "/" << m;
      EXPECT_LE(s.size(), 7u / m + 1) << k << "/" << m;
      for (int c : s) EXPECT_TRUE(seen.insert(c).second) << c << " twice, m=" << m;
    }
    EXPECT_EQ(seen.size(), cpus.size()) << m;
  }
  EXPECT_EQ(cpu_slice({4, 5, 8, 9}, 1, 2), (std::vector<int>{8, 9}));
}

TEST(CoreShare, RejectsMoreSlicesThanCpusAndBadIndices) {
  EXPECT_THROW((void)cpu_slice({0, 1}, 0, 3), std::invalid_argument);
  EXPECT_THROW((void)cpu_slice({0, 1}, 2, 2), std::invalid_argument);
  EXPECT_THROW((void)cpu_slice({0, 1}, -1, 2), std::invalid_argument);
  EXPECT_THROW((void)cpu_slice({0, 1}, 0, 0), std::invalid_argument);
}

TEST(CoreShare, FormatsRanges) {
  EXPECT_EQ(format_pu_list({0, 1, 2, 3, 8, 10, 11}), "0-3,8,10-11");
  EXPECT_EQ(format_pu_list({5}), "5");
  EXPECT_EQ(format_pu_list({}), "");
}

TEST(CoreShare, ThisProcessHasCpusAndCanBindToThemAll) {
  const auto cpus = allowed_cpus();
  ASSERT_FALSE(cpus.empty());
  EXPECT_NO_THROW(bind_to_cpus(cpus));
  EXPECT_EQ(allowed_cpus(), cpus);
}

}  // namespace
}  // namespace hrad::experiment
