// The one file that talks to Embree 3. Layout of what is handed to Embree:
//  - one shared float3 vertex buffer holding every input vertex in the normalised
//    frame q = (p - centre) / diagonal (see ray_scene.h);
//  - one triangle geometry (input triangles, plus fan triangles of polygons with more
//    than 4 vertices) and one quad geometry (input quads), each with a table mapping
//    Embree's primID back to the input polygon.
// The scene is built with RTC_SCENE_FLAG_ROBUST (watertight traversal: no rays leak
// through edges shared by neighbouring polygons) and high build quality, since hrad
// casts many rays against a static scene (medium for RayScene::Build::Fast).
// Ignored polygons (occluded()/intersect() arguments, with their twins) are rejected by
// a per-query filter: RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION plus an IgnoreContext that
// begins with the RTCIntersectContext Embree sees; the same filter rejects intersect()'s
// hits on the back of a polygon that has a twin (the twin's front is met at the same
// distance). Queries that need neither set no filter.
#include "core/raycast/ray_scene.h"

#include "core/base/box_tree.h"
#include "core/base/interrupt.h"
#include "core/raycast/face_contacts.h"
#include "core/raycast/face_twins.h"
#include "core/scene/scene.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace hrad {
namespace {

const char* error_name(RTCError e) {
  switch (e) {
    case RTC_ERROR_NONE: return "none";
    case RTC_ERROR_UNKNOWN: return "unknown";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognised";
}

/// Stripes of the ray counter. Each thread adds to one stripe chosen once per thread,
/// so threads rarely share a cache line; the sum over stripes is the total.
constexpr std::size_t kCounterStripes = 32;

std::size_t thread_stripe() {
  static std::atomic<std::size_t> next{0};
  thread_local const std::size_t stripe =
      next.fetch_add(1, std::memory_order_relaxed) % kCounterStripes;
  return stripe;
}

/// An intersection context carrying the polygons to ignore and the tables that map
/// Embree's (geomID, primID) back to input polygons. Embree hands the filter the
/// pointer to `base`, the first member, so the filter can cast it back.
struct IgnoreContext {
  RTCIntersectContext base;
  const std::uint32_t* tri_poly = nullptr;
  const std::uint32_t* quad_poly = nullptr;
  unsigned quad_geom = RTC_INVALID_GEOMETRY_ID;
  std::uint32_t ignore[4] = {RayScene::kNoPolygon, RayScene::kNoPolygon, RayScene::kNoPolygon,
                             RayScene::kNoPolygon};
  /// Set for intersect() in a scene with twins: reject hits on the back of a polygon
  /// that has a twin. Polygon normals (world frame: the same directions) and twins.
  const std::uint32_t* twin = nullptr;
  const Vec3* normal = nullptr;
};
static_assert(std::is_standard_layout_v<IgnoreContext>);

/// Context filter: rejects hits on the ignored polygons (valid[i] = 0).
void ignore_filter(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const IgnoreContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned geom = RTCHitN_geomID(args->hit, args->N, i);
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const std::uint32_t poly = geom == c->quad_geom ? c->quad_poly[prim] : c->tri_poly[prim];
    if (poly == c->ignore[0] || poly == c->ignore[1] || poly == c->ignore[2] ||
        poly == c->ignore[3]) {
      args->valid[i] = 0;
    } else if (c->twin && c->twin[poly] != RayScene::kNoPolygon) {
      const Vec3 d(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                   RTCRayN_dir_z(args->ray, args->N, i));
      if (d.dot(c->normal[poly]) > 0) args->valid[i] = 0;
    }
  }
}

float to_float_distance(double t) {
  // Conversion of a double beyond float's range is undefined; saturate to +inf.
  return t >= static_cast<double>(std::numeric_limits<float>::max())
             ? std::numeric_limits<float>::infinity()
             : static_cast<float>(t);
}

}  // namespace

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  unsigned tri_geom = RTC_INVALID_GEOMETRY_ID;
  unsigned quad_geom = RTC_INVALID_GEOMETRY_ID;

  Vec3 centre = Vec3::Zero();
  double diagonal = 0;   // world units
  double inv_scale = 1;  // world -> normalised frame
  double tolerance = 0;  // scale(), world units
  // kEndpointEpsilon * scale() in the normalised frame; and whether the frame is the
  // bulk's (then a ray's exclusion also grows with its distance from the centre).
  double epsilon = kEndpointEpsilon;
  bool local = false;
  std::size_t polygons = 0;

  // Embree primID -> input polygon (and fan triangle for polygons of > 4 vertices).
  std::vector<std::uint32_t> tri_poly, tri_sub, quad_poly;
  // Plane of each input polygon in world coordinates (unit normal n, n.x = offset):
  // used to recompute hit distances in double precision. n is zero when degenerate.
  std::vector<Vec3> normal;
  std::vector<double> offset;
  // Twin of each input polygon (kNoPolygon), empty when no polygon has one.
  std::vector<std::uint32_t> twin;
  // find_face_contacts over the polygons, at kContactReach * diagonal.
  std::vector<std::uint8_t> contact;
  // The polygons' bounds in world coordinates, for polygon_boxes().
  BoxTree near;
  // coincidence() of each polygon, world units.
  std::vector<double> coincide;

  struct alignas(64) Stripe {
    std::atomic<std::uint64_t> rays{0};
  };
  mutable std::array<Stripe, kCounterStripes> counters;

  // Written by Embree's error callback (possibly from its worker threads).
  std::mutex error_mutex;
  std::string last_error;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  static void on_error(void* user, RTCError code, const char* what) {
    auto* self = static_cast<Impl*>(user);
    std::lock_guard lock(self->error_mutex);
    self->last_error = fmt::format("{} ({})", what ? what : "", error_name(code));
  }

  /// Throws if Embree recorded an error on this thread since the last check.
  void check(const char* during) {
    const RTCError e = rtcGetDeviceError(device);
    if (e == RTC_ERROR_NONE) return;
    std::lock_guard lock(error_mutex);
    throw std::runtime_error(fmt::format("Embree error while {}: {}", during,
                                         last_error.empty() ? error_name(e) : last_error));
  }

  std::uint32_t twin_of(std::uint32_t p) const { return p >= twin.size() ? kNoPolygon : twin[p]; }

  /// The end-point exclusion, normalised, for a ray from normalised point a to b: what
  /// single precision resolves there, if that is more than `epsilon` (only in a bulk's
  /// frame: elsewhere every point lies within 1/2 of the centre, where it never is).
  double exclusion(const Vec3& a, const Vec3& b) const {
    if (!local) return epsilon;
    return std::max(epsilon, resolution(a, b));
  }

  // What single precision tells apart near the points a and b of the normalised frame:
  // kPrecisionUlps units in the last place of the larger's largest coordinate.
  static double resolution(const Vec3& a, const Vec3& b) {
    const double far = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
    return kPrecisionUlps * far * std::numeric_limits<float>::epsilon();
  }

  /// A context that ignores polygons a and b and their twins, and with `front_of_twins`
  /// the backs of polygons with a twin (no filter when there is nothing to reject).
  void init_context(IgnoreContext& c, std::uint32_t a, std::uint32_t b, bool front_of_twins) const {
    rtcInitIntersectContext(&c.base);
    c.tri_poly = tri_poly.data();
    c.quad_poly = quad_poly.data();
    c.quad_geom = quad_geom;
    c.ignore[0] = a;
    c.ignore[1] = b;
    c.ignore[2] = twin_of(a);
    c.ignore[3] = twin_of(b);
    if (front_of_twins && !twin.empty()) {
      c.twin = twin.data();
      c.normal = normal.data();
    }
    if (a != kNoPolygon || b != kNoPolygon || c.twin) c.base.filter = &ignore_filter;
  }

  // The frame of the normalised coordinates and the tolerances: about the bounding box
  // `box` of the referenced vertices, or about the bulk (kLocalFrame).
  void set_frame(const Aabb& box, const Aabb* bulk) {
    if (box.empty()) return;
    centre = box.center();
    diagonal = box.diagonal();
    tolerance = diagonal;
    if (diagonal > 0) inv_scale = 1.0 / diagonal;
    if (bulk && !bulk->empty() && bulk->diagonal() > 0 &&
        diagonal > kLocalFrame * bulk->diagonal()) {
      local = true;
      centre = bulk->center();
      tolerance = kLocalFrame * bulk->diagonal();
      epsilon = kEndpointEpsilon * tolerance * inv_scale;
    }
  }

  // What counts as coincident with each polygon (its bounds[i]): the global reach, unless
  // the polygon is small beside the scene (kCoincidentShare of its own diagonal), but
  // never under what single precision can tell apart where it lies.
  void set_coincidence(const std::vector<Aabb>& bounds) {
    coincide.resize(bounds.size());
    const double reach = 3 * kEndpointEpsilon * tolerance;
    for (std::size_t i = 0; i < bounds.size(); ++i) {
      const Aabb& b = bounds[i];
      const double noise =
          resolution((b.lo - centre) * inv_scale, (b.hi - centre) * inv_scale) / inv_scale;
      coincide[i] = std::min(reach, std::max(noise, kCoincidentShare * b.diagonal()));
    }
  }

  // The Embree device, scene and geometries of the vertices (in the normalised frame)
  // and the triangle and quad index lists.
  void build_embree(std::span<const Vec3> vertices, const std::vector<std::uint32_t>& tri_idx,
                    const std::vector<std::uint32_t>& quad_idx, Build build) {
    device = rtcNewDevice(nullptr);
    if (!device)
      throw std::runtime_error(fmt::format("Embree: cannot create a device ({})",
                                           error_name(rtcGetDeviceError(nullptr))));
    rtcSetDeviceErrorFunction(device, &Impl::on_error, this);
    if (!rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED))
      throw std::runtime_error(
          "Embree was built without filter functions (needed to ignore polygons)");
    scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(
        scene, build == Build::Fast ? RTC_BUILD_QUALITY_MEDIUM : RTC_BUILD_QUALITY_HIGH);
    check("creating the scene");

    if (polygons > 0) {
      // Vertex buffers must stay readable with one 16-byte load at the last vertex:
      // allocate one spare float.
      RTCBuffer vb = rtcNewBuffer(device, (3 * vertices.size() + 1) * sizeof(float));
      if (auto* f = static_cast<float*>(vb ? rtcGetBufferData(vb) : nullptr)) {
        for (std::size_t i = 0; i < vertices.size(); ++i) {
          const Vec3 q = (vertices[i] - centre) * inv_scale;
          for (int c = 0; c < 3; ++c) f[3 * i + c] = static_cast<float>(q[c]);
        }
        f[3 * vertices.size()] = 0;
      }
      try {
        check("allocating the vertex buffer");
        if (!tri_idx.empty())
          tri_geom = add_geometry(RTC_GEOMETRY_TYPE_TRIANGLE, vb, vertices.size(), tri_idx, 3);
        if (!quad_idx.empty())
          quad_geom = add_geometry(RTC_GEOMETRY_TYPE_QUAD, vb, vertices.size(), quad_idx, 4);
      } catch (...) {
        if (vb) rtcReleaseBuffer(vb);
        throw;
      }
      rtcReleaseBuffer(vb);  // the geometries hold their own references
    }
    rtcCommitScene(scene);
    check("building the BVH");
  }

  void count_ray() const { counters[thread_stripe()].rays.fetch_add(1, std::memory_order_relaxed); }

  unsigned add_geometry(RTCGeometryType type, RTCBuffer vertices, std::size_t vertex_count,
                        const std::vector<std::uint32_t>& index_data, unsigned per_prim) {
    RTCGeometry g = rtcNewGeometry(device, type);
    rtcSetGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices, 0,
                         3 * sizeof(float), vertex_count);
    const RTCFormat format = per_prim == 3 ? RTC_FORMAT_UINT3 : RTC_FORMAT_UINT4;
    auto* idx = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, format,
                                per_prim * sizeof(std::uint32_t), index_data.size() / per_prim));
    if (idx) std::copy(index_data.begin(), index_data.end(), idx);
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);  // the scene holds its own reference
    check("building a geometry");
    return id;
  }
};

