// Effects follow the scene: before a run, the solver asks what the scene needs and
// turns off what it does not, each with a reason that stats.json reports under
// "effects". Every shortcut gives the same radiosity as the full computation (to
// round-off; tested in tests/effects_test.cpp); `effects = all` forces the full
// computation for comparison.
//
// | effect          | off when                                    | what is skipped                  |
// |-----------------|---------------------------------------------|----------------------------------|
// | visibility      | the scene is one convex enclosure (every    | every visibility ray: V = 1,     |
// |                 | polygon's plane has all other vertices on   | counted in rays_skipped          |
// |                 | or in front of it), every reflectance is 0  |                                  |
// |                 | (V only weights reflected light), or        |                                  |
// |                 | visibility_rays = 0                         |                                  |
// | interreflection | every reflectance is 0                      | all gather sweeps after the first|
// | colour          | every Kd and Ke is grey (equal channels)    | two of three channels in gather  |
// | emission        | no polygon emits                            | everything: zero solution at once|
// | iterations      | (decided during the run) an iteration       | the remaining iterations         |
// |                 | re-accepted every link, created none and    |                                  |
// |                 | left every radiosity bit-for-bit unchanged  |                                  |
//
// Why a convex enclosure needs no rays: all polygons then lie on the boundary of
// the convex region K where every plane's front side meets. A segment between two
// points of K stays in K, and a polygon's plane bounds K, so the segment can meet
// that plane at an inner point only by lying in the plane altogether (grazing
// pairs, which transport culls as coplanar). Hence nothing blocks it.
//
// Two shortcuts are decided per link rather than per scene and live in transport:
// pairs that face away from each other are culled without rays (always, as
// before), and with `shaft_culling = on` a pair whose shaft holds no polygon gets
// V = 1 without rays (core/transport/shaft.h).
#pragma once

#include "core/config/options.h"
#include "core/scene/scene.h"

#include <array>
#include <string>
#include <utility>

namespace hrad {

/// One effect: computed (on) or skipped (off), and why.
struct Effect {
  bool on = true;
  std::string reason;  ///< why it is off; for an effect that is on, what calls for it
};

struct Effects {
  Effect visibility;       ///< ray-cast visibility between elements
  Effect interreflection;  ///< light reflected more than once (gather sweeps after the first)
  Effect colour;           ///< three colour channels (off: one grey channel, copied)
  Effect emission;         ///< any light at all (off: the solution is zero, nothing is done)
  Effect iterations;       ///< every refinement iteration asked for (off: stopped early)

  /// Every effect with its name (stats.json's "effects" keys), in the order above: what
  /// reports and checks effects walks, so that a new effect is one field and one row.
  [[nodiscard]] std::array<std::pair<const char*, const Effect*>, 5> table() const {
    return {{{"visibility", &visibility},
             {"interreflection", &interreflection},
             {"colour", &colour},
             {"emission", &emission},
             {"iterations", &iterations}}};
  }
};

/// Relative tolerance (of the scene's bounding-box diagonal) within which a vertex
/// counts as on a plane in the convexity test.
inline constexpr double kConvexTolerance = 1e-9;

/// True when every polygon's plane has all the other polygons' vertices on or in
/// front of it (within kConvexTolerance x diagonal). Each plane is first tested
/// against the 26 vertices extreme along the axes and diagonals (almost every
/// non-convex scene fails there: 0.08 s for 186,638 polygons), then against every
/// vertex, but only while polygons x vertices <= 2e8; a larger scene that passes
/// the quick test counts as not convex (visibility stays on, which is always
/// exact). When false and `why` is given, it receives the reason.
bool is_convex_enclosure(const Scene& scene, std::string* why = nullptr);

/// Decides each effect for `scene` under `options` (effects, visibility_rays). The
/// `iterations` effect is left on: the solver decides it while running.
Effects analyse_effects(const Scene& scene, const SolverOptions& options);

}  // namespace hrad
