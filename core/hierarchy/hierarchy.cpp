#include "core/hierarchy/hierarchy.h"

#include "core/base/hash.h"
#include "core/base/interrupt.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <memory>
#include <new>
#include <numeric>

namespace hrad {

std::uint64_t child_id(std::uint64_t parent, std::uint32_t index) {
  return splitmix64_mix(parent * 0x100000001B3ull + index + 0x9E3779B97F4A7C15ull);
}

// Per-worker arenas: blocks of elements in `memory`, never moved, destroyed with
// the hierarchy; link blocks as stored in `staging`, reset once compacted into
// `links`, which release_links() resets.
// Each worker's arenas on lines of their own (allocation writes their cursors).
struct alignas(64) Hierarchy::Arena {
  Arena(int worker, const ArenaPlacement& placement)
      : memory(worker, placement), links(worker, placement), staging(worker, placement) {}
  NodeArena memory;
  NodeArena links;
  NodeArena staging;
  std::vector<std::span<Element>> blocks;
  std::size_t elements = 0;
};

Element* Hierarchy::allocate(std::size_t count, int worker) {
  Arena& a = *arenas_[static_cast<std::size_t>(worker)];
  auto* kids = static_cast<Element*>(a.memory.allocate(count * sizeof(Element), alignof(Element)));
  for (std::size_t i = 0; i < count; ++i) {
    new (kids + i) Element();
    kids[i].home_node = static_cast<std::uint16_t>(a.memory.node_of(kids + i));
  }
  a.blocks.emplace_back(kids, count);
  a.elements += count;
  return kids;
}

Hierarchy::Hierarchy(const Scene& scene, int workers, const ArenaPlacement& placement)
    : scene_(scene) {
  for (int w = 0; w < std::max(workers, 1); ++w)
    arenas_.push_back(std::make_unique<Arena>(w, placement));
  const auto nf = static_cast<std::uint32_t>(scene.faces.size());
  order_.resize(nf);
  std::iota(order_.begin(), order_.end(), 0u);
  std::size_t ngon_corners = 0;
  for (const Face& f : scene.faces)
    if (f.count > 4) ngon_corners += f.count;
  ngon_store_.reserve(ngon_corners);  // never reallocated: elements point into it

  // The build polls for an interrupt (a million polygons take seconds): what it made
  // is destroyed before Interrupted leaves, as ~Hierarchy would.
  try {
    root_ = allocate(1, 0);
    root_->id = 0x68726164;  // "hrad"
    root_->kind = ElementKind::Cluster;
    build_cluster(*root_, 0, nf, 0);

    face_normal_.resize(nf);
    for (std::uint32_t f = 0; f < nf; ++f) {
      poll_interrupt(f);
      face_normal_[f] = scene.face_normal(f);
    }
    find_plane_runs();
    throw_if_interrupted();
    fan_first_.assign(nf, 0);
    for (std::uint32_t f = 0; f < nf; ++f) {
      poll_interrupt(f);
      const Face& face = scene.faces[f];
      if (face.count <= 3) continue;
      fan_first_[f] = static_cast<std::uint32_t>(fan_area_.size());
      auto v = [&](std::uint32_t i) -> const Vec3& {
        return scene.vertices[scene.indices[face.first + i]];
      };
      for (std::uint32_t i = 1; i + 1 < face.count; ++i)
        fan_area_.push_back((v(i) - v(0)).cross(v(i + 1) - v(0)).norm());
    }
  } catch (...) {
    for (const auto& a : arenas_)
      for (std::span<Element> b : a->blocks) std::destroy(b.begin(), b.end());
    throw;
  }
  prefix_area_.assign(nf + 1, 0.0);
  for (std::uint32_t i = 0; i < nf; ++i)
    prefix_area_[i + 1] = prefix_area_[i] + scene.face_area(order_[i]);
}

// Runs of consecutive polygons in cluster order that share a plane and face the same
// way: each polygon's unit normal within round-off of the run's first polygon's (cosine
// above 1 - 1e-12) and every corner within kPlaneTolerance of the scene's diagonal of
// its plane.
void Hierarchy::find_plane_runs() {
  const auto n = static_cast<std::uint32_t>(order_.size());
  plane_run_end_.assign(n, n);
  const double tol = kPlaneTolerance * scene_.bounds().diagonal();
  const auto in_plane_of = [&](std::uint32_t a, std::uint32_t b) {
    const Vec3& na = face_normal_[a];
    if (!(na.dot(face_normal_[b]) > 1 - 1e-12)) return false;
    const Vec3& p0 = scene_.vertices[scene_.indices[scene_.faces[a].first]];
    const Face& fb = scene_.faces[b];
    for (std::uint32_t i = 0; i < fb.count; ++i)
      if (!(std::abs(na.dot(scene_.vertices[scene_.indices[fb.first + i]] - p0)) <= tol))
        return false;
    return true;
  };
  for (std::uint32_t start = 0; start < n;) {
    std::uint32_t end = start + 1;
    while (end < n && in_plane_of(order_[start], order_[end])) ++end;
    std::fill(plane_run_end_.begin() + start, plane_run_end_.begin() + end, end);
    start = end;
  }
}

Hierarchy::~Hierarchy() {
  for (const auto& a : arenas_)
    for (std::span<Element> b : a->blocks) std::destroy(b.begin(), b.end());
}

void Hierarchy::init_surface(Element& e, std::uint32_t face, Element* parent, std::uint64_t id) {
  const Face& f = scene_.faces[face];
  e.id = id;
  e.parent = parent;
  e.kind = ElementKind::Surface;
  e.face = face;
  e.material = f.material;
  e.nverts = static_cast<std::uint16_t>(f.count);
  if (f.count <= 4) {
    for (std::uint32_t i = 0; i < f.count; ++i)
      e.corner[i] = scene_.vertices[scene_.indices[f.first + i]];
  } else {
    const std::size_t at = ngon_store_.size();
    for (std::uint32_t i = 0; i < f.count; ++i)
      ngon_store_.push_back(scene_.vertices[scene_.indices[f.first + i]]);
    e.ngon = ngon_store_.data() + at;
  }
  const auto c = e.corners();
  e.area = polygon_area(c);
  e.normal = polygon_normal(c);
  e.center = polygon_centroid(c);
  for (const Vec3& p : c) e.box.extend(p);
  const Material& m = scene_.materials[f.material];
  e.rho = m.reflectance;
  e.emission = m.emission;
  e.B = m.emission;
}

// Median split along the longest axis of the centroid bounds. Children are built
// into one contiguous block: polygons directly when few remain.
void Hierarchy::build_cluster(Element& c, std::uint32_t begin, std::uint32_t end, int depth) {
  throw_if_interrupted();  // (one relaxed load a cluster)
  c.face = begin;
  c.face_end = end;
  c.depth = static_cast<std::uint8_t>(std::min(depth, 255));
  const std::uint32_t n = end - begin;
  if (n == 0) {
    finish_cluster(c);
    return;
  }
  if (n <= kClusterLeafSize) {
    Element* kids = allocate(n, 0);
    for (std::uint32_t i = 0; i < n; ++i)
      init_surface(kids[i], order_[begin + i], &c, child_id(c.id, i));
    c.child_count = n;
    c.children.store(kids, std::memory_order_release);
    finish_cluster(c);
    return;
  }
  Aabb cb;
  std::vector<Vec3> centroid(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    centroid[i] = polygon_centroid(scene_.face_vertices(order_[begin + i]));
    cb.extend(centroid[i]);
  }
  int axis = 0;
  cb.extent().maxCoeff(&axis);
  // Sort this range by (centroid along axis, face index): deterministic.
  std::vector<std::uint32_t> local(n);
  std::iota(local.begin(), local.end(), 0u);
  std::sort(local.begin(), local.end(), [&](std::uint32_t a, std::uint32_t b) {
    const double ca = centroid[a][axis], cb2 = centroid[b][axis];
    return ca != cb2 ? ca < cb2 : order_[begin + a] < order_[begin + b];
  });
  std::vector<std::uint32_t> sorted(n);
  for (std::uint32_t i = 0; i < n; ++i) sorted[i] = order_[begin + local[i]];
  std::copy(sorted.begin(), sorted.end(), order_.begin() + begin);

  const std::uint32_t mid = begin + n / 2;
  const std::uint32_t ranges[2][2] = {{begin, mid}, {mid, end}};
  Element* kids = allocate(2, 0);
  for (std::uint32_t i = 0; i < 2; ++i) {
    const std::uint32_t b = ranges[i][0], e = ranges[i][1];
    if (e - b == 1) {
      init_surface(kids[i], order_[b], &c, child_id(c.id, i));
    } else {
      kids[i].id = child_id(c.id, i);
      kids[i].parent = &c;
      kids[i].kind = ElementKind::Cluster;
      build_cluster(kids[i], b, e, depth + 1);
    }
  }
  c.child_count = 2;
  c.children.store(kids, std::memory_order_release);
  finish_cluster(c);
}

void Hierarchy::finish_cluster(Element& c) {
  c.area = 0;
  c.box = Aabb{};
  c.dir_area = {};
  Vec3 center = Vec3::Zero();
  Rgb rho = Rgb::Zero(), emission = Rgb::Zero();
  for (Element& k : c.child_span()) {
    c.area += k.area;
    c.box.extend(k.box);
    center += k.area * k.center;
    rho += k.area * k.rho;
    emission += k.area * k.emission;
    if (k.is_cluster()) {
      for (std::size_t i = 0; i < 6; ++i) c.dir_area[i] += k.dir_area[i];
    } else {
      add_by_axis(c.dir_area, k.normal, static_cast<float>(k.area));
    }
  }
  if (c.area > 0) {
    c.center = center / c.area;
    c.rho = rho / c.area;
    c.emission = emission / c.area;
  }
  c.B = c.emission;
}

std::span<Element> Hierarchy::subdivide(Element& e, int worker, LockPool& locks) {
  if (Element* kids = e.children.load(std::memory_order_acquire)) return {kids, e.child_count};
  assert(!e.is_cluster());
  auto guard = locks.lock(&e, worker);
  if (Element* kids = e.children.load(std::memory_order_acquire)) return {kids, e.child_count};

  const auto c = e.corners();
  const std::size_t k = c.size();
  std::vector<std::array<Vec3, 4>> shapes;
  std::vector<int> counts;
  if (k == 3) {
    const Vec3 ab = 0.5 * (c[0] + c[1]), bc = 0.5 * (c[1] + c[2]), ca = 0.5 * (c[2] + c[0]);
    shapes = {{c[0], ab, ca, Vec3::Zero()},
              {ab, c[1], bc, Vec3::Zero()},
              {ca, bc, c[2], Vec3::Zero()},
              {ab, bc, ca, Vec3::Zero()}};
    counts = {3, 3, 3, 3};
  } else {
    // One quad per corner: corner, next edge midpoint, centre, previous edge midpoint.
    // For a quad the centre is the vertex average, so the four children tile it.
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : c) centre += p;
    centre /= static_cast<double>(k);
    if (k > 4) centre = e.center;
    for (std::size_t i = 0; i < k; ++i) {
      const Vec3 next = 0.5 * (c[i] + c[(i + 1) % k]);
      const Vec3 prev = 0.5 * (c[i] + c[(i + k - 1) % k]);
      shapes.push_back({c[i], next, centre, prev});
      counts.push_back(4);
    }
  }
  Element* kids = allocate(shapes.size(), worker);
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    Element& ch = kids[i];
    ch.id = child_id(e.id, static_cast<std::uint32_t>(i));
    ch.parent = &e;
    ch.kind = ElementKind::Surface;
    ch.face = e.face;
    ch.material = e.material;
    ch.depth = static_cast<std::uint8_t>(e.depth + 1);
    ch.nverts = static_cast<std::uint16_t>(counts[i]);
    for (int j = 0; j < counts[i]; ++j) {
      ch.corner[j] = shapes[i][static_cast<std::size_t>(j)];
      ch.box.extend(ch.corner[j]);
    }
    ch.area = polygon_area(ch.corners());
    ch.normal = e.normal;  // children of a planar polygon share its plane
    ch.center = polygon_centroid(ch.corners());
    ch.rho = e.rho;
    ch.emission = e.emission;
    ch.B = e.B;  // until propagation: the parent's (frozen) radiosity
  }
  e.child_count = static_cast<std::uint32_t>(shapes.size());
  e.children.store(kids, std::memory_order_release);
  return {kids, e.child_count};
}