RayScene::RayScene(std::span<const Vec3> vertices, std::span<const std::uint32_t> indices,
                   std::span<const PolygonRange> polygons, Build build,
                   std::span<const std::uint32_t> twins, const Aabb* bulk)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.polygons = polygons.size();
  if (!twins.empty()) {
    if (twins.size() != polygons.size())
      throw std::invalid_argument("RayScene: the twin table needs one entry per polygon");
    bool any = false;
    for (std::size_t i = 0; i < twins.size(); ++i) {
      if (twins[i] == kNoPolygon) continue;
      if (twins[i] >= twins.size() || twins[i] == i || twins[twins[i]] != i)
        throw std::invalid_argument(fmt::format("RayScene: polygon {}'s twin is not paired", i));
      any = true;
    }
    if (any) m.twin.assign(twins.begin(), twins.end());
  }
  for (const Vec3& p : vertices)
    if (!p.allFinite()) throw std::invalid_argument("RayScene: non-finite vertex coordinate");

  // Validate, and collect the bounding box of the referenced vertices and each polygon's.
  Aabb box;
  std::vector<Aabb> bounds(polygons.size());
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    poll_interrupt(i);  // each phase below checks too: a million polygons take seconds
    const PolygonRange& r = polygons[i];
    if (r.count < 3 || std::size_t{r.first} + r.count > indices.size())
      throw std::invalid_argument(fmt::format("RayScene: polygon {} has a bad index range", i));
    for (std::uint32_t k = 0; k < r.count; ++k) {
      if (indices[r.first + k] >= vertices.size())
        throw std::invalid_argument(fmt::format("RayScene: polygon {} indexes past the end", i));
      bounds[i].extend(vertices[indices[r.first + k]]);
    }
    box.extend(bounds[i]);
  }
  m.set_frame(box, bulk);

  m.contact = find_face_contacts(vertices, indices, polygons, m.twin, kContactReach * m.tolerance);
  m.set_coincidence(bounds);
  throw_if_interrupted();
  m.near = BoxTree(std::move(bounds));
  throw_if_interrupted();

  // Split into Embree primitives and record the double-precision planes.
  std::vector<std::uint32_t> tri_idx, quad_idx;
  m.normal.resize(polygons.size());
  m.offset.resize(polygons.size());
  std::vector<Vec3> corners;
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    poll_interrupt(i);
    const PolygonRange& r = polygons[i];
    const std::uint32_t* v = indices.data() + r.first;
    corners.clear();
    for (std::uint32_t k = 0; k < r.count; ++k) corners.push_back(vertices[v[k]]);
    m.normal[i] = polygon_normal(corners);
    m.offset[i] = m.normal[i].dot(polygon_centroid(corners));
    const auto poly = static_cast<std::uint32_t>(i);
    if (r.count == 4) {
      quad_idx.insert(quad_idx.end(), v, v + 4);
      m.quad_poly.push_back(poly);
    } else {
      for (std::uint32_t s = 0; s + 2 < r.count; ++s) {
        tri_idx.insert(tri_idx.end(), {v[0], v[s + 1], v[s + 2]});
        m.tri_poly.push_back(poly);
        m.tri_sub.push_back(s);
      }
    }
  }

  throw_if_interrupted();
  m.build_embree(vertices, tri_idx, quad_idx, build);  // (Embree's build cannot stop)
}

