// Push weights: how a surface element shares the irradiance it receives (through its
// own links and from its ancestors') among its children.
//
// A link r <- s carries the mean of the point form factor over r, and the push hands
// that mean to every part of r. Where the form factor varies over r, a part gets more
// or less than it should; across r it evens out, but not in a leaf's row sum, whose
// parts come from several levels. A leaf in the corner of a room links at its own
// level to the squares beside it on the two walls, and inherits from its ancestors
// their mean form factor to the walls' farther parts, which it sees at grazing angles
// (an ancestor's far-from-the-wall parts see them well): in the empty furnace box at
// rho 0.9 such leaves gathered up to 1.44 of their hemisphere, their neighbours 0.83,
// and the answer came out 4.7 % high (1/(1 - rho S) turns a spread of S into a
// surplus).
//
// So each surface child c of a surface element P gets a weight k_c, the share of P's
// irradiance it receives relative to P's mean: the form factors from c's centre to the
// sources of the links of P's surface chain (P's own and those of its surface
// ancestors up to its input polygon), times each link's visibility and its source's
// radiosity (frozen during refinement), scaled so that the open-area mean of k over
// P's children is 1. The push gives c its own irradiance, what P inherited from the
// clusters above its polygon as it came, and k_c times what P's surface chain gathered
// (P's own links and what it inherited from its surface ancestors), so energy is
// conserved exactly and every link's light is shared out by its own geometry at every
// level below its receiver down to the leaves. Weights from P's own links alone,
// applied to what P's own links gathered, left a corner leaf with its ancestors' mean
// two and three levels up: 80 % of the empty furnace room's area had a row sum within
// 0.97-1.03, and now all of it (the cluttered furnace: 63 % -> 79 %). Children of
// clusters and of elements whose chain has no link get 1. The weights are recomputed
// after each refinement stage.
//
// What P inherited from the cluster receivers above its polygon is shared out too, by
// a third weight, Element::cluster_weight. That light comes from the directions the
// chain's sources leave free (in a closed scene the two parts together cover the
// hemisphere), so a child whose chain covers more of its view gets less of it: the
// weight is 1 - w_c, with w_c the child's geometric chain weight before normalising
// (the sum over the chain of its centre's form factor to each source times the link's
// visibility), scaled to an open-area mean of 1 over P's children, or 1 for all when
// that mean of 1 - w_c is under 0.02 (the chain covers everything: nothing to share).
// Before, the cluster part passed down as it came, alike to every piece of a polygon:
// in builtin:office the piece of a desk's modesty panel 6 cm behind its drawer
// pedestal, which fills most of its view, got the open part's 0.19 W/m² from the
// clusters above, and the probe there read 2.1 times the path-traced value (the office's
// worst two probes of 24: +212 and +207 % -> +144 and +165 %).
//
// A partly visible link's visibility is the mean over its receiver, and the push gives
// it to every child alike (push_visibility = link, the default), so a child beside the
// occluder inherits light from directions it blocks: in the cluttered furnace, floor
// leaves beside a box had B up to 1.19 of the exact value. With push_visibility =
// child each child's weight uses its own visibility to each partly visible source of
// the chain (visibility_rays rays per child and link, Transport::visibility, per unit
// of the child's open area, kept for the next update), which takes the office's worst
// probe from 25 to 10 % and the furnace's from 5 to 1.7 % in 39 % more time on the
// office (docs/accuracy.md, "Per-child visibility in the push weights").
//
// A surface source farther than a few of its radii from a child is weighed by the
// differential form factor (within about 1/9 of the exact one there), the nearer ones
// by the exact point-to-polygon value; the normalisation takes out what is common to
// all children. On builtin:office the chains hold 251 k links (72 k own links) per
// iteration, one evaluation per child and link.
#pragma once

#include "core/config/modes.h"
#include "core/hierarchy/element.h"

#include <cstdint>
#include <vector>

namespace hrad {

class Transport;

/// A chain of more than this many links is cut to its strongest (by the link's form
/// factor x visibility x the source's radiosity); the others add to every child what
/// their links give the receiver (core/solver/push_weights.cpp).
inline constexpr std::size_t kPushExactChain = 1024;

/// Both sets of push weights of every surface child, made in one pass (the form
/// factors are the same, only the sources' radiosities differ): by light, each source
/// counting with its radiosity (for the propagation), and by geometry, every source
/// counting 1 (for row sums, core/solver/row_sums.h, which measure transport). Without light
/// anywhere both are geometric.
class PushWeights {
 public:
  /// Computes both sets for `elements` (all of the hierarchy's elements, in any order)
  /// on `threads` threads; nothing is applied yet. The hierarchy's children must not
  /// change before the last apply(). Returns the rays cast (push_visibility = child).
  /// With push_visibility = child the children's own visibilities are kept, per parent
  /// and source, for the next update on the same hierarchy: a later refinement stage
  /// adds links, and only the new parent-source pairs cast rays (the rays are a pure
  /// function of the two ids and the seed, so the weights are the same either way).
  /// The light weights count a source's radiosity as the sum of its channels times
  /// `channel_weight` (the oracles' channel weights, oracles/oracle.h: each channel
  /// against its own light).
  std::uint64_t update(const std::vector<Element*>& elements, const Transport& transport,
                       int threads, PushVisibility mode = PushVisibility::Link,
                       const Rgb& channel_weight = Rgb::Ones());
  /// Writes one set into every child's push_weight, and the cluster weights (the same
  /// for both sets: geometric) into its cluster_weight.
  void apply(bool geometric) const;
  /// Point evaluations of the last update: one per child and link of its parent's
  /// chain, at most kPushExactChain links per chain.
  [[nodiscard]] std::uint64_t evaluations() const { return evaluations_; }

  /// The children's own visibilities to the partly visible sources of one parent's
  /// chain: sources sorted, visibility[j * children + k] for source j and child k.
  struct ChildVisibility {
    std::vector<const Element*> sources;
    std::vector<float> visibility;
  };

 private:
  std::vector<Element*> parents_;    ///< elements with children
  int threads_ = 1;                  ///< the last update's, for apply()
  std::vector<std::size_t> offset_;  ///< parents_[i]'s children: offset_[i] .. offset_[i + 1]
  std::vector<float> light_, geometry_, cluster_;
  std::vector<ChildVisibility> own_;         ///< per old_parents_[i] (push_visibility = child)
  std::vector<const Element*> old_parents_;  ///< parents_ of the update own_ is from
  std::uint64_t evaluations_ = 0;
};

/// PushWeights::update followed by apply(geometric).
void update_push_weights(const std::vector<Element*>& elements, const Transport& transport,
                         int threads, bool geometric = false,
                         PushVisibility mode = PushVisibility::Link);

}  // namespace hrad
