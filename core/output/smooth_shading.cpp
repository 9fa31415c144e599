#include "core/output/smooth_shading.h"

#include "core/output/smoothing_groups.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace hrad {

namespace {

/// Points within a quantum of each other (on a grid of that spacing) as one id.
class PointIndex {
 public:
  explicit PointIndex(double quantum) : inv_(1.0 / quantum) {}

  std::uint32_t insert(const Vec3& p) {
    auto [it, fresh] = ids_.try_emplace(key(p), static_cast<std::uint32_t>(points_.size()));
    if (fresh) points_.push_back(p);
    return it->second;
  }
  [[nodiscard]] std::optional<std::uint32_t> find(const Vec3& p) const {
    const auto it = ids_.find(key(p));
    if (it == ids_.end()) return std::nullopt;
    return it->second;
  }
  [[nodiscard]] const Vec3& point(std::uint32_t id) const { return points_[id]; }
  [[nodiscard]] std::size_t size() const { return points_.size(); }

 private:
  struct Key {
    std::int64_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0x243F6A8885A308D3ull;
      for (std::int64_t v : {k.x, k.y, k.z}) {
        h ^= static_cast<std::uint64_t>(v) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        h *= 0xBF58476D1CE4E5B9ull;
      }
      return static_cast<std::size_t>(h ^ (h >> 31));
    }
  };
  [[nodiscard]] Key key(const Vec3& p) const {
    // Clamped so that a point far beyond the scale cannot overflow the integer.
    const auto q = [&](double x) {
      return static_cast<std::int64_t>(std::clamp(std::round(x * inv_), -4e18, 4e18));
    };
    return {q(p.x()), q(p.y()), q(p.z())};
  }

  double inv_;
  std::unordered_map<Key, std::uint32_t, KeyHash> ids_;
  std::vector<Vec3> points_;
};

/// Appends to `out`, in order from a to b, the ids of the points strictly inside the
/// segment found by probing midpoints recursively (the midpoint computed as the
/// hierarchy computes a child's corner, 0.5 * (a + b)).
void hanging_points(const PointIndex& index, const Vec3& a, const Vec3& b, double min_length,
                    int depth, std::vector<std::uint32_t>& out) {
  if (depth == 0 || !((b - a).norm() > min_length)) return;
  const Vec3 m = 0.5 * (a + b);
  const auto id = index.find(m);
  if (!id) return;
  hanging_points(index, a, m, min_length, depth - 1, out);
  out.push_back(*id);
  hanging_points(index, m, b, min_length, depth - 1, out);
}

RenderMesh flat_mesh(std::span<const ShadingPatch> patches) {
  RenderMesh mesh;
  for (const ShadingPatch& p : patches) {
    const auto first = static_cast<std::uint32_t>(mesh.positions.size());
    for (const Vec3& c : p.corners) {
      mesh.positions.push_back(c);
      mesh.radiosity.push_back(p.radiosity);
      mesh.reflectance.push_back(p.reflectance);
    }
    const auto k = static_cast<std::uint32_t>(p.corners.size());
    if (k <= 4) {
      mesh.polys.push_back(
          {first, first + 1, first + 2, k == 4 ? first + 3 : RenderMesh::kNoVertex});
    } else {
      for (std::uint32_t i = 1; i + 1 < k; ++i)
        mesh.polys.push_back({first, first + i, first + i + 1, RenderMesh::kNoVertex});
    }
  }
  return mesh;
}

// Each patch's boundary loop: its corners with the hanging points between them, as
// point ids of `index`, loop after loop.
struct Loops {
  std::vector<std::uint32_t> point;
  std::vector<std::uint8_t> is_corner;
  std::vector<std::size_t> begin{0};  // patch i: entries begin[i] .. begin[i + 1]
  std::vector<std::uint32_t> patch;   // per entry: its patch
};

Loops boundary_loops(std::span<const ShadingPatch> patches, const PointIndex& index,
                     double tolerance) {
  Loops l;
  std::vector<std::uint32_t> between;
  for (const ShadingPatch& p : patches) {
    const std::size_t k = p.corners.size();
    for (std::size_t i = 0; i < k; ++i) {
      l.point.push_back(*index.find(p.corners[i]));
      l.is_corner.push_back(1);
      between.clear();
      hanging_points(index, p.corners[i], p.corners[(i + 1) % k], 2 * tolerance, 48, between);
      for (std::uint32_t id : between) {
        l.point.push_back(id);
        l.is_corner.push_back(0);
      }
    }
    l.begin.push_back(l.point.size());
  }
  l.patch.resize(l.point.size());
  for (std::size_t i = 0; i < patches.size(); ++i)
    std::fill(l.patch.begin() + static_cast<std::ptrdiff_t>(l.begin[i]),
              l.patch.begin() + static_cast<std::ptrdiff_t>(l.begin[i + 1]),
              static_cast<std::uint32_t>(i));
  return l;
}

