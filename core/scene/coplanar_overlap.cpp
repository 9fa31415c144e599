#include "core/scene/coplanar_overlap.h"

#include "core/base/interrupt.h"
#include "core/scene/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <span>
#include <tuple>
#include <vector>

namespace hrad {

namespace {

using Point = Eigen::Vector2d;

double area(const std::vector<Point>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Point& x = p[i];
    const Point& y = p[(i + 1) % p.size()];
    a += x.x() * y.y() - x.y() * y.x();
  }
  return 0.5 * a;
}

// The part of convex polygon `a` to the left of the line p -> q (right of it when
// `left` is false); a point on the line counts as left.
std::vector<Point> clip_half(const std::vector<Point>& a, const Point& p, const Point& q,
                             bool left) {
  std::vector<Point> out;
  const auto side = [&](const Point& x) {
    const double d = orient2d(p, q, x);
    return left ? d : -d;
  };
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Point& s = a[i];
    const Point& t = a[(i + 1) % a.size()];
    const double ds = side(s), dt = side(t);
    if (ds >= 0) out.push_back(s);
    if ((ds >= 0) != (dt >= 0)) out.push_back(s + (ds / (ds - dt)) * (t - s));
  }
  return out;
}

// The part of convex polygon `a` inside convex polygon `b`, both counter-clockwise
// (Sutherland-Hodgman).
std::vector<Point> clip(std::vector<Point> a, const std::vector<Point>& b) {
  for (std::size_t e = 0; e < b.size() && !a.empty(); ++e)
    a = clip_half(a, b[e], b[(e + 1) % b.size()], true);
  return a;
}

// Convex polygon `a` less convex polygon `b`, as convex pieces: for each edge of `b`,
// what of `a` lies outside it and inside the edges before it.
std::vector<std::vector<Point>> subtract(std::vector<Point> a, const std::vector<Point>& b) {
  std::vector<std::vector<Point>> pieces;
  for (std::size_t e = 0; e < b.size() && a.size() >= 3; ++e) {
    const Point &p = b[e], &q = b[(e + 1) % b.size()];
    std::vector<Point> out = clip_half(a, p, q, false);
    if (out.size() >= 3 && area(out) > 0) pieces.push_back(std::move(out));
    a = clip_half(a, p, q, true);
  }
  return pieces;
}

struct Flat {
  std::size_t face;
  std::vector<Point> p;  // counter-clockwise in the plane's frame
  Point lo, hi;
  double area;
};

struct Frame {
  Vec3 n, u, v;  // (u, v, n) right-handed: faces are counter-clockwise in (u, v)
};

struct Plane {
  Frame frame;
  std::vector<Flat> flats;
};

// Faces by plane: the normal to 1e-6 and the offset to 1e-7 of the diagonal; only
// planes with two faces or more.
std::vector<std::vector<std::size_t>> plane_groups(const Scene& scene) {
  std::vector<std::vector<std::size_t>> out;
  const double diag = scene.bounds().diagonal();
  if (!(diag > 0)) return out;
  std::map<std::tuple<long long, long long, long long, long long>, std::vector<std::size_t>> planes;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Vec3 n = scene.face_normal(f);
    const double d = n.dot(scene.vertices[scene.indices[scene.faces[f].first]]);
    const auto q = [](double x, double step) {  // clamped: llround of 1e30 has no value
      return std::llround(std::clamp(x / step, -9e18, 9e18));
    };
    planes[{q(n.x(), 1e-6), q(n.y(), 1e-6), q(n.z(), 1e-6), q(d, 1e-7 * diag)}].push_back(f);
  }
  for (auto& [key, group] : planes)
    if (group.size() >= 2) out.push_back(std::move(group));
  return out;
}

// One plane's faces of positive area, in the plane's frame (built one plane at a time:
// a scene's faces all at once took a cabin's load past its memory limit).
Plane make_plane(const Scene& scene, const std::vector<std::size_t>& group) {
  Plane pl;
  pl.frame.n = scene.face_normal(group.front());
  pl.frame.u = pl.frame.n.unitOrthogonal();
  pl.frame.v = pl.frame.n.cross(pl.frame.u);
  pl.flats.reserve(group.size());
  for (const std::size_t f : group) {
    Flat fl{f, {}, Point::Constant(INFINITY), Point::Constant(-INFINITY), 0};
    for (const Vec3& x : scene.face_vertices(f)) {
      fl.p.emplace_back(x.dot(pl.frame.u), x.dot(pl.frame.v));
      fl.lo = fl.lo.cwiseMin(fl.p.back());
      fl.hi = fl.hi.cwiseMax(fl.p.back());
    }
    fl.area = area(fl.p);
    if (fl.area > 0) pl.flats.push_back(std::move(fl));
  }
  return pl;
}

