// Solver: the hierarchical radiosity run as the CLI and experiments see it.
// It owns the hierarchy built over a Scene, runs `options.iterations` refinement
// iterations (refine all links through the chosen scheduler and oracle, then
// propagate), and exposes the solution for the result files.
#pragma once

#include "core/config/options.h"
#include "core/output/run_stats.h"
#include "core/output/smooth_shading.h"
#include "core/scene/probes.h"
#include "core/scene/render_mesh.h"
#include "core/scene/scene.h"

#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

namespace hrad {

/// Called as work progresses: a short phase label ("iteration 2: refine") and a
/// fraction in [0,1] of the whole run. Called from the solver's own thread only.
using ProgressFn = std::function<void(const std::string& phase, double fraction)>;

class RayScene;

/// max_memory_gb in bytes; 0 gives three quarters of the physical memory (sysconf), and
/// no limit (0) where that cannot be read.
std::uint64_t memory_limit_bytes(double gb);
/// "the limit of L GB (max_memory_gb; ...)": how every check against memory_limit_bytes
/// names the limit it refuses.
std::string memory_limit_text(std::uint64_t limit_bytes);

class Solver {
 public:
  /// Throws std::invalid_argument for an unknown scheduler/oracle name or an option
  /// out of range (the message names the option). The scene must outlive the solver.
  Solver(const Scene& scene, const SolverOptions& options, ProgressFn progress = {});
  ~Solver();
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  /// Runs every iteration; returns what was measured.
  RunStats run();

  /// The ray scene of the scene's faces (prim ids are face indices) that visibility
  /// uses, for other queries about the scene (the automatic camera). Thread-safe.
  [[nodiscard]] const RayScene& ray_scene() const;

  /// The leaf elements as a mesh for render.png and solution.ply, shaded as
  /// core/output/smooth_shading.h describes.
  [[nodiscard]] RenderMesh render_mesh(Shading shading = Shading::Smooth) const;
  /// Every link as (receiver id, source id), sorted: the link set, which must not
  /// depend on the scheduler or the thread count.
  [[nodiscard]] std::vector<std::pair<std::uint64_t, std::uint64_t>> link_ids() const;

  /// The leaf surface elements of the solution (for tests and comparisons).
  struct Leaf {
    std::uint64_t id;
    std::uint32_t face;
    double area;
    Vec3 center;
    Rgb radiosity;
  };
  [[nodiscard]] std::vector<Leaf> leaves() const;

  /// Irradiance (W per unit area) at each probe by a final gather over the solved
  /// radiosity, independent of the mesh at the probe. Reports "probes: i of n" to
  /// `progress` (from one thread); throws Interrupted after an interrupt.
  [[nodiscard]] std::vector<Rgb> probe_irradiance(std::span<const Probe> probes,
                                                  const ProgressFn& progress = {}) const;

  /// Where probe i's irradiance comes from (hrad solve --explain-probe): the same final
  /// gather as probe_irradiance, as JSON: the total, the `top` leaves that give it most
  /// (form factor, visibility, radiosity, share), and for the strongest of them every
  /// element above it (surface pieces, then clusters) with its push and cluster weights
  /// and its `top` strongest links. Read after run(). docs/results.md has the fields.
  [[nodiscard]] nlohmann::json explain_probe(std::size_t i, const Probe& probe, int top) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hrad
