#include "experiments/harness/experiment_config.h"

#include "core/base/input_file.h"
#include "core/base/json_input.h"
#include "core/config/options_io.h"
#include "core/scene/builtin_scenes.h"
#include "oracles/oracle.h"
#include "schedulers/scheduler.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace hrad::experiment {
namespace {

using ojson = nlohmann::ordered_json;

constexpr const char* kTopKeys[] = {"name",        "description", "scenes", "settings", "sweep",
                                    "repetitions", "quick",       "plot",   "accuracy"};
constexpr const char* kQuickKeys[] = {"scenes", "settings", "sweep", "repetitions"};
constexpr const char* kAccuracyKeys[] = {"probes", "reference_rel_error", "reference_max_samples",
                                         "floor"};

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw std::invalid_argument(fmt::format("{}: {}", source, what));
}

template <std::size_t N>
void check_keys(const ojson& j, const char* const (&valid)[N], const std::string& source,
                const std::string& where) {
  for (const auto& item : j.items()) {
    if (std::find_if(std::begin(valid), std::end(valid),
                     [&](const char* k) { return item.key() == k; }) != std::end(valid))
      continue;
    std::string list;
    for (const char* k : valid) list += (list.empty() ? "" : ", ") + std::string(k);
    fail(source, fmt::format("unknown key '{}'{}; valid keys: {}", item.key(), where, list));
  }
}

// ordered_json -> json (the options table takes plain json).
nlohmann::json plain(const ojson& j) { return nlohmann::json::parse(j.dump()); }

std::string get_string(const ojson& j, const std::string& key, const std::string& source) {
  if (!j.is_string())
    fail(source,
         fmt::format("'{}' must be a string, got {} {}", key, j.type_name(), brief_json(j)));
  return j.get<std::string>();
}

// The most runs of a point (a million runs of the smallest scene take hours).
constexpr std::int64_t kMaxRepetitions = 1000000;

int get_count(const ojson& j, const std::string& key, const std::string& source) {
  if (!j.is_number_integer() || j.get<std::int64_t>() < 1 ||
      j.get<std::int64_t>() > kMaxRepetitions)
    fail(source, fmt::format("'{}' must be an integer between 1 and {}, got {}", key,
                             kMaxRepetitions, brief_json(j)));
  return j.get<int>();
}

std::vector<std::string> get_scenes(const ojson& j, const std::string& key,
                                    const std::string& source) {
  if (!j.is_array())
    fail(source, fmt::format("'{}' must be a list of scene specs, got {}", key, j.type_name()));
  if (j.empty()) fail(source, fmt::format("'{}' is empty: name at least one scene", key));
  std::vector<std::string> out;
  for (const ojson& s : j) {
    if (!s.is_string() || s.get<std::string>().empty())
      fail(source, fmt::format("'{}' must hold non-empty strings, got {}", key, brief_json(s)));
    out.push_back(s.get<std::string>());
  }
  return out;
}

// Names the solver would reject only when constructed: check them up front.
void check_names(const SolverOptions& o, const std::string& source, const std::string& where) {
  const auto known = [](const std::vector<std::string>& names, const std::string& n) {
    return std::find(names.begin(), names.end(), n) != names.end();
  };
  const auto list = [](const std::vector<std::string>& names) {
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
  };
  if (!known(scheduler_names(), o.scheduler))
    fail(source, fmt::format("{}unknown scheduler '{}'; known: {}", where, o.scheduler,
                             list(scheduler_names())));
  if (!known(oracle_names(), o.oracle))
    fail(source,
         fmt::format("{}unknown oracle '{}'; known: {}", where, o.oracle, list(oracle_names())));
}

// Applies {key: value} over `base`, range-checks, and checks names. Errors name `where`.
SolverOptions checked_apply(const SolverOptions& base, const std::string& key, const ojson& value,
                            const std::string& source, const std::string& where) {
  SolverOptions o = base;
  try {
    apply_options_json(o, nlohmann::json{{key, plain(value)}}, source + ": " + where);
    validate_options(o);
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    // apply_options_json already starts with the source; validate_options does not.
    if (msg.rfind(source, 0) == 0) throw;
    fail(source, fmt::format("{}: {}", where, msg));
  }
  check_names(o, source, where + ": ");
  return o;
}

