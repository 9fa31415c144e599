#include "core/scene/scene_builder.h"

#include "core/base/interrupt.h"
#include "core/base/kd_tree_2d.h"
#include "core/scene/coplanar_overlap.h"
#include "core/scene/self_overlap.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hrad {

namespace {
constexpr double kMaxCoordinate = 1e30;
// A polygon counts as planar when no vertex is further than this fraction of
// sqrt(area) from its mean plane.
constexpr double kPlanarTolerance = 1e-3;

bool finite_nonneg(const Rgb& c) { return c.isFinite().all() && (c >= 0).all(); }
}  // namespace

SceneBuilder::SceneBuilder(std::string name, std::string source) {
  scene_.name = std::move(name);
  scene_.source = std::move(source);
}

std::uint32_t SceneBuilder::add_vertex(const Vec3& p, const SourceLoc& at) {
  for (int i = 0; i < 3; ++i) {
    if (std::isnan(p[i])) throw InputError(at.file, at.line, "coordinate is NaN");
    if (!std::isfinite(p[i]) || std::abs(p[i]) > kMaxCoordinate)
      throw InputError(at.file, at.line,
                       fmt::format("coordinate {} is infinite or beyond +-1e30", p[i]));
  }
  scene_.vertices.push_back(p);
  return static_cast<std::uint32_t>(scene_.vertices.size() - 1);
}

std::uint32_t SceneBuilder::add_material(Material m, const SourceLoc& at) {
  const Rgb& r = m.reflectance;
  if (!r.isFinite().all() || (r < 0).any() || (r > 1).any())
    throw InputError(at.file, at.line,
                     fmt::format("material '{}': reflectance ({}, {}, {}) is outside [0, 1]",
                                 m.name, r[0], r[1], r[2]));
  if (!finite_nonneg(m.emission))
    throw InputError(at.file, at.line,
                     fmt::format("material '{}': emission ({}, {}, {}) is negative or not finite",
                                 m.name, m.emission[0], m.emission[1], m.emission[2]));
  if (const double top = m.emission.maxCoeff(); top > 0 && top < kMinExitance)
    throw InputError(
        at.file, at.line,
        fmt::format("material '{}': emission ({:g}, {:g}, {:g}) is below {:g} (results are "
                    "32-bit floats; the solution scales with the emission: give it in larger "
                    "units)",
                    m.name, m.emission[0], m.emission[1], m.emission[2], kMinExitance));
  if ((m.emission > kMaxExitance).any())
    throw InputError(
        at.file, at.line,
        fmt::format("material '{}': emission ({:g}, {:g}, {:g}) is above {:g} "
                    "(results are 32-bit floats, and interreflection multiplies it)",
                    m.name, m.emission[0], m.emission[1], m.emission[2], kMaxExitance));
  scene_.materials.push_back(std::move(m));
  return static_cast<std::uint32_t>(scene_.materials.size() - 1);
}

std::uint32_t SceneBuilder::default_material() {
  ++defaulted_faces_;
  if (default_material_ == UINT32_MAX) {
    Material m;
    m.name = "(default grey 0.5)";
    scene_.materials.push_back(m);
    default_material_ = static_cast<std::uint32_t>(scene_.materials.size() - 1);
  }
  return default_material_;
}