// One vertex per point and smoothing group (patches of one material whose normals are
// within kSmoothAngleDeg), valued by the group's open-area mean; returns each loop
// entry's vertex.
std::vector<std::uint32_t> shared_vertices(std::span<const ShadingPatch> patches,
                                           const PointIndex& index, const Loops& l,
                                           RenderMesh& mesh) {
  // The loop entries at each point (compressed rows).
  std::vector<std::size_t> at_begin(index.size() + 1, 0);
  for (std::uint32_t id : l.point) ++at_begin[id + 1];
  for (std::size_t i = 0; i < index.size(); ++i) at_begin[i + 1] += at_begin[i];
  std::vector<std::size_t> at(l.point.size());
  {
    std::vector<std::size_t> fill(at_begin.begin(), at_begin.end() - 1);
    for (std::size_t e = 0; e < l.point.size(); ++e) at[fill[l.point[e]]++] = e;
  }
  std::vector<std::uint32_t> loop_vertex(l.point.size());
  const double min_cos = std::cos(kSmoothAngleDeg * std::numbers::pi / 180);
  std::vector<std::uint32_t> material;
  std::vector<Vec3> normal;
  std::vector<std::size_t> group;
  std::vector<Rgb> open_sum, area_sum;
  std::vector<double> open_w, area_w;
  std::vector<std::uint32_t> vertex;
  for (std::size_t pt = 0; pt < index.size(); ++pt) {
    const std::size_t b = at_begin[pt], n = at_begin[pt + 1] - b;
    const auto patch_at = [&](std::size_t i) -> const ShadingPatch& {
      return patches[l.patch[at[b + i]]];
    };
    material.resize(n);
    normal.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      material[i] = patch_at(i).material;
      normal[i] = patch_at(i).normal;
    }
    smoothing_groups(material, normal, min_cos, group);
    // Each group's open-area mean, summed in the order of its leaves.
    open_sum.assign(n, Rgb::Zero());
    area_sum.assign(n, Rgb::Zero());
    open_w.assign(n, 0.0);
    area_w.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const ShadingPatch& p = patch_at(i);
      const std::size_t g = group[i];
      const double w = p.area * std::clamp(p.open, 0.0, 1.0);
      open_sum[g] += w * p.radiosity;
      open_w[g] += w;
      area_sum[g] += p.area * p.radiosity;
      area_w[g] += p.area;
    }
    vertex.resize(n);
    for (std::size_t g = 0; g < n; ++g) {
      if (group[g] != g) continue;
      vertex[g] = static_cast<std::uint32_t>(mesh.positions.size());
      mesh.positions.push_back(index.point(static_cast<std::uint32_t>(pt)));
      mesh.radiosity.push_back(open_w[g] > 0   ? Rgb(open_sum[g] / open_w[g])
                               : area_w[g] > 0 ? Rgb(area_sum[g] / area_w[g])
                                               : patch_at(g).radiosity);
      mesh.reflectance.push_back(patch_at(g).reflectance);
    }
    for (std::size_t i = 0; i < n; ++i) loop_vertex[at[b + i]] = vertex[group[i]];
  }
  return loop_vertex;
}

RenderMesh smooth_mesh(std::span<const ShadingPatch> patches, double tolerance) {
  PointIndex index(tolerance);
  for (const ShadingPatch& p : patches)
    for (const Vec3& c : p.corners) (void)index.insert(c);
  const Loops loops = boundary_loops(patches, index, tolerance);
  RenderMesh mesh;
  const std::vector<std::uint32_t> loop_vertex = shared_vertices(patches, index, loops, mesh);

  // The polygons: a leaf without hanging points as it is; one with them (or with more
  // than 4 corners) as a fan around its centre.
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const ShadingPatch& p = patches[i];
    const std::size_t b = loops.begin[i], e = loops.begin[i + 1], k = p.corners.size();
    if (e - b == k && k <= 4) {
      mesh.polys.push_back({loop_vertex[b], loop_vertex[b + 1], loop_vertex[b + 2],
                            k == 4 ? loop_vertex[b + 3] : RenderMesh::kNoVertex});
      continue;
    }
    Vec3 centre = Vec3::Zero();
    Rgb value = Rgb::Zero();
    for (std::size_t j = b; j < e; ++j)
      if (loops.is_corner[j]) value += mesh.radiosity[loop_vertex[j]];
    for (const Vec3& c : p.corners) centre += c;
    centre /= static_cast<double>(k);  // the bilinear centre of a quad, a triangle's centroid
    if (k > 4) centre = p.centre;
    const auto c = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.push_back(centre);
    mesh.radiosity.push_back(value / static_cast<double>(k));
    mesh.reflectance.push_back(p.reflectance);
    for (std::size_t j = b; j < e; ++j)
      mesh.polys.push_back(
          {c, loop_vertex[j], loop_vertex[j + 1 < e ? j + 1 : b], RenderMesh::kNoVertex});
  }
  return mesh;
}

}  // namespace

RenderMesh shade_patches(std::span<const ShadingPatch> patches, Shading mode, double tolerance) {
  if (!(tolerance > 0) || !std::isfinite(tolerance))
    throw std::invalid_argument(
        fmt::format("shade_patches: the tolerance must be a finite number > 0, got {}", tolerance));
  for (std::size_t i = 0; i < patches.size(); ++i)
    if (patches[i].corners.size() < 3)
      throw std::invalid_argument(
          fmt::format("shade_patches: patch {} has {} corners (at least 3 needed)", i,
                      patches[i].corners.size()));
  return mode == Shading::Flat ? flat_mesh(patches) : smooth_mesh(patches, tolerance);
}

}  // namespace hrad
