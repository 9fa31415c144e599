// core/base/hash.h: splitmix64 gives the reference generator's outputs (Vigna's splitmix64.c
// from state 0), so every random stream built on it stays what it was.
#include "core/base/hash.h"

#include <gtest/gtest.h>

namespace hrad {
namespace {

TEST(Hash, Splitmix64MatchesTheReferenceGenerator) {
  std::uint64_t state = 0;
  EXPECT_EQ(splitmix64(state), 0xE220A8397B1DCDAFull);
  EXPECT_EQ(splitmix64(state), 0x6E789E6AA1B965F4ull);
  EXPECT_EQ(splitmix64(state), 0x06C45D188009454Full);
  EXPECT_EQ(state, 3 * 0x9E3779B97F4A7C15ull);
}

TEST(Hash, Splitmix64MixIsTheGeneratorsFinaliser) {
  static_assert(splitmix64_mix(0) == 0);
  EXPECT_EQ(splitmix64_mix(0x9E3779B97F4A7C15ull), 0xE220A8397B1DCDAFull);
  EXPECT_EQ(splitmix64_mix(1), 0x5692161D100B05E5ull);
}

}  // namespace
}  // namespace hrad
