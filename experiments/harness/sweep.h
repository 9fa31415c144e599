// Sweep expansion: an experiment configuration becomes an ordered list of points
// (scene x the cartesian product of the sweep axes) and each point runs `repetitions`
// times. Scenes vary slowest, then the sweep axes in file order (the last fastest), so
// the numbering is stable for a given configuration: runs.csv names each run by its
// point index and repetition, which is what --resume matches on.
#pragma once

#include "core/config/options.h"
#include "experiments/harness/experiment_config.h"

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace hrad::experiment {

struct SweepPoint {
  int index = 0;      ///< 0-based, in expansion order
  std::string scene;  ///< scene spec
  /// The swept keys and this point's values, in axis order.
  std::vector<std::pair<std::string, nlohmann::json>> values;
  SolverOptions options;  ///< settings + this point's values, validated
};

/// One run: a point and a repetition (0-based).
struct RunId {
  int point = 0;
  int repetition = 0;
  friend auto operator<=>(const RunId&, const RunId&) = default;
};

/// Expands `c` (quick overrides already applied or not, as the caller wants; --quick is
/// apply_quick). Throws std::invalid_argument when a combination is out of range.
[[nodiscard]] std::vector<SweepPoint> expand_sweep(const ExperimentConfig& c);

/// "threads=4 scheduler=stack" (values as in the JSON, strings unquoted); "" when nothing
/// is swept.
[[nodiscard]] std::string describe_point(const SweepPoint& p);

}  // namespace hrad::experiment
