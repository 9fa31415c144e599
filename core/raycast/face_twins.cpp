#include "core/raycast/face_twins.h"

#include "core/base/interrupt.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/polygon_key.h"
#include "core/scene/scene.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace hrad {

std::vector<std::uint32_t> find_twins(std::span<const Vec3> vertices,
                                      std::span<const std::uint32_t> indices,
                                      std::span<const PolygonRange> polygons) {
  const std::size_t n = polygons.size();
  std::vector<std::uint32_t> twin(n, kNoTwin);
  auto corners = [&](std::size_t i, std::vector<Vec3>& out) {
    out.clear();
    for (std::uint32_t k = 0; k < polygons[i].count; ++k)
      out.push_back(vertices[indices[polygons[i].first + k]]);
  };
  // Forward hashes, sorted with their polygons (16 bytes a polygon; a hash multimap's nodes and
  // buckets took about 40, gigabytes on large scenes before any memory limit applied); then each
  // polygon looks up its reversed cycle, candidates in polygon order.
  std::vector<std::pair<std::size_t, std::uint32_t>> by_hash(n);
  std::vector<Vec3> p, q;
  for (std::size_t i = 0; i < n; ++i) {
    poll_interrupt(i);
    corners(i, p);
    by_hash[i] = {cycle_hash(p), static_cast<std::uint32_t>(i)};
  }
  std::sort(by_hash.begin(), by_hash.end());
  throw_if_interrupted();  // (the sort cannot stop midway)
  for (std::size_t i = 0; i < n; ++i) {
    poll_interrupt(i);
    if (twin[i] != kNoTwin) continue;
    corners(i, p);
    const std::size_t h = cycle_hash(p, /*reversed=*/true);
    for (auto it = std::lower_bound(by_hash.begin(), by_hash.end(), std::make_pair(h, 0u));
         it != by_hash.end() && it->first == h; ++it) {
      const std::uint32_t j = it->second;
      if (j == i || twin[j] != kNoTwin) continue;
      corners(j, q);
      if (!same_cycle(p, q, /*reversed=*/true)) continue;
      twin[i] = j;
      twin[j] = static_cast<std::uint32_t>(i);
      break;
    }
  }
  return twin;
}

std::vector<std::uint32_t> find_twins(const Scene& scene) {
  std::vector<PolygonRange> polys;
  polys.reserve(scene.faces.size());
  for (const Face& f : scene.faces) polys.push_back({f.first, f.count});
  return find_twins(scene.vertices, scene.indices, polys);
}

}  // namespace hrad
