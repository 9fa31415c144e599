#include "core/scene/polygon_key.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <functional>

namespace hrad {

namespace {

std::size_t mix(std::size_t h, double x) {
  const double y = x == 0 ? 0.0 : x;  // -0 and +0 are the same position
  std::uint64_t bits = 0;
  std::memcpy(&bits, &y, sizeof bits);
  return h ^ (std::hash<std::uint64_t>{}(bits) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2));
}

// The i-th vertex of the cycle read from `start`, forwards or backwards.
const Vec3& at(std::span<const Vec3> p, std::size_t start, std::size_t i, bool reversed) {
  const std::size_t k = p.size();
  return p[reversed ? (start + k - i) % k : (start + i) % k];
}

}  // namespace

std::size_t cycle_start(std::span<const Vec3> p) {
  std::size_t first = 0;
  for (std::size_t i = 1; i < p.size(); ++i)
    if (std::lexicographical_compare(p[i].data(), p[i].data() + 3, p[first].data(),
                                     p[first].data() + 3))
      first = i;
  return first;
}

std::vector<double> cycle_key(std::span<const Vec3> p, bool reversed) {
  const std::size_t s = cycle_start(p);
  std::vector<double> key;
  key.reserve(3 * p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& x = at(p, s, i, reversed);
    key.insert(key.end(), {x.x(), x.y(), x.z()});
  }
  return key;
}

std::size_t cycle_hash(std::span<const Vec3> p, bool reversed) {
  const std::size_t s = cycle_start(p);
  std::size_t h = 3 * p.size();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& x = at(p, s, i, reversed);
    h = mix(mix(mix(h, x.x()), x.y()), x.z());
  }
  return h;
}

bool same_cycle(std::span<const Vec3> a, std::span<const Vec3> b, bool reversed) {
  if (a.size() != b.size() || a.empty()) return false;
  const std::size_t sa = cycle_start(a), sb = cycle_start(b);
  for (std::size_t i = 0; i < a.size(); ++i)
    if (at(a, sa, i, reversed) != at(b, sb, i, false)) return false;
  return true;
}

std::size_t PositionsHash::operator()(const std::vector<double>& v) const noexcept {
  std::size_t h = v.size();
  for (double x : v) h = mix(h, x);
  return h;
}

}  // namespace hrad
