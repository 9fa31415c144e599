// Ray queries against a static polygon scene: "is this segment blocked?" and
// "what does this ray hit first?". The implementation (ray_scene.cpp) is the only
// file in hrad that includes Embree; nothing Embree-specific leaks through here.
//
// Precision and scale. Embree works in single precision. RayScene therefore maps the
// scene into a normalised frame, q = (p - c) / D with c the bounding-box centre and D
// its diagonal, before handing coordinates to Embree, so translating or scaling a scene
// (units of mm or km, or far from the origin) changes neither the answers nor their
// accuracy. Every tolerance below is relative to D.
//
// Thread-safety. After construction a RayScene is immutable except for the ray
// counter: occluded() and intersect() may be called concurrently from any number of
// threads. Construction and destruction are not thread-safe with respect to queries.
#pragma once

#include "core/base/geometry.h"

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>

namespace hrad {

class BoxTree;

struct Scene;

/// First hit of a ray.
struct RayHit {
  std::uint32_t prim = 0;  ///< index of the input polygon that was hit
  double t = 0;            ///< hit point = origin + t * dir (t in units of |dir|)
  /// Embree's surface coordinates of the hit, in [0,1]:
  ///  - triangle (p0,p1,p2): barycentric, p = (1-u-v) p0 + u p1 + v p2;
  ///  - quad (p0,p1,p2,p3): bilinear, p ~ (1-u)(1-v) p0 + u(1-v) p1 + u v p2 + (1-u) v p3
  ///    (exact for parallelograms; Embree splits the quad along p1-p3 otherwise);
  ///  - polygon with k > 4 vertices: barycentric within fan triangle (p0, p[s+1], p[s+2]).
  double u = 0, v = 0;
  std::uint32_t sub = 0;  ///< fan triangle s for polygons with more than 4 vertices, else 0
};

/// Index range of one input polygon in an index array (the same shape as Scene's Face).
struct PolygonRange {
  std::uint32_t first = 0;  ///< position of the first vertex index
  std::uint32_t count = 0;  ///< number of vertices, >= 3
};

class RayScene {
 public:
  /// Segment end points (and ray origins) are excluded by this distance, relative to
  /// the scene's tolerance scale (scale(): its bounding-box diagonal, or near its bulk
  /// when a little geometry lies far from the rest, see the constructor): hits closer
  /// than kEndpointEpsilon * scale() to either end are ignored. Single precision places
  /// a point to about 1e-7 of the diagonal; with 1e-5, a segment ending on a surface is
  /// not reported as occluded by that surface down to grazing angles of about 0.1
  /// degree (tested; 1e-6 fails below about 1 degree). The price: an occluder within
  /// 1e-5 of the diagonal of an end point is missed (0.1 mm in a 10 m room).
  static constexpr double kEndpointEpsilon = 1e-5;
  /// intersect() from farther than this many diagonals from the scene's centre starts
  /// the ray again just outside the scene (a camera far away): Embree's single
  /// precision rays may not start beyond 1.8e19, and lose the scene's detail long before.
  static constexpr double kFarOrigin = 4;

  /// Polygons are convex and planar (triangles, quads, or larger convex polygons that
  /// are fan-triangulated internally). Degenerate polygons are accepted and never hit.
  /// Throws std::invalid_argument on a polygon with fewer than 3 vertices, an index out
  /// of range or a non-finite coordinate; std::runtime_error when Embree fails.
  /// How much time the acceleration structure's build may take: Quality (the
  /// default) for scenes that many rays are cast into; Fast (several times quicker to
  /// build, somewhat slower rays) for a few thousand rays. Answers are the same.
  enum class Build { Quality, Fast };

  ///
  /// `twins` (empty, or one entry per polygon: the index of its twin or kNoPolygon,
  /// symmetric; core/raycast/face_twins.h) pairs polygons that are the two sides of one sheet.
  /// Ignoring one of a pair ignores both, and intersect() never reports the back of a
  /// polygon that has a twin: the ray meets the twin's front there instead. Throws
  /// std::invalid_argument when `twins` has the wrong size or is not symmetric.
  ///
  /// `bulk`, when given, is the box that holds most of the area (Scene::bulk_bounds).
  /// When the bounding box's diagonal D is more than kLocalFrame times bulk's, the
  /// tolerances follow the bulk: scale() is kLocalFrame times bulk's diagonal, and the
  /// single-precision frame is centred on it, so that a little geometry far away (a
  /// 0.1-unit triangle 30,000 units from a unit room) does not make every distance in
  /// the room a contact. Far from the bulk, where single precision cannot resolve
  /// that, a ray's exclusion grows with its end points' distance from the bulk's
  /// centre (kPrecisionUlps units in the last place of the larger).
  RayScene(std::span<const Vec3> vertices, std::span<const std::uint32_t> indices,
           std::span<const PolygonRange> polygons, Build build = Build::Quality,
           std::span<const std::uint32_t> twins = {}, const Aabb* bulk = nullptr);
  static constexpr double kLocalFrame = 10;
  static constexpr double kPrecisionUlps = 32;
  /// All faces of the scene, with their twins (find_twins) and its bulk
  /// (Scene::bulk_bounds); prim ids are face indices.
  static RayScene from_scene(const Scene& scene, Build build = Build::Quality);

