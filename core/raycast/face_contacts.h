// Face contacts: polygons that lie against another polygon face to face, such as a box's
// bottom and the floor it stands on, or a cabinet's back and the wall behind it. Only
// there can a point see, at distance zero, a surface that the rays' end-point exclusion
// hides (the open fractions' contact tests, core/transport/open_fraction.cpp); every other
// polygon can skip those tests.
#pragma once

#include "core/base/geometry.h"

#include <cstdint>
#include <span>
#include <vector>

namespace hrad {

struct PolygonRange;

/// For each polygon, 1 when another polygon lies against it: the two face opposite ways
/// (normals within kContactDegrees of opposite), each comes within `tolerance` of the
/// other's plane, and their bounding boxes, grown by `tolerance`, overlap. A polygon's
/// twin (`twins`, core/raycast/face_twins.h; empty for none) does not count: it is the other
/// side of the same sheet. Degenerate polygons (zero normal) are marked, and so is a
/// polygon among more than kContactCandidates candidates that could not all be tested:
/// a 1 only costs its tests, a wrong 0 would skip a contact. Time O(n log n) for n
/// polygons plus the candidates tested.
std::vector<std::uint8_t> find_face_contacts(std::span<const Vec3> vertices,
                                             std::span<const std::uint32_t> indices,
                                             std::span<const PolygonRange> polygons,
                                             std::span<const std::uint32_t> twins,
                                             double tolerance);

/// Normals within this angle of opposite count as facing each other.
inline constexpr double kContactDegrees = 2.0;
/// The most candidates tested for one polygon before it is marked without more tests.
inline constexpr int kContactCandidates = 512;

}  // namespace hrad