RayScene RayScene::from_scene(const Scene& scene, Build build) {
  std::vector<PolygonRange> polys;
  polys.reserve(scene.faces.size());
  for (const Face& f : scene.faces) polys.push_back({f.first, f.count});
  const std::vector<std::uint32_t> twins = find_twins(scene);
  static_assert(kNoTwin == kNoPolygon);
  throw_if_interrupted();
  const Aabb bulk = scene.bulk_bounds();
  throw_if_interrupted();
  return RayScene(scene.vertices, scene.indices, polys, build, twins, &bulk);
}

RayScene::RayScene(RayScene&&) noexcept = default;
RayScene& RayScene::operator=(RayScene&&) noexcept = default;
RayScene::~RayScene() = default;

double RayScene::scale() const { return impl_->tolerance; }

bool RayScene::local_frame() const { return impl_->local; }

std::size_t RayScene::polygon_count() const { return impl_->polygons; }

std::uint32_t RayScene::twin(std::uint32_t poly) const { return impl_->twin_of(poly); }

const Vec3& RayScene::normal(std::uint32_t poly) const { return impl_->normal.at(poly); }

bool RayScene::lies_against(std::uint32_t poly) const { return impl_->contact.at(poly) != 0; }

double RayScene::coincidence(std::uint32_t poly) const { return impl_->coincide.at(poly); }