nlohmann::json get_settings(const ojson& j, const std::string& key, const std::string& source) {
  if (!j.is_object())
    fail(source, fmt::format("'{}' must be an object of option keys, got {}", key, j.type_name()));
  return plain(j);
}

// "threads": "cores" sweeps 1, 2, 4, ... up to this machine's logical CPUs, and that
// count itself when it is no power of two: the figures run to the machine at hand.
std::vector<nlohmann::json> threads_to_cores() {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<nlohmann::json> v;
  for (int t = 1; t < cores; t *= 2) v.emplace_back(t);
  v.emplace_back(cores);
  return v;
}

std::vector<SweepAxis> get_sweep(const ojson& j, const std::string& key,
                                 const std::string& source) {
  if (!j.is_object())
    fail(source, fmt::format("'{}' must be an object: option key -> list of values, got {}", key,
                             j.type_name()));
  std::vector<SweepAxis> axes;
  for (const auto& item : j.items()) {
    const OptionInfo* info = find_option(item.key());
    if (!info || info->name != item.key())
      fail(source, fmt::format("'{}': unknown option key '{}'; valid keys: {}", key, item.key(),
                               option_key_list()));
    if (item.key() == "threads" && item.value() == "cores") {
      axes.push_back(SweepAxis{item.key(), threads_to_cores()});
      continue;
    }
    if (!item.value().is_array())
      fail(source, fmt::format("'{}.{}' must be a list of values (or, for threads, \"cores\"), "
                               "got {}",
                               key, item.key(), brief_json(item.value())));
    if (item.value().empty())
      fail(source, fmt::format("'{}.{}' is an empty list: a sweep needs at least one value", key,
                               item.key()));
    SweepAxis axis{item.key(), {}};
    // Duplicates by an ordered set (1 and 1.0 are one value, as for ==): a linear
    // search made a sweep of 80,000 seeds take 6 s to check.
    std::set<nlohmann::json> seen;
    for (const ojson& v : item.value()) {
      nlohmann::json pv = plain(v);
      if (!seen.insert(pv).second)
        fail(source, fmt::format("'{}.{}' lists {} twice", key, item.key(), brief_json(v)));
      axis.values.push_back(std::move(pv));
    }
    axes.push_back(std::move(axis));
  }
  return axes;
}

// Every setting and every swept value must be valid over the settings.
void check_options(const ExperimentConfig& c, const std::string& source, const char* part) {
  SolverOptions base;
  for (const auto& item : c.settings.items())
    base = checked_apply(base, item.key(), ojson(item.value()), source,
                         fmt::format("{}settings.{}", part, item.key()));
  try {
    validate_options(base);
  } catch (const std::invalid_argument& e) {
    fail(source, fmt::format("{}settings: {}", part, e.what()));
  }
  for (const SweepAxis& a : c.sweep) {
    if (c.settings.contains(a.key))
      fail(source,
           fmt::format("'{}' is both in {}settings and in the sweep: keep one", a.key, part));
    for (const nlohmann::json& v : a.values)
      checked_apply(base, a.key, ojson(v), source,
                    fmt::format("sweep.{} = {}", a.key, brief_json(v)));
  }
}

