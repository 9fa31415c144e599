// PathTracer: see path_tracer.h for the estimator, the batching and the stopping rule.
#include "core/reference/path_tracer.h"

#include "core/base/clock.h"
#include "core/base/hash.h"
#include "core/base/interrupt.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace hrad {

namespace {

/// Orthonormal basis around unit n (Duff et al. 2017, branchless).
void basis(const Vec3& n, Vec3& t, Vec3& b) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double c = n.x() * n.y() * a;
  t = Vec3(1.0 + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
  b = Vec3(c, sign + n.y() * n.y() * a, -n.y());
}

}  // namespace

/// xoshiro256** seeded through splitmix64 from (seed, stream, batch).
class PathTracer::Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t stream, std::uint64_t batch) {
    std::uint64_t s = seed;
    s = splitmix64(s) ^ stream;
    s = splitmix64(s) ^ batch;
    for (std::uint64_t& w : s_) w = splitmix64(s);
  }
  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t next() {
    const std::uint64_t r = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return r;
  }
  std::uint64_t s_[4];
};

PathTracer::PathTracer(const Scene& scene) : scene_(scene), rays_(RayScene::from_scene(scene)) {
  if (scene.faces.empty()) throw std::invalid_argument("PathTracer: the scene has no polygon");
  const std::size_t n = scene.faces.size();
  normals_.resize(n);
  areas_.resize(n);
  emit_pdf_.assign(n, 0.0);
  double total = 0;
  for (std::size_t f = 0; f < n; ++f) {
    normals_[f] = scene.face_normal(f);
    areas_[f] = scene.face_area(f);
    const Material& m = scene.face_material(f);
    if (m.emits() && areas_[f] > 0) {
      const double w = areas_[f] * m.emission.maxCoeff();
      total += w;
      emitters_.push_back({static_cast<std::uint32_t>(f), total, w});
    }
  }
  for (Emitter& e : emitters_) {
    e.cdf /= total;
    e.pdf /= total;
    emit_pdf_[e.face] = e.pdf;
  }
  if (!emitters_.empty()) emitters_.back().cdf = 1.0;
}

Vec3 PathTracer::sample_on_face(std::uint32_t face, Rng& rng) const {
  // Fan triangles from vertex 0 (the polygon is convex), one chosen by area.
  const Face& fc = scene_.faces[face];
  const auto v = [&](std::uint32_t k) -> const Vec3& {
    return scene_.vertices[scene_.indices[fc.first + k]];
  };
  std::uint32_t tri = 1;
  if (fc.count > 3) {
    double pick = rng.uniform() * 2.0 * areas_[face];
    for (tri = 1; tri + 2 < fc.count; ++tri) {
      pick -= (v(tri) - v(0)).cross(v(tri + 1) - v(0)).norm();
      if (pick < 0) break;
    }
  }
  const double s = std::sqrt(rng.uniform()), t = rng.uniform();
  return (1 - s) * v(0) + s * (1 - t) * v(tri) + s * t * v(tri + 1);
}

double PathTracer::light_pdf(std::uint32_t face, const Vec3& x, const Vec3& z) const {
  const double pa = emit_pdf_[face] / areas_[face];
  if (!(pa > 0)) return 0;
  const Vec3 d = x - z;
  const double r2 = d.squaredNorm();
  const double cos_z = normals_[face].dot(d) / std::sqrt(r2);
  return cos_z > 0 ? pa * r2 / cos_z : 0;
}

Rgb PathTracer::direct(const Vec3& x, const Vec3& n, std::uint32_t face, Rng& rng) const {
  if (emitters_.empty()) return Rgb::Zero();
  const double u = rng.uniform();
  const auto it = std::lower_bound(emitters_.begin(), emitters_.end(), u,
                                   [](const Emitter& e, double val) { return e.cdf <= val; });
  const Emitter& e = it == emitters_.end() ? emitters_.back() : *it;
  const Vec3 z = sample_on_face(e.face, rng);
  const Vec3 d = z - x;
  const double r2 = d.squaredNorm();
  if (!(r2 > 0)) return Rgb::Zero();
  const double r = std::sqrt(r2);
  const double cos_x = n.dot(d) / r;
  const double cos_z = -normals_[e.face].dot(d) / r;
  if (cos_x <= 0 || cos_z <= 0) return Rgb::Zero();
  // A segment between points on two planar polygons cannot hit either of them again:
  // ignoring them removes single-precision grazing self-hits (see RayScene::occluded).
  if (rays_.occluded(x, z, face, static_cast<std::uint32_t>(e.face))) return Rgb::Zero();
  // The end-point exclusion skips a face coincident with the emitter's at z: from inside
  // a box pushed against an emitting wall the wall must not show.
  if (rays_.back_coincides(x, d / r, r, e.face)) return Rgb::Zero();
  // (E / pi) cos_x cos_z / r^2 / p_area times the balance weight p_l / (p_l + p_b),
  // with p_l = p_area r^2 / cos_z and p_b = cos_x / pi (solid angle): E cos_x / (pi (p_l + p_b)).
  const double p_l = e.pdf / areas_[e.face] * r2 / cos_z;
  const double p_b = cos_x / std::numbers::pi;
  return scene_.face_material(e.face).emission * (cos_x / (std::numbers::pi * (p_l + p_b)));
}

