// Shading of a solution's picture and mesh: how the constant radiosity of each leaf
// element becomes values at the vertices of the RenderMesh that render.png and
// solution.ply show.
//
// flat: every leaf keeps its own corners and its own radiosity (a constant per leaf,
//   exactly what the solver computed; the quadtree shows as patches).
// smooth (the default): one value per vertex *position and surface*, interpolated
//   linearly (bilinearly on quads) inside each leaf, so that neighbouring leaves agree
//   along their whole shared edge:
//   1. Every point where leaf corners meet gets, for each smoothing group there, the
//      mean radiosity of the group's leaves touching it (weighted by open area: area x
//      open fraction, core/transport/open_fraction.h; by area where the whole group is closed in).
//      Leaves belong to one group when they share the material and their normals lie
//      within kSmoothAngleDeg of each other (closed transitively at the point), so
//      creases (a box's edges, a wall meeting the floor) and light outlines stay sharp,
//      while the leaves of one polygon and the facets of a tessellated curved surface
//      blend.
//   2. T-vertices: a corner of a finer leaf that lies inside the edge of a coarser one
//      is found by probing the coarse edge's midpoint, recursively (quadtree leaves,
//      and polygons that share whole edges, meet only at such dyadic points). The
//      coarse leaf counts as touching that point (step 1) and is drawn as a fan of
//      triangles around its centre through every such point, the centre carrying the
//      mean of its corner values (its bilinear value there). Along any shared edge
//      both sides then interpolate linearly between the same values: no crack, no
//      step.
//   Not handled: T-junctions of the input itself (a polygon edge ending part-way
//   along another polygon's edge, at no dyadic point of it): values are continuous
//   at shared corners only there.
#pragma once

#include "core/config/modes.h"
#include "core/scene/render_mesh.h"

#include <span>
#include <string>
#include <string_view>

namespace hrad {

/// Normals of leaves smoothed together differ by at most this angle (degrees).
inline constexpr double kSmoothAngleDeg = 30;

/// One leaf element as the shading sees it.
struct ShadingPatch {
  std::span<const Vec3> corners;  ///< planar convex polygon, >= 3 corners, in order
  Vec3 centre = Vec3::Zero();     ///< inside the polygon (the fan's centre for > 4 corners)
  Vec3 normal = Vec3::Zero();     ///< unit normal
  std::uint32_t material = 0;     ///< leaves of different materials never blend
  double area = 0;
  double open = 1;  ///< open fraction in [0, 1]
  Rgb radiosity = Rgb::Zero();
  Rgb reflectance = Rgb::Zero();
};

/// The RenderMesh of these leaves. `tolerance` (scene units, > 0) is the distance
/// under which two corners count as one point (the solver uses 1e-7 x the scene's
/// diagonal). Throws std::invalid_argument for a patch with fewer than 3 corners or a
/// tolerance that is not positive.
[[nodiscard]] RenderMesh shade_patches(std::span<const ShadingPatch> patches, Shading mode,
                                       double tolerance);

}  // namespace hrad