void SceneBuilder::add_polygon(std::span<const std::uint32_t> idx, std::uint32_t material,
                               const SourceLoc& at) {
  if (idx.size() < 3)
    throw InputError(at.file, at.line,
                     fmt::format("a face needs at least 3 vertices, this one has {}", idx.size()));
  if (idx.size() > kMaxPolygonVertices)
    throw InputError(at.file, at.line,
                     fmt::format("a face of {} vertices: at most {} are taken (give it as "
                                 "several polygons)",
                                 idx.size(), kMaxPolygonVertices));
  for (std::uint32_t i : idx)
    if (i >= scene_.vertices.size())
      throw InputError(at.file, at.line,
                       fmt::format("vertex index {} is out of range (there are {} vertices)", i + 1,
                                   scene_.vertices.size()));
  if (material >= scene_.materials.size())
    throw InputError(at.file, at.line, fmt::format("material index {} is out of range", material));

  throw_if_interrupted();  // (one atomic load: cheap beside a polygon's checks)
  std::vector<Vec3> p;
  p.reserve(idx.size());
  for (std::uint32_t i : idx) p.push_back(scene_.vertices[i]);
  // A polygon that crosses or retraces itself has no one area or orientation (a
  // bow-tie's lobes cancel, a pentagram counts its centre twice): dropped, before the
  // area test could call a bow-tie a sliver (core/scene/self_overlap.h).
  if (const SelfOverlap o = find_self_overlap(p); o.found) {
    if (self_overlapping_faces_++ == 0)
      first_self_overlap_ = fmt::format("{}:{}: {}", at.file, at.line, o.what);
    return;
  }
  // Zero area, relative to the face's own size (edge lengths), is degenerate.
  double perimeter2 = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    perimeter2 += (p[(i + 1) % p.size()] - p[i]).squaredNorm();
  const double area = polygon_area(p);
  if (!(area > kSliverAreaRatio * perimeter2)) {
    // A face of no area at all, or a sliver (kSliverAreaRatio), whose normal cannot be
    // trusted. They were all called zero-area.
    ++(area > 0 ? sliver_faces_ : degenerate_faces_);
    return;
  }
  // The same polygon again (McGuire's Cornell box repeats a side face of each block
  // under a "Bottom Face" comment): both copies would reflect and emit, doubling that
  // face's light (the blocks' probes near the floor came out 8-11 % too bright). The
  // reversed order is another polygon: the other side of a sheet.
  std::vector<double> key = cycle_key(p);
  if (!seen_.insert(std::move(key)).second) {
    ++duplicate_faces_;
    return;
  }
  ++polygons_;  // the faces emitted below come from this input polygon
  if (idx.size() == 3) {
    emit_face(idx, material);
  } else if (relative_nonplanarity(p) <= kPlanarTolerance && is_convex(p)) {
    emit_face(idx, material);
  } else {
    ++triangulated_faces_;
    triangulate(idx, material);
  }
}

void SceneBuilder::add_polygon(std::span<const Vec3> pts, std::uint32_t material,
                               const SourceLoc& at) {
  std::vector<std::uint32_t> idx;
  idx.reserve(pts.size());
  for (const Vec3& p : pts) idx.push_back(add_vertex(p, at));
  add_polygon(idx, material, at);
}

void SceneBuilder::emit_face(std::span<const std::uint32_t> idx, std::uint32_t material) {
  Face f;
  f.first = static_cast<std::uint32_t>(scene_.indices.size());
  f.count = static_cast<std::uint32_t>(idx.size());
  f.material = material;
  scene_.indices.insert(scene_.indices.end(), idx.begin(), idx.end());
  scene_.faces.push_back(f);
  source_.push_back(polygons_);
}

