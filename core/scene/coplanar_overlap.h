// Faces that lie in one plane, face the same way and overlap: the same surface given
// twice (a floor given again as two triangles), which the solver treats as two surfaces
// that each reflect and emit (probes came out 35-48 % too bright, without a word; the
// path tracer, which meets only one of them, was right). Exact repeats are dropped by
// SceneBuilder; what a later face shares with an earlier one is cut out of the later
// face here, and what could not be cut is reported (core/scene/scene_builder.h).
#pragma once

#include "core/base/geometry.h"
#include "core/scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace hrad {

struct CoplanarOverlaps {
  std::size_t pairs = 0;      ///< pairs of faces that share area
  double area = 0;            ///< the area they share, summed over the pairs
  Vec3 first = Vec3::Zero();  ///< the centroid of the first pair's first face
};

/// Pairs of faces in one plane (normals within 1e-6, offsets within 1e-7 of the scene's
/// diagonal), facing the same way, sharing more than 1e-6 of the smaller one's area.
/// Faces are convex (SceneBuilder's invariant). `source`, when not empty, gives each
/// face's input polygon: the triangles of one triangulated polygon are not compared.
/// Sorted sweeps per plane, each stopped after kMaxOverlapChecks candidate pairs (a
/// polygon of 20,000 corners triangulated into long thin triangles made the sweep
/// quadratic: 3.4 s), so the test is bounded and may miss overlaps in such a plane.
inline constexpr std::size_t kMaxOverlapChecks = 20'000'000;
CoplanarOverlaps find_coplanar_overlaps(const Scene& scene,
                                        std::span<const std::uint32_t> source = {});

/// What remove_coplanar_overlaps did.
struct CoplanarCuts {
  std::size_t faces_cut = 0;      ///< later faces that lost area to an earlier one
  std::size_t faces_dropped = 0;  ///< of those, the ones an earlier face covered whole
  std::size_t pieces = 0;         ///< convex faces that replaced the cut ones' remains
  double area = 0;                ///< the area taken out of the later faces
  Vec3 first = Vec3::Zero();      ///< the centroid of the first face cut
};

/// Most convex pieces one face may be cut into; a face that would need more is left
/// whole (and reported by find_coplanar_overlaps).
inline constexpr std::size_t kMaxOverlapPieces = 256;

/// Cuts out of every face what earlier faces (in input order) in its plane, facing the
/// same way, cover, by the tests of find_coplanar_overlaps: the earlier face keeps the
/// shared area, its material and emission, and the later face's remains become convex
/// pieces in its place (its material, its input polygon in `source`), so each part of
/// a surface is solved once. Pieces of a sliver's proportions (area below 1e-12 of the
/// squared edge lengths, or below 1e-9 of the face's area) are dropped. `source` gives
/// each face's input polygon (faces of one polygon are not compared; when its size is
/// not the faces', every face is taken as its own polygon) and is rewritten for the new
/// faces; the order of the faces is kept, pieces where their face was.
CoplanarCuts remove_coplanar_overlaps(Scene& scene, std::vector<std::uint32_t>& source);

}  // namespace hrad