AccuracySpec get_accuracy(const ojson& j, const std::string& source) {
  if (!j.is_object())
    fail(source, fmt::format("'accuracy' must be an object, got {}", j.type_name()));
  check_keys(j, kAccuracyKeys, source, " in 'accuracy'");
  AccuracySpec a;
  a.enabled = true;
  if (!j.contains("probes"))
    fail(source, "'accuracy' needs 'probes': a probe file, or an object scene -> probe file");
  const ojson& p = j["probes"];
  if (p.is_string() && !p.get<std::string>().empty()) {
    a.probes_all = p.get<std::string>();
  } else if (p.is_object() && !p.empty()) {
    for (const auto& item : p.items()) {
      if (!item.value().is_string() || item.value().get<std::string>().empty())
        fail(source, fmt::format("'accuracy.probes.{}' must be a file name, got {}", item.key(),
                                 brief_json(item.value())));
      a.probes_by_scene.emplace_back(item.key(), item.value().get<std::string>());
    }
  } else {
    fail(source, fmt::format("'accuracy.probes' must be a file name or a non-empty object "
                             "scene -> file name, got {}",
                             brief_json(p)));
  }
  const auto positive = [&](const char* key, bool allow_zero) {
    const ojson& v = j[key];
    if (!v.is_number() || !std::isfinite(v.get<double>()) ||
        (allow_zero ? v.get<double>() < 0 : v.get<double>() <= 0))
      fail(source, fmt::format("'accuracy.{}' must be a number {} 0, got {}", key,
                               allow_zero ? ">=" : ">", brief_json(v)));
    return v.get<double>();
  };
  if (j.contains("reference_rel_error"))
    a.reference_rel_error = positive("reference_rel_error", false);
  if (j.contains("floor")) a.floor = positive("floor", true);
  if (j.contains("reference_max_samples")) {
    const ojson& v = j["reference_max_samples"];
    if (!v.is_number_integer() || v.get<std::int64_t>() < 1)
      fail(source, fmt::format("'accuracy.reference_max_samples' must be an integer >= 1, got {}",
                               brief_json(v)));
    a.reference_max_samples = v.get<std::int64_t>();
  }
  return a;
}

void check_accuracy_scenes(const AccuracySpec& a, const std::vector<std::string>& scenes,
                           const std::string& source, const char* part) {
  if (!a.enabled) return;
  for (const std::string& s : scenes)
    if (accuracy_probe_file(a, s).empty())
      fail(source, fmt::format("'accuracy.probes' names no probe file for scene '{}' (in "
                               "'{}scenes')",
                               s, part));
}

}  // namespace

std::filesystem::path accuracy_probe_file(const AccuracySpec& a, const std::string& scene) {
  std::string file = a.probes_all;
  if (file.empty()) {
    // A builtin scene's parameters may be written either way (',' or '?' and '&').
    const std::string spec = normal_builtin_spec(scene), base = builtin_base(scene);
    for (const auto& [key, f] : a.probes_by_scene)
      if (normal_builtin_spec(key) == spec) file = f;
    if (file.empty())
      for (const auto& [key, f] : a.probes_by_scene)
        if (key == base) file = f;
  }
  if (file.empty()) return {};
  const std::filesystem::path p(file);
  return p.is_absolute() || a.base_dir.empty() ? p : a.base_dir / p;
}