// Ear clipping in the polygon's best-fit plane. Works for simple (non
// self-intersecting) polygons, convex or not; for a bad polygon it falls back to a
// fan so that nothing is lost silently (degenerate ears are dropped later). Only a
// reflex corner can lie inside an ear of a simple polygon, so the test for an ear
// asks a k-d tree of the reflex corners (core/base/kd_tree_2d.h) for those in its box;
// the ring is a linked list, and the walk goes on from where the last ear was cut.
// (Restarting the walk and testing every corner made a 50,000-corner polygon take 39 s;
// a grid of the reflex corners, tested for each ear's box, took 303 s for a comb of
// 600,002 corners, whose long slanted ears over the base cover most corners; the tree,
// asked for the ear itself, 0.6 s, or 1.9 s with teeth 2,000 long.)
void SceneBuilder::triangulate(std::span<const std::uint32_t> idx, std::uint32_t material) {
  const std::size_t n = idx.size();
  std::vector<Vec3> p;
  for (std::uint32_t i : idx) p.push_back(scene_.vertices[i]);
  const Vec3 nrm = polygon_normal(p);
  const Vec3 u = nrm.unitOrthogonal();
  const Vec3 v = nrm.cross(u);
  std::vector<Eigen::Vector2d> q;
  for (const Vec3& x : p) q.emplace_back(x.dot(u), x.dot(v));
  auto add_tri = [&](std::size_t a, std::size_t b, std::size_t c) {
    const std::uint32_t t[3] = {idx[a], idx[b], idx[c]};
    const Vec3 tp[3] = {p[a], p[b], p[c]};
    if (polygon_area(tp) > 0) emit_face(t, material);
  };
  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  const auto is_reflex = [&](std::size_t i) { return orient2d(q[prev[i]], q[i], q[next[i]]) <= 0; };
  std::vector<char> reflex(n);
  for (std::size_t i = 0; i < n; ++i) reflex[i] = is_reflex(i) ? 1 : 0;
  // The reflex corners, indexed once; a corner that stops being reflex, or is cut, is
  // skipped by its flag (cutting an ear never makes a corner reflex).
  std::vector<std::size_t> reflex_corners;
  for (std::size_t i = 0; i < n; ++i)
    if (reflex[i]) reflex_corners.push_back(i);
  const KdTree2 tree(q, std::move(reflex_corners));
  std::vector<char> cut(n, 0);
  const auto ear = [&](std::size_t a, std::size_t b, std::size_t c) {
    if (orient2d(q[a], q[b], q[c]) <= 0) return false;  // reflex corner
    const Eigen::Vector2d blo = q[a].cwiseMin(q[b]).cwiseMin(q[c]);
    const Eigen::Vector2d bhi = q[a].cwiseMax(q[b]).cwiseMax(q[c]);
    // A node's box may hold a blocking corner when it meets the ear's box and is not
    // wholly outside one of its edges: orient2d is largest over the box at the corner
    // chosen by its coefficients' signs (and evaluated there as it is for a corner, so
    // rounding never prunes a box holding a corner the test below would find).
    const auto beyond = [&](const Eigen::Vector2d& p0, const Eigen::Vector2d& p1,
                            const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
      const Eigen::Vector2d d = p1 - p0;
      const Eigen::Vector2d best(d.y() < 0 ? hi.x() : lo.x(), d.x() > 0 ? hi.y() : lo.y());
      return orient2d(p0, p1, best) < 0;
    };
    const auto may_block = [&](const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
      if ((hi.array() < blo.array()).any() || (lo.array() > bhi.array()).any()) return false;
      return !beyond(q[a], q[b], lo, hi) && !beyond(q[b], q[c], lo, hi) &&
             !beyond(q[c], q[a], lo, hi);
    };
    return tree.for_each_where(may_block, [&](std::size_t o) {
      if (cut[o] || !reflex[o] || o == a || o == b || o == c) return true;
      // Copies of the ear's own corners (a polygon with a hole written as one loop
      // with a seam repeats two vertices) do not block it; other points block it when
      // inside or on its boundary.
      if (q[o] == q[a] || q[o] == q[b] || q[o] == q[c]) return true;
      return !(orient2d(q[a], q[b], q[o]) >= 0 && orient2d(q[b], q[c], q[o]) >= 0 &&
               orient2d(q[c], q[a], q[o]) >= 0);
    });
  };
  std::size_t left = n, at = 0, since_cut = 0;
  for (std::size_t step = 1; left > 3 && since_cut < left; ++step) {
    poll_interrupt(step);
    const std::size_t a = prev[at], c = next[at];
    if (!ear(a, at, c)) {
      at = c;
      ++since_cut;
      continue;
    }
    add_tri(a, at, c);
    cut[at] = 1;
    next[a] = c;
    prev[c] = a;
    --left;
    reflex[a] = is_reflex(a) ? 1 : 0;
    reflex[c] = is_reflex(c) ? 1 : 0;
    at = a;  // the corner before may be an ear now
    since_cut = 0;
  }
  // What is left (a triangle, or a ring ear clipping could not finish) as a fan.
  std::vector<std::size_t> ring;
  for (std::size_t k = 0, i = at; k < left; ++k, i = next[i]) ring.push_back(i);
  for (std::size_t k = 1; k + 1 < ring.size(); ++k) add_tri(ring[0], ring[k], ring[k + 1]);
}

