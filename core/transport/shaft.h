// Shaft culling: can anything block a segment between elements r and s? Every
// visibility ray of the pair r <- s runs from a point of r to a point of s, so it
// lies in the convex hull of the two (the shaft). When no input polygon meets the
// shaft, every ray is unblocked and V = 1 needs no rays.
//
// The test is conservative: it answers "clear" only when it has proved, polygon by
// polygon, that none can meet the shaft; any doubt means "cast the rays". A node of
// the cluster hierarchy is skipped as a whole when its bounding box
//   - misses the shaft's bounding box (r.box united with s.box), or
//   - lies on or behind the plane of a surface r (or s) while the other element
//     lies wholly on or in front of that plane: rays then leave r into its front
//     half-space and cannot come back.
// An input polygon P is skipped by the same tests on its vertices, or when the
// points of r and s (corners for surfaces, box corners for clusters) all lie on
// one side of P's plane (touching it is fine: a segment meets the plane of P at an
// inner point only if it crosses it or lies in it; when r and s both lie in the
// plane the answer is "cast the rays").
//
// Cost: a walk over the cluster tree that stops at the first polygon that may
// block, so a blocked pair is cheap and a clear pair costs the nodes near its
// shaft. Thread-safe (no state beyond the hierarchy, which must not change shape
// above the input polygons: only surface quadtrees grow during refinement).
#pragma once

#include "core/hierarchy/element.h"

namespace hrad {

class Hierarchy;

class ShaftCuller {
 public:
  explicit ShaftCuller(const Hierarchy& hierarchy);

  /// True when no input polygon can meet a segment between a point of r and a
  /// point of s (so V = 1 exactly). False when some polygon may.
  [[nodiscard]] bool clear(const Element& r, const Element& s) const;

 private:
  const Hierarchy& hierarchy_;
  double tol_;  ///< on-plane tolerance, relative to the scene's diagonal
};

}  // namespace hrad