Rgb PathTracer::trace(const Probe& probe, Rng& rng, int rr_depth, bool& cut) const {
  Rgb sum = Rgb::Zero();
  Rgb beta = Rgb::Ones();
  Vec3 x = probe.p, n = probe.n;
  std::uint32_t face = RayScene::kNoPolygon;  // the polygon x lies on
  int bounce = 0;
  for (; bounce < kMaxBounces; ++bounce) {
    sum += beta * direct(x, n, face, rng);
    // Cosine-weighted direction around n.
    const double r = std::sqrt(rng.uniform()), phi = 2 * std::numbers::pi * rng.uniform();
    Vec3 t, b;
    basis(n, t, b);
    const Vec3 dir =
        r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1 - r * r)) * n;
    const std::optional<RayHit> hit =
        rays_.intersect(x, dir, std::numeric_limits<double>::infinity(), face);
    if (!hit) break;
    const Vec3& nf = normals_[hit->prim];
    const double cos_y = -dir.dot(nf);
    if (cos_y <= 0) break;  // the back of a polygon is black
    if (rays_.back_coincides(x, dir, hit->t, hit->prim))
      break;  // ... and so is a front that coincides with a back (the inside of a solid)
    const Vec3 y = x + hit->t * dir;
    const Material& m = scene_.face_material(hit->prim);
    if (m.emits()) {
      // The emission seen along the cosine direction (estimate E), with the balance
      // weight p_b / (p_b + p_l) that complements next-event estimation's.
      const double p_b = n.dot(dir) / std::numbers::pi;
      const double p_l = light_pdf(hit->prim, x, y);
      if (p_b > 0) sum += beta * m.emission * (p_b / (p_b + p_l));
    }
    beta *= m.reflectance;
    if (!(beta > 0).any()) break;
    if (bounce + 1 >= rr_depth) {
      const double q = std::min(1.0, beta.maxCoeff());
      if (rng.uniform() >= q) break;
      beta /= q;
    }
    x = y;
    n = nf;
    face = static_cast<std::uint32_t>(hit->prim);
  }
  cut = bounce == kMaxBounces;  // every break ends a path before the cap
  return sum;
}

Rgb PathTracer::batch_mean(const Probe& probe, std::uint64_t seed, std::uint64_t stream,
                           std::uint64_t batch, int paths, int rr_depth,
                           std::uint64_t* truncated) const {
  Rng rng(seed, stream, batch);
  Rgb sum = Rgb::Zero();
  for (int k = 0; k < paths; ++k) {
    bool cut = false;
    sum += trace(probe, rng, rr_depth, cut);
    if (cut && truncated) ++*truncated;
  }
  return sum / static_cast<double>(std::max(paths, 1));
}

namespace {

// A probe's estimate from its batch means (at least two), in batch order: their mean, the
// standard error of that mean, the samples, and the paths cut at the bounce cap.
void summarise(const std::vector<Rgb>& means, const std::vector<std::uint64_t>& cut, int batch_size,
               ProbeEstimate& e) {
  const auto nb = static_cast<double>(means.size());
  Rgb m = Rgb::Zero();
  for (const Rgb& v : means) m += v;
  m /= nb;
  Rgb var = Rgb::Zero();
  for (const Rgb& v : means) var += (v - m).square();
  var /= (nb - 1);
  e.irradiance = m;
  e.std_error = (var / nb).sqrt();
  e.samples = means.size() * static_cast<std::uint64_t>(batch_size);
  e.truncated = 0;
  for (const std::uint64_t t : cut) e.truncated += t;
}

}  // namespace