Scene SceneBuilder::finish(const std::string& file) {
  if (defaulted_faces_ > 0)
    warn(fmt::format("{} face(s) named no material and got the default grey (0.5)",
                     defaulted_faces_));
  if (degenerate_faces_ > 0)
    warn(fmt::format("{} degenerate (zero-area) face(s) dropped", degenerate_faces_));
  if (sliver_faces_ > 0)
    warn(
        fmt::format("{} sliver face(s) dropped (area below {:g} of the squared edge lengths: "
                    "too thin for a reliable normal)",
                    sliver_faces_, kSliverAreaRatio));
  if (self_overlapping_faces_ > 0)
    warn(
        fmt::format("{} self-overlapping polygon(s) dropped (the first at {}): a polygon whose "
                    "boundary crosses or retraces itself covers part of its area twice or with "
                    "both orientations; give it as simple polygons",
                    self_overlapping_faces_, first_self_overlap_));
  if (duplicate_faces_ > 0)
    warn(
        fmt::format("{} duplicate face(s) dropped (the same vertices in the same order as an "
                    "earlier face: a coincident copy would reflect and emit the same light "
                    "twice)",
                    duplicate_faces_));
  if (triangulated_faces_ > 0)
    warn(fmt::format("{} non-planar or non-convex polygon(s) triangulated", triangulated_faces_));
  if (scene_.faces.empty())
    throw InputError(file, 0, "the scene has no polygon with positive area");
  // What a later face shares with an earlier one in its plane is cut out of it;
  // reported when the area is more than 1e-3 of the scene's: builtin:office and
  // builtin:lab hold a few hundred small overlaps of boxes (0.1 and 0.2 units² of 720
  // and 1,690), below that.
  const CoplanarCuts c = remove_coplanar_overlaps(scene_, source_);
  if (c.faces_cut > 0 && c.area > kCoplanarOverlapShare * scene_.total_area())
    warn(fmt::format(
        "{} face(s) lay in one plane with an earlier face, facing the same way, and "
        "overlapped it ({:.3g} units² in common; the first near ({:.4g}, {:.4g}, {:.4g})): "
        "the shared area is solved once, as part of the earlier face{}{}",
        c.faces_cut, c.area, c.first.x(), c.first.y(), c.first.z(),
        c.faces_dropped > 0
            ? fmt::format("; {} lay wholly under earlier faces and were dropped", c.faces_dropped)
            : std::string(),
        c.pieces > 0
            ? fmt::format("; the rest of the others is kept as {} convex piece(s)", c.pieces)
            : std::string()));
  // What could not be cut (a face that would need more than kMaxOverlapPieces pieces),
  // from the same pass.
  if (c.left_pairs > 0 && c.left_area > kCoplanarOverlapShare * scene_.total_area())
    warn(fmt::format(
        "{} pair(s) of faces lie in one plane, face the same way and overlap ({:.3g} "
        "units² in common; the first near ({:.4g}, {:.4g}, {:.4g})): each is solved "
        "as its own surface, so the area they share reflects and emits twice; give "
        "each surface once",
        c.left_pairs, c.left_area, c.left_first.x(), c.left_first.y(), c.left_first.z()));
  if (scene_.emitter_count() == 0) warn(kNoEmitterWarning);
  return std::move(scene_);
}

}  // namespace hrad