ExperimentConfig parse_experiment_config(const ojson& j, const std::string& source) {
  if (!j.is_object())
    fail(source,
         fmt::format("an experiment configuration must be a JSON object, not a {}", j.type_name()));
  check_keys(j, kTopKeys, source, "");
  ExperimentConfig c;
  if (!j.contains("name")) fail(source, "missing key 'name'");
  c.name = get_string(j["name"], "name", source);
  if (c.name.empty() ||
      !std::all_of(c.name.begin(), c.name.end(),
                   [](char ch) {
                     return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' ||
                            ch == '_' || ch == '.';
                   }) ||
      c.name[0] == '.')
    fail(source, fmt::format("'name' must be a non-empty folder name of letters, digits, '-', "
                             "'_' and '.', got \"{}\"",
                             c.name));
  if (j.contains("description"))
    c.description = get_string(j["description"], "description", source);
  if (!j.contains("scenes")) fail(source, "missing key 'scenes' (a list of scene specs)");
  c.scenes = get_scenes(j["scenes"], "scenes", source);
  if (j.contains("settings")) c.settings = get_settings(j["settings"], "settings", source);
  if (j.contains("sweep")) c.sweep = get_sweep(j["sweep"], "sweep", source);
  if (j.contains("repetitions")) c.repetitions = get_count(j["repetitions"], "repetitions", source);
  if (j.contains("plot")) {
    const ojson& p = j["plot"];
    if (p.is_string()) {
      c.plots.push_back(p.get<std::string>());
    } else if (p.is_array()) {
      for (const ojson& s : p) c.plots.push_back(get_string(s, "plot", source));
    } else {
      fail(source,
           fmt::format("'plot' must be a string or a list of strings, got {}", brief_json(p)));
    }
    for (const std::string& s : c.plots)
      if (s.empty() || s.find_first_of("/\\. ") != std::string::npos)
        fail(source, fmt::format("'plot' names a script in plots/ without '.py', got \"{}\"", s));
  }
  check_options(c, source, "");
  if (j.contains("accuracy")) c.accuracy = get_accuracy(j["accuracy"], source);
  check_accuracy_scenes(c.accuracy, c.scenes, source, "");

  if (j.contains("quick")) {
    const ojson& q = j["quick"];
    if (!q.is_object())
      fail(source, fmt::format("'quick' must be an object, got {}", q.type_name()));
    check_keys(q, kQuickKeys, source, " in 'quick'");
    if (q.contains("scenes")) c.quick.scenes = get_scenes(q["scenes"], "quick.scenes", source);
    if (q.contains("settings"))
      c.quick.settings = get_settings(q["settings"], "quick.settings", source);
    if (q.contains("sweep")) c.quick.sweep = get_sweep(q["sweep"], "quick.sweep", source);
    for (const SweepAxis& a : c.quick.sweep)
      if (std::none_of(c.sweep.begin(), c.sweep.end(),
                       [&](const SweepAxis& b) { return b.key == a.key; }))
        fail(source, fmt::format("'quick.sweep.{}': '{}' is not swept by 'sweep'", a.key, a.key));
    if (q.contains("repetitions"))
      c.quick.repetitions = get_count(q["repetitions"], "quick.repetitions", source);
    check_options(apply_quick(c), source, "quick.");
    check_accuracy_scenes(c.accuracy, apply_quick(c).scenes, source, "quick.");
  }
  return c;
}

ExperimentConfig load_experiment_config(const std::filesystem::path& path) {
  check_input_file(path, "the experiment configuration");
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(fmt::format("{}: cannot open the file", path.string()));
  std::stringstream text;
  text << in.rdbuf();
  const auto j = parse_json_document<ojson>(text.str(), path.string(), /*comments=*/true);
  ExperimentConfig c = parse_experiment_config(j, path.string());
  c.accuracy.base_dir = path.parent_path();
  return c;
}

ExperimentConfig apply_quick(const ExperimentConfig& config) {
  ExperimentConfig c = config;
  if (!c.quick.scenes.empty()) c.scenes = c.quick.scenes;
  for (const auto& item : c.quick.settings.items()) {
    c.settings[item.key()] = item.value();
    std::erase_if(c.sweep, [&](const SweepAxis& a) { return a.key == item.key(); });
  }
  for (const SweepAxis& q : c.quick.sweep)
    for (SweepAxis& a : c.sweep)
      if (a.key == q.key) a.values = q.values;
  if (c.quick.repetitions > 0) c.repetitions = c.quick.repetitions;
  c.quick = QuickOverrides{};
  return c;
}

