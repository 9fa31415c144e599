// An experiment configuration: which scenes, which fixed solver options, which options
// to sweep (their cartesian product), how many repetitions, what --quick changes, and
// which plot to draw. One JSON object, checked strictly like SolverOptions files (an
// unknown key anywhere is an error naming it and the valid keys):
//
// | key          | type                     | meaning                                          |
// |--------------|--------------------------|--------------------------------------------------|
// | name         | string (required)        | results go to results/<name>/<stamp>/; [A-Za-z0-9_.-] |
// | description  | string                   | one line for the manifest and the plot caption    |
// | scenes       | list of strings (required)| scene specs as `hrad solve` takes them           |
// | settings     | object                   | fixed SolverOptions keys (core/config/options.h)          |
// | sweep        | object: key -> list      | option keys to vary; non-empty lists               |
// | repetitions  | integer >= 1 (default 1) | runs of every point                               |
// | quick        | object                   | what --quick changes: scenes, settings (merged),  |
// |              |                          | sweep (per key, replacing), repetitions           |
// | plot         | string or list           | plots/<plot>.py run on the result folder at the end|
// | accuracy     | object                   | probe error of every run against a path-traced   |
// |              |                          | reference (AccuracySpec below)                    |
//
// Keys of `sweep` keep their file order: the first key varies slowest, the last fastest,
// and scenes are outermost. `//` and `/* */` comments are accepted.
#pragma once

#include "core/config/options.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hrad::experiment {

/// One swept dimension: an option key (canonical name) and its values.
struct SweepAxis {
  std::string key;
  std::vector<nlohmann::json> values;  ///< each checked against the key's type
};

/// What --quick changes; an absent part changes nothing.
struct QuickOverrides {
  std::vector<std::string> scenes;                     ///< replaces `scenes` when non-empty
  nlohmann::json settings = nlohmann::json::object();  ///< merged over `settings`
  std::vector<SweepAxis> sweep;                        ///< replaces the values of these axes
  int repetitions = 0;                                 ///< replaces `repetitions` when > 0
};

/// The `accuracy` block: after each run, irradiance at probe points (Solver::
/// probe_irradiance) is compared with a path-traced reference (core/reference/path_tracer.h,
/// computed once per scene and cached in the result folder as reference-<scene>.csv),
/// by the probe metric of core/reference/error_metrics.h. Keys:
///   probes               string (one file for every scene) or object: scene -> file.
///                        An object key matches a scene spec exactly (a builtin
///                        scene's parameters written with ',' or with '?' and '&'
///                        alike), or the scene's builtin:NAME (so "builtin:office"
///                        covers "builtin:office,desks=4").
///                        Relative paths are relative to the configuration file's folder.
///   reference_rel_error  number > 0 (default 0.005): the reference's target relative
///                        standard error per probe
///   reference_max_samples integer >= 1 (default 4194304): paths per probe at most
///   floor                number >= 0 (default 0: 1e-3 x mean reference irradiance):
///                        the error metric's absolute floor
struct AccuracySpec {
  bool enabled = false;
  std::string probes_all;  ///< the single file, when `probes` is a string
  std::vector<std::pair<std::string, std::string>> probes_by_scene;  ///< file order
  double reference_rel_error = 0.005;
  std::int64_t reference_max_samples = 1 << 22;
  double floor = 0;
  std::filesystem::path base_dir;  ///< the config file's folder (not serialised)
};

/// The probe file of `scene` (resolved against base_dir), or "" when none is given.
[[nodiscard]] std::filesystem::path accuracy_probe_file(const AccuracySpec& a,
                                                        const std::string& scene);

struct ExperimentConfig {
  std::string name;
  std::string description;
  std::vector<std::string> scenes;
  nlohmann::json settings = nlohmann::json::object();  ///< option key -> value
  std::vector<SweepAxis> sweep;
  int repetitions = 1;
  QuickOverrides quick;
  std::vector<std::string> plots;  ///< plot script names (plots/<name>.py)
  AccuracySpec accuracy;           ///< probe error columns (enabled when the block is given)
};

/// Parses and checks a configuration. `source` (a file name) starts every error
/// message. Throws std::invalid_argument for: a non-object, an unknown key, a missing
/// `name` or `scenes`, a value of the wrong type, an empty `scenes` or sweep list, an
/// option key unknown to SolverOptions, a setting or sweep value of the wrong type or
/// out of range, an unknown scheduler or oracle name, or a key both fixed and swept.
[[nodiscard]] ExperimentConfig parse_experiment_config(const nlohmann::ordered_json& j,
                                                       const std::string& source);

/// Reads `path` (JSON with comments) and parses it. Throws std::invalid_argument naming
/// the file (and the line for JSON syntax errors).
[[nodiscard]] ExperimentConfig load_experiment_config(const std::filesystem::path& path);

/// Applies config.quick: the result has no quick part left.
[[nodiscard]] ExperimentConfig apply_quick(const ExperimentConfig& config);

/// `--set KEY=VALUE`: an option key fixes that option (and removes it from the sweep);
/// `sweep.KEY=V1,V2,...` sweeps an option over these values (replacing its list, or
/// adding an axis, and removing it from the settings); `repetitions=N` sets the
/// repetitions; `scenes=SPEC[,SPEC...]` replaces the scenes.
/// Throws std::invalid_argument for an unknown key or a bad value.
void apply_experiment_set(ExperimentConfig& config, const std::string& key_eq_value);

/// The configuration as JSON, in the file's format (for manifest.json). Parsing the
/// result gives back an equal configuration.
[[nodiscard]] nlohmann::ordered_json experiment_config_to_json(const ExperimentConfig& c);

/// The solver options of `settings` over the defaults (not range-checked).
[[nodiscard]] SolverOptions base_options(const ExperimentConfig& c);

}  // namespace hrad::experiment