ReferenceResult PathTracer::estimate(std::span<const Probe> probes, const PathTracerOptions& o,
                                     const ReferenceProgressFn& progress) const {
  if (!(o.rel_error > 0) || !std::isfinite(o.rel_error))
    throw std::invalid_argument(fmt::format("rel_error {} must be > 0", o.rel_error));
  if (o.batch_size < 1) throw std::invalid_argument("batch_size must be >= 1");
  if (o.min_batches < 2) throw std::invalid_argument("min_batches must be >= 2");
  if (o.threads < 1) throw std::invalid_argument("threads must be >= 1");
  if (o.max_samples < static_cast<std::uint64_t>(o.batch_size) * o.min_batches)
    throw std::invalid_argument(
        fmt::format("max_samples {} is below batch_size x min_batches = {}", o.max_samples,
                    static_cast<std::uint64_t>(o.batch_size) * o.min_batches));
  const auto t0 = Clock::now();
  const std::uint64_t rays0 = rays_cast();
  const std::size_t np = probes.size();
  const std::uint64_t max_batches = o.max_samples / static_cast<std::uint64_t>(o.batch_size);

  // Per probe: the batch means in batch order, and how many batches it should have.
  std::vector<std::vector<Rgb>> means(np);
  std::vector<std::vector<std::uint64_t>> cut(np);  // truncated paths per batch
  std::vector<std::uint64_t> target(np, static_cast<std::uint64_t>(o.min_batches));
  std::vector<char> done(np, 0);
  ReferenceResult res;
  res.probes.resize(np);

  struct Work {
    std::uint32_t probe;
    std::uint64_t batch;
  };
  for (;;) {
    std::vector<Work> work;
    for (std::size_t i = 0; i < np; ++i) {
      if (done[i]) continue;
      means[i].resize(target[i]);
      cut[i].resize(target[i]);
      for (std::uint64_t b = res.probes[i].samples / o.batch_size; b < target[i]; ++b)
        work.push_back({static_cast<std::uint32_t>(i), b});
    }
    if (work.empty()) break;
    ++res.rounds;
    const auto nw = static_cast<std::ptrdiff_t>(work.size());
#pragma omp parallel for num_threads(o.threads) schedule(dynamic, 1)
    for (std::ptrdiff_t w = 0; w < nw; ++w) {
      if (interrupted()) continue;  // the rest of the round is skipped, then abandoned
      const Work& k = work[static_cast<std::size_t>(w)];
      means[k.probe][k.batch] = batch_mean(probes[k.probe], o.seed, k.probe, k.batch, o.batch_size,
                                           o.rr_depth, &cut[k.probe][k.batch]);
    }
    throw_if_interrupted();

    // Statistics, in batch order (deterministic).
    Rgb floor_sum = Rgb::Zero();
    for (std::size_t i = 0; i < np; ++i) {
      summarise(means[i], cut[i], o.batch_size, res.probes[i]);
      floor_sum += res.probes[i].irradiance.abs();
    }
    res.floor = o.abs_floor > 0
                    ? Rgb::Constant(o.abs_floor)
                    : Rgb(1e-3 * floor_sum / static_cast<double>(std::max<std::size_t>(np, 1)));
    std::size_t converged = 0;
    for (std::size_t i = 0; i < np; ++i) {
      ProbeEstimate& e = res.probes[i];
      const Rgb allowed = o.rel_error * e.irradiance.abs().max(res.floor);
      // ratio > 1: not there yet. A channel with zero SE and zero allowance is done.
      double ratio = 0;
      for (int c = 0; c < 3; ++c)
        if (e.std_error[c] > 0)
          ratio = std::max(ratio, allowed[c] > 0 ? e.std_error[c] / allowed[c]
                                                 : std::numeric_limits<double>::infinity());
      e.converged = ratio <= 1 && e.truncated == 0;
      const std::uint64_t nb = means[i].size();
      // A floor change may reopen a probe; one with truncated paths has no finite answer.
      done[i] = e.converged || nb >= max_batches || e.truncated > 0;
      if (!done[i]) {
        // SE ~ 1/sqrt(batches): predict the batches needed, with 10% margin.
        const double want = std::isfinite(ratio) ? 1.1 * ratio * ratio * static_cast<double>(nb)
                                                 : 4.0 * static_cast<double>(nb);
        const std::uint64_t next =
            std::clamp<std::uint64_t>(static_cast<std::uint64_t>(std::ceil(std::min(want, 1e18))),
                                      nb + static_cast<std::uint64_t>(o.min_batches), 4 * nb);
        target[i] = std::min(next, max_batches);
      }
      converged += e.converged;
    }
    if (progress)
      progress(fmt::format("round {}: {} of {} probes converged", res.rounds, converged, np),
               np ? static_cast<double>(converged) / static_cast<double>(np) : 1.0);
  }
  res.rays = rays_cast() - rays0;
  res.seconds = seconds_since(t0);
  return res;
}

}  // namespace hrad