  RayScene(RayScene&&) noexcept;
  RayScene& operator=(RayScene&&) noexcept;
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;
  ~RayScene();

  /// "No polygon": a face id that ignores nothing.
  static constexpr std::uint32_t kNoPolygon = ~std::uint32_t{0};

  /// True when some polygon crosses the open segment from `from` to `to`, ignoring
  /// hits within kEndpointEpsilon * scale() of either end point. Segments shorter
  /// than twice that are never occluded. Thread-safe.
  ///
  /// `ignore_a`, `ignore_b`: polygons whose hits are ignored, with their twins
  /// (kNoPolygon: none). Pass
  /// the polygons the end points lie on: a segment from a point on a planar polygon
  /// meets that polygon's plane only at its start, so any hit on it is false, but in
  /// single precision a segment that skims along the polygon from an end point within
  /// ~1e-5 of the diagonal of it is reported blocked by it (grazing self-hits).
  [[nodiscard]] bool occluded(const Vec3& from, const Vec3& to, std::uint32_t ignore_a = kNoPolygon,
                              std::uint32_t ignore_b = kNoPolygon) const;

  /// First hit along origin + t * dir with kEndpointEpsilon * scale() <= t |dir| and
  /// t <= tmax, skipping polygon `ignore` (the one the origin lies on, if known; see
  /// occluded()) and its twin. `dir` need not be unit length, but must be non-zero.
  /// Polygons are hit from both sides, except one with a twin, which is hit only from
  /// its front (its twin covers the back). Thread-safe.
  [[nodiscard]] std::optional<RayHit> intersect(
      const Vec3& origin, const Vec3& dir, double tmax = std::numeric_limits<double>::infinity(),
      std::uint32_t ignore = kNoPolygon) const;

  /// The tolerance scale: the bounding-box diagonal D of all vertices referenced by
  /// polygons (0 when empty), or kLocalFrame times the bulk's diagonal when that is
  /// smaller (see the constructor).
  [[nodiscard]] double scale() const;
  /// Whether scale() follows the bulk rather than the bounding box.
  [[nodiscard]] bool local_frame() const;
  [[nodiscard]] std::size_t polygon_count() const;
  /// The twin of polygon `poly` (see the constructor), or kNoPolygon.
  [[nodiscard]] std::uint32_t twin(std::uint32_t poly) const;
  /// Unit normal of input polygon `poly` (Newell's, from its vertex order; zero when
  /// degenerate): which side of a polygon a ray hit, d.normal(hit.prim) < 0 for the front.
  [[nodiscard]] const Vec3& normal(std::uint32_t poly) const;
  /// Whether another polygon lies against `poly` face to face (a box's bottom and the
  /// floor under it): facing it, within kContactReach * scale() of its plane, their
  /// boxes overlapping (core/raycast/face_contacts.h; a twin does not count). Only such
  /// a polygon has a surface at distance zero that the end-point exclusion hides.
  [[nodiscard]] bool lies_against(std::uint32_t poly) const;
  /// Whether, where the ray origin + t * dir meets the front of `poly`, the back of
  /// another polygon coincides with it (a box pushed against the wall `poly`): the point
  /// there is the inside of a solid, whichever of the two intersect() reported. A second
  /// look around the hit, without `poly`; false at once for a polygon that does not
  /// lie_against() another. The solver's open fractions and probes
  /// (core/transport/open_fraction.cpp) and the reference's paths
  /// (core/reference/path_tracer.cpp) take such a point as black.
  [[nodiscard]] bool back_coincides(const Vec3& origin, const Vec3& dir, double t,
                                    std::uint32_t poly) const;
  /// The reach of lies_against(), relative to scale(): four times the reach of the open
  /// fractions' contact tests (core/transport/open_fraction.cpp).
  static constexpr double kContactReach = 16 * kEndpointEpsilon;
  /// How far (world units) a surface may lie from `poly` and still count as touching it
  /// (back_coincides(), the open fractions' facing faces): kCoincidentShare of the
  /// polygon's own bounding-box diagonal, or the single-precision resolution where it
  /// lies if that is more, but never more than 3 kEndpointEpsilon scale(), the reach
  /// every polygon had before. Tolerances relative
  /// to the whole scene took a room's floor 5 mm above a 200 x 200 ground (a scale()
  /// of 283) for the inside of a solid: its probes came out 8-17 % dark, in the
  /// solver and in `hrad reference` alike.
  [[nodiscard]] double coincidence(std::uint32_t poly) const;
  static constexpr double kCoincidentShare = 1e-3;
  /// The polygons' bounding boxes (world coordinates, polygon i as box i) in a tree that
  /// finds those reaching a sphere and stops when its visitor says so
  /// (core/base/box_tree.h). Thread-safe.
  [[nodiscard]] const BoxTree& polygon_boxes() const;

  /// Rays cast so far by occluded() and intersect() together (segments too short to
  /// test are not counted). Counted in per-thread-striped relaxed atomics, so the
  /// total is exact once the querying threads have joined.
  [[nodiscard]] std::uint64_t rays_cast() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hrad