// Calls visit(a, b) for each pair of a plane's faces whose boxes overlap and that come
// from different input polygons, in a sweep sorted by the boxes' lower x (which
// reorders `flats`), at most kMaxOverlapChecks candidates.
template <class Visit>
void for_each_candidate(std::vector<Flat>& flats, std::span<const std::uint32_t> source,
                        Visit visit) {
  std::sort(flats.begin(), flats.end(), [](const Flat& a, const Flat& b) {
    return a.lo.x() != b.lo.x() ? a.lo.x() < b.lo.x() : a.face < b.face;
  });
  std::size_t checks = 0;
  for (std::size_t i = 0; i < flats.size() && checks < kMaxOverlapChecks; ++i) {
    poll_interrupt(i);
    for (std::size_t j = i + 1; j < flats.size() && flats[j].lo.x() < flats[i].hi.x(); ++j) {
      if (++checks >= kMaxOverlapChecks) break;
      poll_interrupt(checks);
      const Flat &a = flats[i], &b = flats[j];
      if (b.lo.y() >= a.hi.y() || a.lo.y() >= b.hi.y()) continue;
      if (!source.empty() && source[a.face] == source[b.face]) continue;
      visit(a, b);
    }
  }
}

// Whether two faces share enough area to count as overlapping.
bool shares_area(double shared, double a, double b) { return shared > 1e-6 * std::min(a, b); }

// A piece too thin or too small to keep: a sliver by the builder's test
// (kSliverAreaRatio) or below 1e-9 of its face's area.
bool negligible(const std::vector<Point>& p, double face_area) {
  double edges2 = 0;
  for (std::size_t i = 0; i < p.size(); ++i) edges2 += (p[(i + 1) % p.size()] - p[i]).squaredNorm();
  const double a = area(p);
  return !(a > kSliverAreaRatio * edges2) || !(a > 1e-9 * face_area);
}

// Per cut face, its remains as convex pieces in its plane's frame.
using Remains = std::map<std::size_t, std::pair<Frame, std::vector<std::vector<Point>>>>;

// A later face b cut by its earlier neighbours (sorted by face index here): its pieces,
// whether any cut it, and whether it made more than kMaxOverlapPieces (then left whole).
struct FaceCut {
  std::vector<std::vector<Point>> pieces;
  bool cut = false, too_many = false;
};
FaceCut cut_face(const Flat& b, std::vector<std::pair<const Flat*, double>>& earlier) {
  std::sort(earlier.begin(), earlier.end(),
            [](const auto& x, const auto& y) { return x.first->face < y.first->face; });
  FaceCut fc;
  fc.pieces = {b.p};
  for (const auto& [a, shared] : earlier) {
    poll_interrupt(a->face);
    std::vector<std::vector<Point>> next;
    for (std::vector<Point>& piece : fc.pieces) {
      if (!shares_area(area(clip(piece, a->p)), a->area, b.area)) {
        next.push_back(std::move(piece));
        continue;
      }
      fc.cut = true;
      for (std::vector<Point>& rest : subtract(std::move(piece), a->p))
        if (!negligible(rest, b.area)) next.push_back(std::move(rest));
    }
    fc.pieces = std::move(next);
    if (fc.pieces.size() > kMaxOverlapPieces) {
      fc.too_many = true;
      break;
    }
  }
  return fc;
}

