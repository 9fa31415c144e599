// PathTracer: an independent Monte Carlo reference for probe irradiance. It shares no
// code with the hierarchical solver: it reads only the Scene (core/scene/scene.h) and asks
// the one Embree file (core/raycast/ray_scene.h) for first hits and occlusion.
//
// Estimator. With exitance E and reflectance rho (Material), a diffuse surface point y
// has radiance L(y) = (E(y) + rho(y) H(y)) / pi, where H is the irradiance arriving at
// y. The irradiance at a probe (x, n) is H(x) = integral of L cos over the hemisphere
// of n. One path from x estimates it with both strategies of the direct part combined
// by multiple importance sampling (balance heuristic):
//   - next-event estimation: one point z drawn on an emitting polygon (polygon chosen
//     in proportion to area x largest exitance channel, then uniformly by area), shadow
//     ray x -> z, term (E(z) / pi) cos_x cos_z / r^2 / p_area(z), weighted
//     p_l / (p_l + p_b) with p_l = p_area r^2 / cos_z and p_b = cos_x / pi;
//   - a cosine-weighted direction (pdf p_b = cos / pi, which cancels the 1/pi of L) to
//     the first hit y: its exitance E(y) counts with weight p_b / (p_b + p_l), its
//     reflectance multiplies the path throughput, and the path continues at y.
// Both weighted terms are bounded by E, so the estimator has bounded variance even at
// points next to an emitter's edge (where plain NEE's cos cos / r^2 blows up: in the
// furnace, where every wall emits, plain NEE underestimated by 2% at 4 SE).
// Polygons emit and reflect on their front side only (the side their normal points
// to), as in the solver: a ray that reaches a polygon's back ends the path (black).
// Russian roulette from bounce `rr_depth` on, survival probability min(1, largest
// throughput channel); a hard cap of kMaxBounces bounces (bias rho^4096, negligible).
//
// Statistics and determinism. A probe is estimated in batches of `batch_size` paths;
// batch b of probe i draws its random numbers from a generator seeded by
// hash(seed, i, b) alone. The standard error per channel is the standard deviation of
// the batch means over sqrt(batches). Work proceeds in rounds: every unconverged probe
// gets the batches it is predicted to need (at least min_batches more, at most 4x what it
// has, at most max_samples), the batches of a round run in parallel, then each probe is
// tested in batch order. So results are bit-identical for any thread count.
// A probe has converged when, in every channel, SE <= rel_error x max(|mean|, floor),
// where floor is abs_floor or, when abs_floor <= 0, 1e-3 x the channel's mean
// irradiance over all probes (so dark probes do not demand endless samples).
#pragma once

#include "core/base/geometry.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/probes.h"
#include "core/scene/scene.h"

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace hrad {

struct PathTracerOptions {
  double rel_error = 1e-2;               ///< target relative standard error per probe, > 0
  double abs_floor = 0;                  ///< absolute SE floor; <= 0: 1e-3 x mean probe irradiance
  std::uint64_t max_samples = 1u << 22;  ///< paths per probe at most
  std::uint64_t seed = 1;                ///< mixed into every probe's random numbers
  int threads = 1;                       ///< OpenMP threads (results do not depend on it)
  int batch_size = 64;                   ///< paths per batch, >= 1
  int min_batches = 16;                  ///< batches before a probe is first tested, >= 2
  int rr_depth = 3;                      ///< bounces before Russian roulette starts
};

/// The estimate at one probe.
struct ProbeEstimate {
  Rgb irradiance = Rgb::Zero();  ///< mean over all paths (W per unit area)
  Rgb std_error = Rgb::Zero();   ///< standard error of that mean, per channel
  std::uint64_t samples = 0;     ///< paths traced
  /// Paths cut at kMaxBounces: the scene keeps (nearly) all the light it receives
  /// (reflectance 1 in a closed scene has no finite solution), and the estimate is a
  /// truncated sum. Such a probe is never converged, and is not sampled further.
  std::uint64_t truncated = 0;
  bool converged = false;  ///< the relative-error target was met
};

struct ReferenceResult {
  std::vector<ProbeEstimate> probes;
  Rgb floor = Rgb::Zero();  ///< the absolute floor used in the convergence test
  int rounds = 0;
  std::uint64_t rays = 0;  ///< rays cast (first hits and shadow rays)
  double seconds = 0;      ///< wall time
};

/// Called after each round with a label and the fraction of probes converged.
using ReferenceProgressFn = std::function<void(const std::string& phase, double fraction)>;

class PathTracer {
 public:
  static constexpr int kMaxBounces = 4096;

  /// Throws std::invalid_argument when the scene has no polygon.
  explicit PathTracer(const Scene& scene);

  /// One independent batch: the mean of `paths` single-path estimates at `probe` with
  /// the generator seeded by (seed, stream, batch). Thread-safe.
  /// `truncated`, when given, gets the number of paths cut at kMaxBounces.
  [[nodiscard]] Rgb batch_mean(const Probe& probe, std::uint64_t seed, std::uint64_t stream,
                               std::uint64_t batch, int paths, int rr_depth = 3,
                               std::uint64_t* truncated = nullptr) const;

  /// Estimates every probe until converged or out of samples (see the file comment).
  /// Throws std::invalid_argument for options out of range.
  [[nodiscard]] ReferenceResult estimate(std::span<const Probe> probes,
                                         const PathTracerOptions& options,
                                         const ReferenceProgressFn& progress = {}) const;

  [[nodiscard]] std::uint64_t rays_cast() const { return rays_.rays_cast(); }

 private:
  struct Emitter {
    std::uint32_t face;
    double cdf;  ///< cumulative selection probability up to and including this one
    double pdf;  ///< probability of choosing this emitter
  };
  class Rng;
  /// `face`: the polygon x lies on (RayScene::kNoPolygon for a probe), whose hits the
  /// shadow ray ignores, like the emitter's own.
  Rgb direct(const Vec3& x, const Vec3& n, std::uint32_t face, Rng& rng) const;
  /// Solid-angle density at x of next-event estimation choosing point z on `face`.
  double light_pdf(std::uint32_t face, const Vec3& x, const Vec3& z) const;
  Vec3 sample_on_face(std::uint32_t face, Rng& rng) const;
  /// One path's estimate; `cut`: it reached kMaxBounces.
  Rgb trace(const Probe& probe, Rng& rng, int rr_depth, bool& cut) const;

  const Scene& scene_;
  RayScene rays_;
  std::vector<Vec3> normals_;
  std::vector<double> areas_;
  std::vector<Emitter> emitters_;
  std::vector<double> emit_pdf_;  ///< per face: probability that NEE picks it (0: not an emitter)
};

}  // namespace hrad
