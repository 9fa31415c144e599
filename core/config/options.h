// SolverOptions: every knob of a run, one plain struct with defaults. The CLI,
// the JSON config and `--set key=value` all write into it through options_io.h,
// which rejects unknown keys by name. A mode is an enum whose one table of names
// (core/base/enum_names.h, beside the enum) gives the values parsing accepts, the
// help text and docs/configuration.md's "allowed" column; the meanings are in options_io.cpp's
// key table and docs/configuration.md.
//
// | key                 | type            | default      | meaning                                 |
// |---------------------|-----------------|--------------|-----------------------------------------|
// | scheduler           | string          | "blocked"    | refinement task order (scheduler_names) |
// | block_size          | int             | 0            | tasks a refiner takes per visit; 0: guided |
// | threads             | int             | 1            | refiner threads                         |
// | oracle              | string          | "bf"         | refinement oracle (oracle_names)        |
// | eps                 | double          | 1e-4         | oracle threshold, of emitted power      |
// | min_area            | double          | 1e-4         | smallest element, of total area         |
// | iterations          | int             | 4            | refinement iterations                   |
// | visibility_rays     | int             | 4            | rays per link (0: no rays)              |
// | pin                 | PinPolicy       | none         | core/parallel/pin_plan.h                |
// | placement           | MemBind         | first-touch  | core/parallel/topology.h                |
// | pool_order          | PoolOrder       | submitted    | schedulers/scheduler.h                  |
// | seed                | uint64          | 1            | mixed into every per-link random number |
// | gather_tolerance    | double          | 1e-5         | propagation's stop (core/solver/solver) |
// | max_gather_sweeps   | int             | 100000       | sweeps per iteration, at most           |
// | cluster_model       | ClusterModel    | directional  | core/transport/cluster_model.h          |
// | cluster_receiver    | ClusterReceiver | cosine       | core/config/modes.h                     |
// | cluster_members     | ClusterMembers  | alike        | core/transport/cluster_exposure.h       |
// | row_sums            | RowSumMode      | keep         | core/config/modes.h, core/solver/row_sums.h |
// | row_sum_rays        | int             | 64           | covered-share rays per leaf (normalize)  |
// | locks_pool          | int             | 0            | hashed locks per class (0: 2 x threads) |
// | trace               | string          | ""           | task trace file ("" = none)             |
// | image_width         | int             | 640          | render.png width                        |
// | image_samples       | int             | 2            | samples per pixel side (antialiasing)   |
// | effects             | EffectsMode     | auto         | core/config/modes.h, effects.h          |
// | shaft_culling       | ShaftCulling    | off          | core/config/modes.h                     |
// | decision_rays       | DecisionRays    | shared       | core/config/modes.h                     |
// | decision_visibility_rays | int        | 0            | rays of a visibility-dependent decision (0: visibility_rays) |
// | push_visibility     | PushVisibility  | link         | core/config/modes.h, push_weights.h     |
// | max_memory_gb       | double          | 0            | every phase's memory limit (0: 3/4 RAM) |
// | camera              | string          | ""           | core/scene/camera_spec.h, auto, or ""   |
// | sides               | Sides           | auto         | core/scene/back_faces.h                 |
// | emitter_sides       | EmitterSides    | front        | core/scene/back_faces.h                 |
// | segments            | int             | 0            | MGF circle divisions (0: by size)       |
// | shading             | Shading         | smooth       | core/config/modes.h                     |
// | exposure            | double          | 0            | render.png's exposure, in stops         |
// | scheduler.NAME.KEY, | int or double   | the plug-in's| a plug-in's own parameter, declared     |
// | oracle.NAME.KEY     |                 |              | where it registers (plugin_params)      |
#pragma once

#include "core/base/plugin_params.h"
#include "core/config/modes.h"
#include "core/parallel/pin_plan.h"
#include "core/parallel/topology.h"
#include "core/scene/back_faces.h"
#include "core/transport/cluster_model.h"
#include "schedulers/scheduler.h"

#include <cstdint>
#include <string>

namespace hrad {

/// Upper bounds of the numeric keys (validate_options): far above any useful value, low
/// enough that nothing is made that cannot be run.
inline constexpr int kMaxThreads = 1024;
inline constexpr int kMaxBlockSize = 1 << 20;
inline constexpr int kMaxIterations = 10000;
inline constexpr int kMaxRaysPerLink = 1024;
inline constexpr int kMaxGatherSweeps = 10000000;
inline constexpr int kMaxRowSumRays = 65536;
inline constexpr int kMaxLocksPool = 1 << 20;

struct SolverOptions {
  std::string scheduler = "blocked";
  /// 0: guided (schedulers/scheduler.h, guided_block); N: at most N tasks per visit.
  int block_size = 0;
  int threads = 1;
  std::string oracle = "bf";
  double eps = 1e-4;
  double min_area = 1e-4;
  int iterations = 4;
  int visibility_rays = 4;
  PinPolicy pin = PinPolicy::None;
  MemBind placement = MemBind::FirstTouch;
  PoolOrder pool_order = PoolOrder::Submitted;
  std::uint64_t seed = 1;
  // 1e-6 took 3 more sweeps on the lab and 2 on the cabin (of 11 and 16) and moved
  // their probes by at most 0.001 %.
  double gather_tolerance = 1e-5;
  int max_gather_sweeps = 100000;
  ClusterModel cluster_model = ClusterModel::Directional;
  ClusterReceiver cluster_receiver = ClusterReceiver::Cosine;
  ClusterMembers cluster_members = ClusterMembers::Alike;
  RowSumMode row_sums = RowSumMode::Keep;
  int row_sum_rays = 64;
  int locks_pool = 0;
  std::string trace;
  int image_width = 640;
  int image_samples = 2;
  EffectsMode effects = EffectsMode::Auto;
  ShaftCulling shaft_culling = ShaftCulling::Off;
  DecisionRays decision_rays = DecisionRays::Shared;
  int decision_visibility_rays = 0;
  PushVisibility push_visibility = PushVisibility::Link;
  double max_memory_gb = 0;
  std::string camera;
  Sides sides = Sides::Auto;
  EmitterSides emitter_sides = EmitterSides::Front;
  int segments = 0;
  Shading shading = Shading::Smooth;
  double exposure = 0;
  /// The plug-ins' own parameters (core/base/plugin_params.h), by their option key
  /// KIND.NAME.KEY ("scheduler.stealing.victims"), each value as checked text. Only
  /// the selected scheduler's and oracle's may be set (validate_options).
  ParamValues plugin_params;
};

}  // namespace hrad