// The faces of one plane's group that share area with earlier ones, cut into `remains`,
// with what was cut or left in `r`.
void cut_plane(const Scene& scene, const std::vector<std::size_t>& group,
               const std::vector<std::uint32_t>& source, CoplanarCuts& r, Remains& remains) {
  Plane pl = make_plane(scene, group);
  // Each later face (by face index) with its earlier neighbours that share area with
  // it, and the area each shares (for the report of what is not cut); then cut in
  // input order.
  struct Cutters {
    const Flat* later = nullptr;
    std::vector<std::pair<const Flat*, double>> earlier;
  };
  std::map<std::size_t, Cutters> cutters;
  for_each_candidate(pl.flats, source, [&](const Flat& a, const Flat& b) {
    const double shared = area(clip(a.p, b.p));
    if (!shares_area(shared, a.area, b.area)) return;
    const bool a_first = a.face < b.face;
    Cutters& c = cutters[a_first ? b.face : a.face];
    c.later = a_first ? &b : &a;
    c.earlier.emplace_back(a_first ? &a : &b, shared);
  });
  for (auto& [face, c] : cutters) {
    FaceCut fc = cut_face(*c.later, c.earlier);
    if (fc.too_many) {  // left whole: each pair it makes with an earlier face is reported
      for (const auto& [a, shared] : c.earlier) {
        if (r.left_pairs++ == 0) r.left_first = polygon_centroid(scene.face_vertices(a->face));
        r.left_area += shared;
      }
      continue;
    }
    if (!fc.cut) continue;
    double left = 0;
    for (const auto& piece : fc.pieces) left += area(piece);
    if (r.faces_cut++ == 0) r.first = polygon_centroid(scene.face_vertices(face));
    r.area += std::max(0.0, c.later->area - left);
    if (fc.pieces.empty()) ++r.faces_dropped;
    r.pieces += fc.pieces.size();
    remains[face] = {pl.frame, std::move(fc.pieces)};
  }
}

// The faces again, in their order, each cut face replaced by its pieces; a piece's
// corner that is one of its face's own corners keeps that vertex.
void replace_cut_faces(Scene& scene, std::vector<std::uint32_t>& source, const Remains& remains,
                       std::size_t pieces) {
  std::vector<Face> faces;
  std::vector<std::uint32_t> indices, sources;
  faces.reserve(scene.faces.size() + pieces);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Face& old = scene.faces[f];
    const auto it = remains.find(f);
    if (it == remains.end()) {
      Face kept = old;
      kept.first = static_cast<std::uint32_t>(indices.size());
      indices.insert(indices.end(), scene.indices.begin() + old.first,
                     scene.indices.begin() + old.first + old.count);
      faces.push_back(kept);
      sources.push_back(source[f]);
      continue;
    }
    const Frame& pl = it->second.first;
    const Vec3 n = scene.face_normal(f);
    const double d = n.dot(scene.vertices[scene.indices[old.first]]);
    for (const std::vector<Point>& piece : it->second.second) {
      Face nf = old;
      nf.first = static_cast<std::uint32_t>(indices.size());
      nf.count = static_cast<std::uint32_t>(piece.size());
      for (const Point& x : piece) {
        std::uint32_t id = UINT32_MAX;
        for (std::uint32_t k = 0; k < old.count && id == UINT32_MAX; ++k) {
          const std::uint32_t vi = scene.indices[old.first + k];
          const Vec3& c = scene.vertices[vi];
          if (c.dot(pl.u) == x.x() && c.dot(pl.v) == x.y()) id = vi;
        }
        if (id == UINT32_MAX) {
          // In the face's own plane: along the plane's normal to n . p = d.
          const Vec3 inplane = x.x() * pl.u + x.y() * pl.v;
          const Vec3 p = inplane + ((d - n.dot(inplane)) / n.dot(pl.n)) * pl.n;
          id = static_cast<std::uint32_t>(scene.vertices.size());
          scene.vertices.push_back(p);
        }
        indices.push_back(id);
      }
      faces.push_back(nf);
      sources.push_back(source[f]);
    }
  }
  scene.faces = std::move(faces);
  scene.indices = std::move(indices);
  source = std::move(sources);
}

}  // namespace

CoplanarCuts remove_coplanar_overlaps(Scene& scene, std::vector<std::uint32_t>& source) {
  CoplanarCuts r;
  if (source.size() != scene.faces.size()) {  // not given: every face its own polygon
    source.resize(scene.faces.size());
    std::iota(source.begin(), source.end(), std::uint32_t{0});
  }
  Remains remains;
  for (const std::vector<std::size_t>& group : plane_groups(scene))
    cut_plane(scene, group, source, r, remains);
  if (!remains.empty()) replace_cut_faces(scene, source, remains, r.pieces);
  return r;
}

}  // namespace hrad
