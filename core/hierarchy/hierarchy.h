// Hierarchy: the complete hierarchy over a scene — clusters built top-down over
// the input polygons at construction, and below each polygon a quadtree built
// lazily during refinement (triangles into 4 at edge midpoints; quads and convex
// n-gons into one quad per corner, through edge midpoints and the centroid).
//
// Determinism: the cluster tree is a pure function of the scene (median splits
// with index tie-breaks), children are a pure function of their parent, and ids
// hash the path from the root.
//
// Threading: subdivide() may be called concurrently; it builds each element's
// children exactly once (double-checked under a hashed lock) and allocates them
// from the calling worker's arena (core/parallel/node_arena.h: page-aligned chunks that
// record their owner and NUMA node; each element records its node in home_node).
// Links are stored the same way, from a staging arena per worker (store_links), and
// compacted into a link arena per worker when a refinement stage ends; elements live
// as long as the hierarchy, links until release_links().
#pragma once

#include "core/hierarchy/element.h"
#include "core/parallel/lock_pool.h"
#include "core/parallel/node_arena.h"
#include "core/scene/scene.h"

#include <memory>
#include <span>
#include <vector>

namespace hrad {

/// The distance, as a share of the scene's diagonal, within which a point counts as on
/// a plane: for Hierarchy::common_normal and Transport::classify, which must agree.
inline constexpr double kPlaneTolerance = 1e-9;

class Hierarchy {
 public:
  /// Polygons per cluster below which a cluster's children are its polygons.
  static constexpr std::uint32_t kClusterLeafSize = 4;
  /// Surface subdivision stops at this depth below the input polygon whatever
  /// the area threshold says (4^-24 of the polygon's area).
  static constexpr int kMaxSurfaceDepth = 24;

  /// The cluster tree is built here, into worker 0's arena.
  Hierarchy(const Scene& scene, int workers, const ArenaPlacement& placement = {});
  ~Hierarchy();
  Hierarchy(const Hierarchy&) = delete;
  Hierarchy& operator=(const Hierarchy&) = delete;

  [[nodiscard]] Element& root() { return *root_; }
  [[nodiscard]] const Element& root() const { return *root_; }
  [[nodiscard]] const Scene& scene() const { return scene_; }

  /// True when `e` has or may get children.
  [[nodiscard]] static bool can_subdivide(const Element& e) {
    return e.is_cluster() ? e.child_count > 0 : e.depth < kMaxSurfaceDepth;
  }
  /// The children of `e`, creating them (once, whoever races) if needed.
  std::span<Element> subdivide(Element& e, int worker, LockPool& locks);

  /// A point on the surface of `e` (on a member polygon for clusters, chosen with
  /// probability proportional to area), from three uniform numbers in [0,1).
  /// When `toward` is given and `e` is a cluster, the member polygon is redrawn
  /// (up to kFacingTries times, with numbers derived from u3) until it faces
  /// `toward`, so that a visibility ray does not start on the far side of the
  /// cluster's own objects: the cluster model's projected area A/4 already
  /// accounts for members facing away, and counting their self-occlusion again
  /// would lose that transport twice.
  /// When `face` is given, it receives the input polygon the point lies on (~0u for
  /// the centre of an empty cluster), for rays that must ignore that polygon.
  [[nodiscard]] Vec3 sample_point(const Element& e, double u1, double u2, double u3,
                                  const Vec3* toward = nullptr,
                                  std::uint32_t* face = nullptr) const;
  static constexpr int kFacingTries = 8;
  /// Unit front normal of input polygon `face`.
  [[nodiscard]] const Vec3& face_normal(std::uint32_t face) const { return face_normal_[face]; }
  /// For a cluster whose member polygons all lie in one plane and face the same way
  /// (a polygon triangulated into slivers, a tessellated floor): that front normal;
  /// else (other clusters, surfaces) null. Its centre lies in the plane.
  [[nodiscard]] const Vec3* common_normal(const Element& e) const {
    if (!e.is_cluster() || e.face >= e.face_end || plane_run_end_[e.face] < e.face_end)
      return nullptr;
    return &face_normal_[order_[e.face]];
  }

