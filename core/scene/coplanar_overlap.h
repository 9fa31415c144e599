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

/// Faces in one plane: normals within 1e-6, offsets within 1e-7 of the scene's
/// diagonal. Overlapping: sharing more than 1e-6 of the smaller one's area. Candidates
/// come from sorted sweeps per plane, each stopped after kMaxOverlapChecks candidate
/// pairs (a polygon of 20,000 corners triangulated into long thin triangles made the
/// sweep quadratic: 3.4 s), so the search is bounded and may miss overlaps in such a
/// plane.
inline constexpr std::size_t kMaxOverlapChecks = 20'000'000;

/// What remove_coplanar_overlaps did.
struct CoplanarCuts {
  std::size_t faces_cut = 0;      ///< later faces that lost area to an earlier one
  std::size_t faces_dropped = 0;  ///< of those, the ones an earlier face covered whole
  std::size_t pieces = 0;         ///< convex faces that replaced the cut ones' remains
  double area = 0;                ///< the area taken out of the later faces
  Vec3 first = Vec3::Zero();      ///< the centroid of the first face cut
  /// Pairs left overlapping (a face that would need more than kMaxOverlapPieces pieces
  /// is left whole), the area they share, and the first pair's earlier face's centroid.
  std::size_t left_pairs = 0;
  double left_area = 0;
  Vec3 left_first = Vec3::Zero();
};

/// Most convex pieces one face may be cut into; a face that would need more is left
/// whole (and counted in CoplanarCuts::left_pairs).
inline constexpr std::size_t kMaxOverlapPieces = 256;

/// Cuts out of every face what earlier faces (in input order) in its plane, facing the
/// same way, cover (the tests of kMaxOverlapChecks' comment): the earlier face keeps the
/// shared area, its material and emission, and the later face's remains become convex
/// pieces in its place (its material, its input polygon in `source`), so each part of
/// a surface is solved once. Pieces of a sliver's proportions (area below 1e-12 of the
/// squared edge lengths, or below 1e-9 of the face's area) are dropped. `source` gives
/// each face's input polygon (faces of one polygon are not compared; when its size is
/// not the faces', every face is taken as its own polygon) and is rewritten for the new
/// faces; the order of the faces is kept, pieces where their face was.
CoplanarCuts remove_coplanar_overlaps(Scene& scene, std::vector<std::uint32_t>& source);

}  // namespace hrad
