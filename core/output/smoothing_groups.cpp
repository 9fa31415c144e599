#include "core/output/smoothing_groups.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>

namespace hrad {

namespace {

std::size_t root_of(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

void smoothing_groups(std::span<const std::uint32_t> material, std::span<const Vec3> normal,
                      double min_cos, std::vector<std::size_t>& group) {
  assert(material.size() == normal.size());
  const std::size_t n = material.size();
  std::vector<std::size_t>& parent = group;
  parent.resize(n);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  const auto close = [&](std::size_t i, std::size_t j) {
    return material[i] == material[j] && normal[i].dot(normal[j]) >= min_cos;
  };
  const auto join = [&](std::size_t i, std::size_t j) {
    parent[root_of(parent, j)] = root_of(parent, i);
  };
  if (n <= kPairwiseLeaves) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j)
        if (close(i, j)) join(i, j);
  } else {
    // Unit normals within min_cos are within the chord sqrt(2 - 2 min_cos) of each
    // other; two in one cube of side `side` are within side * sqrt(3), under it.
    const double chord = std::sqrt(std::max(0.0, 2 - 2 * min_cos));
    const double side = 0.999 * chord / std::sqrt(3.0);
    struct Entry {
      std::array<std::int64_t, 4> key;  // material, cell; a non-unit normal: a cell alone
      std::size_t leaf;
    };
    std::vector<Entry> entries(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double len2 = normal[i].squaredNorm();
      Entry& e = entries[i];
      e.leaf = i;
      e.key[0] = material[i];
      if (side > 0 && std::abs(len2 - 1) < 1e-9) {
        for (int c = 0; c < 3; ++c)
          e.key[c + 1] = static_cast<std::int64_t>(std::floor(normal[i][c] / side));
      } else {
        e.key[1] = std::numeric_limits<std::int64_t>::min();  // beyond every cell
        e.key[2] = static_cast<std::int64_t>(i);
        e.key[3] = 0;
      }
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
      return a.key != b.key ? a.key < b.key : a.leaf < b.leaf;
    });
    // Whether no normal of one cell can be within the chord of one of the other's: the
    // cubes are farther apart than that (the three faces of a box corner, each a fan of
    // slivers, were compared leaf by leaf).
    const auto apart = [&](const Entry& a, const Entry& b) {
      if (a.key[1] == std::numeric_limits<std::int64_t>::min() ||
          b.key[1] == std::numeric_limits<std::int64_t>::min())
        return false;
      double gap2 = 0;
      for (int c = 1; c < 4; ++c) {
        const double cells_between =
            std::max<double>(0, static_cast<double>(std::abs(a.key[c] - b.key[c])) - 1);
        gap2 += cells_between * cells_between;
      }
      return gap2 * side * side > chord * chord;
    };
    // Cells: runs of one key, each joined at once (a lone cell holds one leaf).
    std::vector<std::size_t> begin;
    for (std::size_t k = 0; k < n; ++k) {
      if (k == 0 || entries[k].key != entries[k - 1].key) {
        begin.push_back(k);
      } else {
        join(entries[begin.back()].leaf, entries[k].leaf);
      }
    }
    begin.push_back(n);
    // Cells of one material: compare leaves until one pair is close, unless already joined.
    const std::size_t cells = begin.size() - 1;
    for (std::size_t a = 0; a < cells; ++a) {
      for (std::size_t b = a + 1; b < cells; ++b) {
        const Entry& ea = entries[begin[a]];
        const Entry& eb = entries[begin[b]];
        if (ea.key[0] != eb.key[0]) break;  // sorted: no later cell has a's material
        if (root_of(parent, ea.leaf) == root_of(parent, eb.leaf)) continue;
        if (apart(ea, eb)) continue;
        bool found = false;
        for (std::size_t i = begin[a]; i < begin[a + 1] && !found; ++i)
          for (std::size_t j = begin[b]; j < begin[b + 1] && !found; ++j)
            found = close(entries[i].leaf, entries[j].leaf);
        if (found) join(ea.leaf, eb.leaf);
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) group[i] = root_of(parent, i);
}

}  // namespace hrad
