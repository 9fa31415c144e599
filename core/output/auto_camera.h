// The automatic camera: a view chosen with rays (core/raycast/ray_scene.h) for scenes that
// bring none (OBJ, MGF), or when asked for with `--camera auto`.
//
// The rule (also in docs/cli.md, "The camera"):
//  1. Candidates: a jittered 5 x 5 x 5 grid over the scene's bounding box, one point
//     per cell (fixed seed, so the choice is deterministic).
//  2. Each candidate casts kSphereRays rays spread over the sphere. It is in free
//     space when at most a quarter of the rays that hit something hit a back face
//     (from inside a solid, most do) and nothing is closer than 0.5% of the scene's
//     diagonal D; it is enclosed when at most 4% of its rays escape.
//  3. Which view:
//     - some free candidate is enclosed (a closed scene): the best interior view;
//     - else, a side of the bounding box is open (Scene::open_side_camera: the Cornell
//       box, a single object): the outside view through it;
//     - else, some candidate is free with under half its rays escaping (a room
//       without a ceiling): the best interior view among those;
//     - else Scene::default_camera().
//  4. Best interior view: the kKeep candidates with the largest mean free distance
//     (over their sphere rays) each look along 8 horizontal directions at two
//     pitches (level and 20 degrees down), up = the scene's up axis, fov 60 degrees.
//     A view is scored by a 8 x 6 grid of rays over its frustum: the sum over rays
//     that hit a front face of min(t, D/2) / D (seeing far, into the room), times
//     the number of differently oriented surfaces hit (of the 26 axis and diagonal
//     directions, at most 6), so that a view at a single wall loses. The highest score
//     wins (ties: the first); look is the point the central ray hits.
#pragma once

#include "core/scene/scene.h"

#include <cstdint>
#include <string>

namespace hrad {

struct AutoCamera {
  Camera camera;
  /// How step 3 decided: "interior", "open side", "default".
  std::string view;
  std::uint64_t rays = 0;  ///< rays cast to choose it
  double seconds = 0;      ///< wall time to choose it (with the ray scene's build, if any)
};

class RayScene;

/// The automatic camera of `scene` (rule above), with rays cast into `rays`, a ray
/// scene of its faces (RayScene::from_scene(scene); the solver's will do). Throws
/// std::invalid_argument when `rays` does not hold one polygon per face.
[[nodiscard]] AutoCamera automatic_camera(const Scene& scene, const RayScene& rays);
/// The same with a ray scene of its own (RayScene::Build::Fast).
[[nodiscard]] AutoCamera automatic_camera(const Scene& scene);

}  // namespace hrad