void apply_experiment_set(ExperimentConfig& config, const std::string& key_eq_value) {
  const auto eq = key_eq_value.find('=');
  const std::string source = "--set " + key_eq_value;
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument(
        fmt::format("{}: expected key=value (an option key, repetitions or scenes)", source));
  const std::string key = key_eq_value.substr(0, eq);
  const std::string value = key_eq_value.substr(eq + 1);
  if (key == "repetitions") {
    long long n = 0;
    try {
      std::size_t used = 0;
      n = std::stoll(value, &used);
      if (used != value.size()) n = 0;
    } catch (const std::exception&) {
      n = 0;
    }
    if (n < 1 || n > kMaxRepetitions)
      throw std::invalid_argument(fmt::format("{}: repetitions must be an integer between 1 and {}",
                                              source, kMaxRepetitions));
    config.repetitions = static_cast<int>(n);
    return;
  }
  if (key == "scenes") {
    const std::vector<std::string> scenes = split_scene_list(value);
    if (scenes.empty()) throw std::invalid_argument(source + ": name at least one scene");
    config.scenes = scenes;
    return;
  }
  if (key.rfind("sweep.", 0) == 0) {
    const OptionInfo* info = find_option(key.substr(6));
    if (!info)
      throw std::invalid_argument(fmt::format("{}: unknown option key '{}'; valid keys: {}", source,
                                              key.substr(6), option_key_list()));
    SweepAxis axis{info->name, {}};
    const bool to_cores = info->name == "threads" && value == "cores";
    if (to_cores) axis.values = threads_to_cores();
    std::stringstream ss(to_cores ? std::string() : value);
    for (std::string v; std::getline(ss, v, ',');) {
      SolverOptions o = base_options(config);
      apply_option_value(o, info->name, v, source);
      validate_options(o);
      check_names(o, source, "");
      const nlohmann::json jv = options_to_json(o)[info->name];
      if (std::find(axis.values.begin(), axis.values.end(), jv) != axis.values.end())
        throw std::invalid_argument(fmt::format("{}: '{}' is listed twice", source, v));
      axis.values.push_back(jv);
    }
    if (axis.values.empty())
      throw std::invalid_argument(source + ": a sweep needs at least one value");
    config.settings.erase(info->name);
    const auto it = std::find_if(config.sweep.begin(), config.sweep.end(),
                                 [&](const SweepAxis& a) { return a.key == info->name; });
    if (it != config.sweep.end())
      it->values = axis.values;
    else
      config.sweep.push_back(std::move(axis));
    return;
  }
  const OptionInfo* info = find_option(key);
  if (!info)
    throw std::invalid_argument(
        fmt::format("{}: unknown key '{}'; valid keys: repetitions, scenes, sweep.KEY, {}", source,
                    key, option_key_list()));
  SolverOptions o = base_options(config);
  apply_option_value(o, key, value, source);
  validate_options(o);
  check_names(o, source, "");
  config.settings[info->name] = options_to_json(o)[info->name];
  std::erase_if(config.sweep, [&](const SweepAxis& a) { return a.key == info->name; });
}

nlohmann::ordered_json experiment_config_to_json(const ExperimentConfig& c) {
  const auto sweep_json = [](const std::vector<SweepAxis>& axes) {
    ojson s = ojson::object();
    for (const SweepAxis& a : axes) {
      ojson values = ojson::array();
      for (const nlohmann::json& v : a.values) values.push_back(ojson::parse(v.dump()));
      s[a.key] = values;
    }
    return s;
  };
  ojson j = ojson::object();
  j["name"] = c.name;
  j["description"] = c.description;
  j["scenes"] = c.scenes;
  j["settings"] = ojson::parse(c.settings.dump());
  j["sweep"] = sweep_json(c.sweep);
  j["repetitions"] = c.repetitions;
  const QuickOverrides& q = c.quick;
  if (!q.scenes.empty() || !q.settings.empty() || !q.sweep.empty() || q.repetitions > 0) {
    ojson quick = ojson::object();
    if (!q.scenes.empty()) quick["scenes"] = q.scenes;
    if (!q.settings.empty()) quick["settings"] = ojson::parse(q.settings.dump());
    if (!q.sweep.empty()) quick["sweep"] = sweep_json(q.sweep);
    if (q.repetitions > 0) quick["repetitions"] = q.repetitions;
    j["quick"] = quick;
  }
  if (!c.plots.empty()) j["plot"] = c.plots;
  if (c.accuracy.enabled) {
    const AccuracySpec& a = c.accuracy;
    ojson acc = ojson::object();
    if (!a.probes_all.empty()) {
      acc["probes"] = a.probes_all;
    } else {
      ojson by = ojson::object();
      for (const auto& [scene, file] : a.probes_by_scene) by[scene] = file;
      acc["probes"] = by;
    }
    acc["reference_rel_error"] = a.reference_rel_error;
    acc["reference_max_samples"] = a.reference_max_samples;
    acc["floor"] = a.floor;
    j["accuracy"] = acc;
  }
  return j;
}

SolverOptions base_options(const ExperimentConfig& c) {
  SolverOptions o;
  apply_options_json(o, c.settings, "settings");
  return o;
}

}  // namespace hrad::experiment