Vec3 Hierarchy::sample_face(std::uint32_t face, double u1, double u2, double u3) const {
  const Face& f = scene_.faces[face];
  auto v = [&](std::uint32_t i) -> const Vec3& {
    return scene_.vertices[scene_.indices[f.first + i]];
  };
  // Fan triangle chosen by area with u3, then a uniform point in it.
  std::uint32_t tri = 1;
  if (f.count > 3) {
    const double* fan = fan_area_.data() + fan_first_[face];  // triangle i at fan[i - 1]
    double total = 0;
    for (std::uint32_t i = 1; i + 1 < f.count; ++i) total += fan[i - 1];
    double target = u3 * total;
    for (tri = 1; tri + 2 < f.count; ++tri) {
      target -= fan[tri - 1];
      if (target < 0) break;
    }
  }
  const double s = std::sqrt(u1);
  return (1 - s) * v(0) + s * (1 - u2) * v(tri) + s * u2 * v(tri + 1);
}

Vec3 Hierarchy::sample_point(const Element& e, double u1, double u2, double u3, const Vec3* toward,
                             std::uint32_t* face) const {
  if (e.is_cluster()) {
    if (e.face == e.face_end) {
      if (face) *face = ~std::uint32_t{0};
      return e.center;
    }
    const double lo = prefix_area_[e.face], hi = prefix_area_[e.face_end];
    std::uint32_t i = e.face;
    double u3b = 0.5;
    double u = u3;
    for (int attempt = 0; attempt < (toward ? kFacingTries : 1); ++attempt) {
      const double target = lo + u * (hi - lo);
      auto it = std::upper_bound(prefix_area_.begin() + e.face, prefix_area_.begin() + e.face_end,
                                 target);
      i = static_cast<std::uint32_t>(
          std::max<std::ptrdiff_t>(it - prefix_area_.begin() - 1, e.face));
      i = std::min(i, e.face_end - 1);
      // Reuse u's leftover precision: remap it within the chosen face's share.
      const double share = prefix_area_[i + 1] - prefix_area_[i];
      u3b = share > 0 ? std::clamp((target - prefix_area_[i]) / share, 0.0, 1.0) : 0.5;
      if (!toward) break;
      const Vec3 p = sample_face(order_[i], u1, u2, u3b);
      if (face_normal_[order_[i]].dot(*toward - p) > 0) {
        if (face) *face = order_[i];
        return p;
      }
      u = std::fmod(u + 0.6180339887498949, 1.0);  // next draw: golden-ratio step
    }
    if (face) *face = order_[i];
    return sample_face(order_[i], u1, u2, u3b);
  }
  if (face) *face = e.face;
  const auto c = e.corners();
  if (c.size() == 4) {
    return (1 - u1) * (1 - u2) * c[0] + u1 * (1 - u2) * c[1] + u1 * u2 * c[2] +
           (1 - u1) * u2 * c[3];
  }
  if (c.size() == 3) {
    const double s = std::sqrt(u1);
    return (1 - s) * c[0] + s * (1 - u2) * c[1] + s * u2 * c[2];
  }
  return sample_face(e.face, u1, u2, u3);  // an input n-gon: same shape as its face
}

