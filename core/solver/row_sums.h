// Row sums: the total transport a leaf gathers, sum over the links of the leaf
// and of its ancestors of F x V. Physically it is the fraction of the leaf's
// hemisphere that meets a lit surface, so it lies in [0, 1]: 1 less the directions
// that leave the scene or meet a back face (black).
//
// The hierarchical estimate misses this locally: a leaf in a corner gathers
// from coarse ancestors' links the ancestor's average form factor, and its row
// sum can exceed 1 (measured up to 1.3 in a closed cube at eps = 1e-4), while
// the area-weighted mean stays within 1e-3 of the truth. The correction modes
// (option row_sums) are post-hoc rescales kept for the study of such errors:
//   keep       use the links as they are (the default: neither rescale fixes
//              the transport, and both bias the answer);
//   clamp      scale a leaf's gathered irradiance by 1 / S when its row sum S
//              exceeds 1 (no rays; never adds energy, so it is biased low by
//              construction: 17 % low in builtin:furnace,rho=0.9, where keep is
//              within 2 %);
//   normalize  scale it by (1 - uncovered) / S, at most kNormalizeGainCap (2) times,
//              where `uncovered` is the share of cosine-distributed rays from the
//              leaf's open points that meet no lit surface: they escape, meet a back
//              face (black, as in `hrad reference`), or meet the inside of a solid
//              (row_sum_rays rays per leaf, rounded down to a multiple of 4 and at
//              least 4, 4 from each point; a point most of whose
//              rays meet back faces is closed in and not counted). A closed-in leaf
//              (open fraction 0) is left alone. Exact for a closed scene without
//              open-ended objects (every ray from an open point meets a front face);
//              noisy by about sqrt(u (1 - u) / rays) per leaf otherwise, so a
//              correction d of the row sum is shrunk by d^2 / (d^2 + se^2), se the
//              estimate's standard error over its points (Wiener). A surplus
//              (S above the target) comes out of what the leaf inherits from cluster
//              receivers first (Element::cluster_scale), and out of its surface chain's
//              light only beyond that. It corrects each leaf's total transport, not how
//              the leaf's links share it among sources of different radiosity.
#pragma once

#include "core/hierarchy/element.h"
#include "core/solver/propagation.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hrad {

class Hierarchy;
class RayScene;

/// Half-width of the band around 1 that RowSumStats::within_band counts.
inline constexpr double kRowSumBand = 0.03;

struct RowSumStats {
  double min = 0, max = 0, area_mean = 0;  ///< of the uncorrected leaf row sums
  /// Share of the leaves' open area whose row sum is within kRowSumBand of 1 (in a
  /// closed scene, where every row sum should be 1: issue 13 asks for 99 %).
  double within_band = 0;
  std::uint64_t corrected = 0;  ///< leaves whose gather_scale is not 1
  /// Leaves whose open-area gain was capped (see apply_row_sums), in every mode.
  std::uint64_t open_capped = 0;
  std::uint64_t rays_cast = 0;  ///< escape rays cast by this call
  /// Elements whose gather rows were kept from the last propagation (push_transport).
  std::uint64_t rows_kept = 0;
};

/// Sets every element's gather_scale (parents before children in `elements`).
/// `receiver` must be the propagation's, so that the sums are what the leaves gather.
/// `cache`: the run's PropagationCache (core/solver/propagation.h), when it has one.
RowSumStats apply_row_sums(const std::vector<Element*>& elements, RowSumMode mode,
                           ClusterReceiver receiver, const Hierarchy& hierarchy,
                           const RayScene& rays, int rays_per_leaf, std::uint64_t seed, int threads,
                           PropagationCache* cache = nullptr);

}  // namespace hrad