  /// Every element, parents before children (a snapshot; call when no refiner runs).
  [[nodiscard]] std::vector<Element*> elements();
  [[nodiscard]] std::size_t element_count() const;
  [[nodiscard]] std::size_t element_bytes() const;
  /// Element bytes by NUMA node, summed over the arenas (size = placement nodes).
  [[nodiscard]] std::vector<std::uint64_t> element_bytes_per_node() const;
  /// A worker's element arena (for tests and placement reports).
  [[nodiscard]] const NodeArena& arena(int worker) const;

  /// Appends `links` at receiver `r` in blocks from `worker`'s link staging arena;
  /// true when r had no links before (the caller then compacts r, see below). The
  /// caller holds r's link lock (or no refiner runs); a worker's arenas are used by
  /// that worker only.
  bool store_links(Element& r, std::span<const Link> links, int worker);
  /// Moves r's links into one block of `worker`'s link arena (core/hierarchy/link_list.h).
  /// Call once per receiver when a refinement stage's stores are over, then
  /// reset_link_staging() for every worker.
  void compact_links(Element& r, int worker);
  /// Hands `worker`'s staging arena out again from its start: every list it held
  /// has been compacted.
  void reset_link_staging(int worker);
  /// Clears the links of every element in `elements` (which must hold every element
  /// that has links) and hands all link arenas' memory out again from the start.
  /// Call when no refiner runs.
  void release_links(const std::vector<Element*>& elements, int threads = 1);
  /// Link bytes (blocks with their headers and free slots, in the link and staging
  /// arenas), total and by NUMA node.
  [[nodiscard]] std::size_t link_bytes() const;
  [[nodiscard]] std::vector<std::uint64_t> link_bytes_per_node() const;
  /// Up to `per_arena` pages of each element and link arena, with the node the arena
  /// counts each on (see NodeArena::sample_pages).
  [[nodiscard]] std::vector<std::pair<const void*, int>> sample_pages(std::size_t per_arena) const;
  /// A worker's link arena and link staging arena (for tests).
  [[nodiscard]] const NodeArena& link_arena(int worker) const;
  [[nodiscard]] const NodeArena& link_staging_arena(int worker) const;

 private:
  struct Arena;
  Element* allocate(std::size_t count, int worker);
  void init_surface(Element& e, std::uint32_t face, Element* parent, std::uint64_t id);
  void build_cluster(Element& c, std::uint32_t begin, std::uint32_t end, int depth);
  void finish_cluster(Element& c);
  void find_plane_runs();
  [[nodiscard]] Vec3 sample_face(std::uint32_t face, double u1, double u2, double u3) const;

  const Scene& scene_;
  std::vector<std::uint32_t> order_;  ///< faces in cluster order
  std::vector<double> prefix_area_;   ///< prefix sums of face areas in order_
  std::vector<Vec3> face_normal_;     ///< unit normal of each input polygon
  /// Per position i of order_: one past the last position j such that the polygons at
  /// positions i .. j - 1 share order_[i]'s plane and normal (common_normal).
  std::vector<std::uint32_t> plane_run_end_;
  /// Polygons with more than 3 corners: twice the area of each fan triangle (corner 0,
  /// i, i + 1), from fan_area_[fan_first_[face]] on, for sample_face.
  std::vector<std::uint32_t> fan_first_;
  std::vector<double> fan_area_;
  std::vector<Vec3> ngon_store_;  ///< corners of input polygons with > 4 vertices
  std::vector<std::unique_ptr<Arena>> arenas_;
  Element* root_ = nullptr;
};

/// Mixes a parent id and a child index into the child's id (splitmix64 finaliser).
std::uint64_t child_id(std::uint64_t parent, std::uint32_t index);

}  // namespace hrad