std::vector<Element*> Hierarchy::elements() {
  std::vector<Element*> out;
  out.reserve(element_count());
  out.push_back(root_);
  for (std::size_t i = 0; i < out.size(); ++i)
    for (Element& k : out[i]->child_span()) out.push_back(&k);
  return out;
}

std::size_t Hierarchy::element_count() const {
  std::size_t n = 0;
  for (const auto& a : arenas_) n += a->elements;
  return n;
}

std::vector<std::uint64_t> Hierarchy::element_bytes_per_node() const {
  std::vector<std::uint64_t> total;
  for (const auto& a : arenas_) add_bytes_per_node(total, a->memory.bytes_per_node());
  return total;
}

std::vector<std::uint64_t> Hierarchy::link_bytes_per_node() const {
  std::vector<std::uint64_t> total;
  for (const auto& a : arenas_) {
    add_bytes_per_node(total, a->links.bytes_per_node());
    add_bytes_per_node(total, a->staging.bytes_per_node());
  }
  return total;
}

std::size_t Hierarchy::link_bytes() const {
  std::size_t n = 0;
  for (const auto& a : arenas_) n += a->links.bytes_used() + a->staging.bytes_used();
  return n;
}

bool Hierarchy::store_links(Element& r, std::span<const Link> links, int worker) {
  const bool first = r.links.empty();
  r.links.append(links, arenas_[static_cast<std::size_t>(worker)]->staging);
  return first && !links.empty();
}

