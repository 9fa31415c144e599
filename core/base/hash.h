// splitmix64 (Steele, Lea & Flood 2014; Vigna's constants): its finaliser, a cheap
// 64-bit mix whose every output bit depends on every input bit, used to hash ids and
// keys into random streams; and its generator step, which feeds the finaliser a
// state advanced by the golden-ratio increment.
#pragma once

#include <cstdint>

namespace hrad {

/// The splitmix64 finaliser: a bijection of 64-bit words.
constexpr std::uint64_t splitmix64_mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// One step of the splitmix64 generator: advances `state` and returns the next output.
constexpr std::uint64_t splitmix64(std::uint64_t& state) {
  return splitmix64_mix(state += 0x9E3779B97F4A7C15ull);
}

/// Counter-based random numbers: the i-th uniform double in [0,1) of stream `key`.
inline double hashed_uniform(std::uint64_t key, std::uint64_t i) {
  const std::uint64_t z = splitmix64_mix(key + 0x9E3779B97F4A7C15ull * (i + 1));
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

}  // namespace hrad