bool RayScene::back_coincides(const Vec3& origin, const Vec3& dir, double t,
                              std::uint32_t poly) const {
  if (!lies_against(poly)) return false;  // nothing coincides with it
  const double back_off = 4 * kEndpointEpsilon * scale() / dir.norm();
  // Beyond the hit, only a back within coincidence(poly) (4/3 of it: 4 kEndpointEpsilon
  // scale() at most, as before the hit) lies against it: a room's floor 5 mm above a
  // 200 x 200 ground that faces down is no contact with it.
  const double beyond = 4.0 / 3.0 * coincidence(poly) / dir.norm();
  // (Not from behind the origin: the face it lies on would be met there.)
  const double start = std::max(t - back_off, 0.0);
  const auto twin = intersect(origin + start * dir, dir, t - start + beyond, poly);
  return twin && normal(twin->prim).dot(dir) > 0;
}

const BoxTree& RayScene::polygon_boxes() const { return impl_->near; }

std::uint64_t RayScene::rays_cast() const {
  std::uint64_t n = 0;
  for (const auto& s : impl_->counters) n += s.rays.load(std::memory_order_relaxed);
  return n;
}

bool RayScene::occluded(const Vec3& from, const Vec3& to, std::uint32_t ignore_a,
                        std::uint32_t ignore_b) const {
  const Impl& m = *impl_;
  const Vec3 o = (from - m.centre) * m.inv_scale;
  const Vec3 d = (to - from) * m.inv_scale;
  const double len = d.norm();
  assert(std::isfinite(len) && "occluded() needs finite end points");
  // The exclusion is a distance in the normalised frame; dividing by len turns it into
  // the parameter along d.
  const double epsilon = m.exclusion(o, o + d);
  if (!(len > 2 * epsilon) || m.polygons == 0) return false;
  const double margin = epsilon / len;

  IgnoreContext ctx;
  m.init_context(ctx, ignore_a, ignore_b, /*front_of_twins=*/false);
  RTCRay ray;
  ray.org_x = static_cast<float>(o.x());
  ray.org_y = static_cast<float>(o.y());
  ray.org_z = static_cast<float>(o.z());
  ray.dir_x = static_cast<float>(d.x());
  ray.dir_y = static_cast<float>(d.y());
  ray.dir_z = static_cast<float>(d.z());
  ray.tnear = static_cast<float>(margin);
  ray.tfar = static_cast<float>(1.0 - margin);
  ray.time = 0;
  ray.mask = ~0u;
  ray.id = 0;
  ray.flags = 0;
  rtcOccluded1(m.scene, &ctx.base, &ray);
  m.count_ray();
  return ray.tfar < 0;  // Embree sets tfar to -inf on a hit
}