void Hierarchy::compact_links(Element& r, int worker) {
  r.links.compact(arenas_[static_cast<std::size_t>(worker)]->links);
}

void Hierarchy::reset_link_staging(int worker) {
  arenas_[static_cast<std::size_t>(worker)]->staging.reset();
}

void Hierarchy::release_links(const std::vector<Element*>& elements, int threads) {
  const auto n = static_cast<std::ptrdiff_t>(elements.size());
#pragma omp parallel for num_threads(threads) schedule(static) if (n > 65536)
  for (std::ptrdiff_t i = 0; i < n; ++i) elements[static_cast<std::size_t>(i)]->links.clear();
  for (const auto& a : arenas_) {
    a->links.reset();
    a->staging.reset();
  }
}

std::vector<std::pair<const void*, int>> Hierarchy::sample_pages(std::size_t per_arena) const {
  std::vector<std::pair<const void*, int>> out;
  for (const auto& a : arenas_)
    for (const NodeArena* m : {&a->memory, &a->links, &a->staging}) {
      const auto s = m->sample_pages(per_arena);
      out.insert(out.end(), s.begin(), s.end());
    }
  return out;
}

const NodeArena& Hierarchy::link_arena(int worker) const {
  return arenas_.at(static_cast<std::size_t>(worker))->links;
}

const NodeArena& Hierarchy::link_staging_arena(int worker) const {
  return arenas_.at(static_cast<std::size_t>(worker))->staging;
}

const NodeArena& Hierarchy::arena(int worker) const {
  return arenas_.at(static_cast<std::size_t>(worker))->memory;
}

std::size_t Hierarchy::element_bytes() const {
  return element_count() * sizeof(Element) + ngon_store_.capacity() * sizeof(Vec3) +
         order_.capacity() * sizeof(std::uint32_t) + prefix_area_.capacity() * sizeof(double) +
         face_normal_.capacity() * sizeof(Vec3) + fan_first_.capacity() * sizeof(std::uint32_t) +
         fan_area_.capacity() * sizeof(double);
}

}  // namespace hrad
