// SolverOptions: every knob of a run, one plain struct with defaults. The CLI,
// the JSON config and `--set key=value` all write into it through options_io.h,
// which rejects unknown keys by name.
//
// | key                 | type   | default      | meaning                                                    |
// |---------------------|--------|--------------|------------------------------------------------------------|
// | scheduler           | string | "stack"      | refinement task order (a name in scheduler_names())        |
// | block_size          | int    | 10           | tasks a refiner takes (and buffers) per scheduler visit    |
// | threads             | int    | 1            | refiner threads                                            |
// | oracle              | string | "bf"         | refinement oracle (a name in oracle_names())               |
// | eps                 | double | 1e-4         | oracle threshold, relative to total emitted power          |
// | min_area            | double | 1e-4         | smallest element, relative to total scene area             |
// | iterations          | int    | 4            | refinement iterations (the paper uses 4)                   |
// | visibility_rays     | int    | 4            | rays per link for the visibility estimate (0: no rays)     |
// | pin                 | string | "none"       | thread pinning (none, compact, scatter, node-round-robin)  |
// | placement           | string | "first-touch"| memory placement (first-touch, interleave, node0)          |
// | pool_order          | string | "submitted"  | central pools sort each batch: submitted, address, subtree |
// | seed                | uint64 | 1            | mixed into every per-link random number                    |
// | gather_tolerance    | double | 1e-6         | propagation stops when the estimated remaining change is   |
// |                     |        |              | below this fraction of the largest radiosity (iterations   |
// |                     |        |              | before the last: max(this, 1e-4), core/solver/solver.cpp)  |
// | max_gather_sweeps   | int    | 100000       | hard cap on gather + push-pull sweeps per iteration        |
// | cluster_model       | string | "directional"| cluster projected areas: isotropic (A/4) or directional    |
// | cluster_receiver    | string | "isotropic"  | how a cluster hands on what it gathers: isotropic, cosine  |
// | row_sums            | string | "keep"       | leaf row-sum correction: keep, clamp, normalize            |
// |                     |        |              | (see core/solver/row_sums.h)                               |
// | row_sum_rays        | int    | 64           | escape rays per leaf for row_sums = normalize              |
// | locks_pool          | int    | 0            | hashed locks per class (0: twice the refiner count)        |
// | trace               | string | ""           | file to record a task trace to ("" = none)                 |
// | image_width         | int    | 640          | render.png width in pixels (height from the aspect 4:3)    |
// | effects             | string | "auto"       | auto: skip what the scene does not need                    |
// |                     |        |              | (core/config/effects.h); all: compute every effect         |
// | shaft_culling       | string | "off"        | on: V = 1 without rays for pairs whose shaft holds no      |
// |                     |        |              | polygon (core/transport/shaft.h); off: always cast rays    |
// | decision_rays       | string | "shared"     | shared: an accepted link keeps the visibility estimate its |
// |                     |        |              | oracle decided on; independent: where that decision        |
// |                     |        |              | depended on it, the estimate is drawn again                |
// |                     |        |              | (core/solver/refiner.h)                                    |
// | max_memory_gb       | double | 0            | refinement stops with an error when its elements and links |
// |                     |        |              | pass this (0: 3/4 of the machine's physical memory)        |
// | camera              | string | ""           | render.png's camera: eye=X,Y,Z:look=X,Y,Z[:up=..][:fov=..] |
// |                     |        |              | (core/scene/camera_spec.h), "auto", or "" (the scene's     |
// |                     |        |              | own, else automatic)                                       |
// | sides               | string | "auto"       | back faces for two-sided materials                         |
// |                     |        |              | (core/scene/back_faces.h): auto (MGF sides 2), one (none), |
// |                     |        |              | two (every face)                                           |
// | segments            | int    | 0            | divisions of a circle for MGF sph, cyl, cone, ring, torus: |
// |                     |        |              | 0 by the shape's size (core/scene/mgf/mgf_segments.h),     |
// |                     |        |              | or 3..4096                                                 |
// | shading             | string | "smooth"     | render.png and solution.ply: smooth (vertex values shared  |
// |                     |        |              | across leaves of one surface) or flat                      |
// |                     |        |              | (core/output/smooth_shading.h)                             |
// | exposure            | double | 0            | render.png's exposure, in stops over the automatic one     |
// |                     |        |              | (core/output/render.h): +1 twice as bright, -1 half        |
#pragma once

#include <cstdint>
#include <string>

namespace hrad {

struct SolverOptions {
  std::string scheduler = "stack";
  int block_size = 10;
  int threads = 1;
  std::string oracle = "bf";
  double eps = 1e-4;
  double min_area = 1e-4;
  int iterations = 4;
  int visibility_rays = 4;
  std::string pin = "none";
  std::string placement = "first-touch";
  std::string pool_order = "submitted";
  std::uint64_t seed = 1;
  double gather_tolerance = 1e-6;
  int max_gather_sweeps = 100000;
  std::string cluster_model = "directional";
  std::string cluster_receiver = "isotropic";
  std::string row_sums = "keep";
  int row_sum_rays = 64;
  int locks_pool = 0;
  std::string trace;
  int image_width = 640;
  std::string effects = "auto";
  std::string shaft_culling = "off";
  std::string decision_rays = "shared";
  double max_memory_gb = 0;
  std::string camera;
  std::string sides = "auto";
  int segments = 0;
  std::string shading = "smooth";
  double exposure = 0;
};

}  // namespace hrad