std::optional<RayHit> RayScene::intersect(const Vec3& origin, const Vec3& dir, double tmax,
                                          std::uint32_t ignore) const {
  const Impl& m = *impl_;
  Vec3 o = (origin - m.centre) * m.inv_scale;
  const Vec3 d = dir * m.inv_scale;
  const double len = d.norm();
  if (!(len > 0) || !std::isfinite(len))
    throw std::invalid_argument("RayScene::intersect: direction must be finite and non-zero");
  double epsilon = m.exclusion(o, o);
  const double tnear = epsilon / len;
  if (m.polygons == 0 || !(tmax >= tnear)) return std::nullopt;
  // From far away (a camera 1e30 from a scene 555 across: 2e27 in the normalised frame,
  // past the 1.8e19 Embree's rays may start at, and its assertion ended the process)
  // the ray starts anew just outside the scene's sphere (radius 1/2 about the centre, 1
  // about a bulk's centre),
  // and its distances count from there.
  double skipped = 0;  // normalised distance along the ray from `o` to the new start
  if (o.cwiseAbs().maxCoeff() > kFarOrigin) {
    const Vec3 u = d / len;
    const double along = -o.dot(u);  // to the point nearest the centre
    if (!(along > 0) || !((o + along * u).norm() <= 1)) return std::nullopt;  // passes by
    // (From the nearest point, not `o + skipped u`: at 1e30, along - 1 is along.)
    skipped = along - 1;
    o = (o + along * u) - u;
    epsilon = m.exclusion(o, o);
    if (!(tmax * len - skipped >= epsilon)) return std::nullopt;
  }
  // Embree takes a unit direction here (its rays must have |dir| below 1.8e18: a
  // direction of length 1 in a scene 1e-20 across is 6e19 in the normalised frame,
  // and its assertion ended the process), with distances along it in the normalised
  // frame; t along `dir` is that distance / len.
  const Vec3 u = d / len;

  IgnoreContext ctx;
  m.init_context(ctx, ignore, kNoPolygon, /*front_of_twins=*/true);
  RTCRayHit rh;
  rh.ray.org_x = static_cast<float>(o.x());
  rh.ray.org_y = static_cast<float>(o.y());
  rh.ray.org_z = static_cast<float>(o.z());
  rh.ray.dir_x = static_cast<float>(u.x());
  rh.ray.dir_y = static_cast<float>(u.y());
  rh.ray.dir_z = static_cast<float>(u.z());
  rh.ray.tnear = static_cast<float>(epsilon);
  rh.ray.tfar = to_float_distance(tmax * len - skipped);
  rh.ray.time = 0;
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(m.scene, &ctx.base, &rh);
  m.count_ray();
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

  RayHit hit;
  if (rh.hit.geomID == m.quad_geom) {
    hit.prim = m.quad_poly[rh.hit.primID];
  } else {
    hit.prim = m.tri_poly[rh.hit.primID];
    hit.sub = m.tri_sub[rh.hit.primID];
  }
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  hit.t = (static_cast<double>(rh.ray.tfar) + skipped) / len;
  // Recompute t in double precision from the polygon's plane, unless the ray grazes
  // the plane (|cos| < 1e-3), where the plane intersection is ill-conditioned.
  const Vec3& n = m.normal[hit.prim];
  const double nd = n.dot(dir);
  if (std::abs(nd) > 1e-3 * dir.norm()) {
    const double t = (m.offset[hit.prim] - n.dot(origin)) / nd;
    if (std::abs(t - hit.t) <= 1e-4 * std::max(hit.t, 1.0 / len)) hit.t = t;
  }
  return hit;
}

}  // namespace hrad
