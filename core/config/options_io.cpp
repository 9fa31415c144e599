#include "core/config/options_io.h"

#include "core/base/json_input.h"
#include "core/scene/camera_spec.h"
#include "oracles/oracle.h"
#include "schedulers/scheduler.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <variant>

namespace hrad {
namespace {

using Member = std::variant<int SolverOptions::*, std::uint64_t SolverOptions::*,
                            double SolverOptions::*, std::string SolverOptions::*>;

// The one table of keys. Order and meanings follow the table in core/config/options.h;
// OptionInfo::type is derived from the member's type, so it cannot disagree.
struct Row {
  const char* name;
  Member member;
  const char* help;
  /// For string keys with a syntax of their own: throws std::invalid_argument saying
  /// what is wrong with the text (nullptr: any text).
  void (*check_text)(const std::string&) = nullptr;
  /// For keys that name a plug-in: its registry's names, appended to the help when the
  /// table is built (at run time, so a new plug-in is listed without editing this).
  std::vector<std::string> (*names)() = nullptr;
};

void check_camera_text(const std::string& text) {
  if (!text.empty() && !is_auto_camera(text)) (void)parse_camera_spec(text);
}

const std::vector<Row>& rows() {
  using S = SolverOptions;
  static const std::vector<Row> table = {
      {"scheduler", &S::scheduler, "refinement scheduler (task order), by name", nullptr,
       &scheduler_names},
      {"block_size", &S::block_size, "tasks a refiner takes (and buffers) per scheduler visit"},
      {"threads", &S::threads, "refiner threads"},
      {"oracle", &S::oracle, "refinement oracle, by name", nullptr, &oracle_names},
      {"eps", &S::eps, "oracle threshold, relative to the total emitted power"},
      {"min_area", &S::min_area, "smallest element area, relative to the total scene area"},
      {"iterations", &S::iterations, "refinement iterations (the paper uses 4)"},
      {"visibility_rays", &S::visibility_rays,
       "rays per link for the visibility estimate (0: no rays)"},
      {"pin", &S::pin, "thread pinning: none, compact, scatter, node-round-robin"},
      {"placement", &S::placement, "memory placement: first-touch, interleave, node0"},
      {"pool_order", &S::pool_order,
       "central pools sort each submitted batch: submitted (no), address, subtree"},
      {"seed", &S::seed, "mixed into every per-link random number"},
      {"gather_tolerance", &S::gather_tolerance,
       "the last iteration's propagation stops when the estimated remaining change is "
       "below this fraction of the largest radiosity (earlier iterations at max(this, 1e-4))"},
      {"max_gather_sweeps", &S::max_gather_sweeps,
       "hard cap on gather + push-pull sweeps per iteration"},
      {"cluster_model", &S::cluster_model,
       "cluster projected areas: isotropic (A/4, Sillion 1995) or directional (per axis)"},
      {"cluster_receiver", &S::cluster_receiver,
       "how a cluster hands what it gathers to its members: isotropic or cosine"},
      {"row_sums", &S::row_sums,
       "leaf row-sum correction: keep, clamp (at 1) or normalize (to 1 - escape, by rays)"},
      {"row_sum_rays", &S::row_sum_rays, "escape rays per leaf when row_sums = normalize"},
      {"locks_pool", &S::locks_pool, "hashed locks per lock class (0: twice the refiner count)"},
      {"trace", &S::trace, "file to record a task trace to (empty: none)"},
      {"image_width", &S::image_width, "render.png width in pixels (height: 3/4 of it)"},
      {"effects", &S::effects,
       "auto: skip what the scene does not need (reported in stats.json); all: compute "
       "every effect"},
      {"shaft_culling", &S::shaft_culling,
       "on: no rays for pairs whose shaft holds no polygon (V = 1); off: always cast them"},
      {"decision_rays", &S::decision_rays,
       "shared: an accepted link keeps the visibility its oracle decided on; independent: "
       "where the decision depended on it, the link's visibility is estimated again from "
       "independent rays (unbiased, for the study of that selection)"},
      {"max_memory_gb", &S::max_memory_gb,
       "refinement stops with an error when its elements and links pass this many GB (0: "
       "3/4 of the machine's physical memory)"},
      {"camera", &S::camera,
       "render.png's camera: eye=X,Y,Z:look=X,Y,Z[:up=X,Y,Z][:fov=DEG], auto, or empty (the "
       "scene's own, else automatic)",
       &check_camera_text},
      {"sides", &S::sides,
       "back faces for two-sided materials: auto (MGF sides 2; OBJ and built-in scenes "
       "one-sided), one (none: every face one-sided), two (every face two-sided)"},
      {"segments", &S::segments,
       "divisions of a full circle for MGF sph, cyl, cone, ring and torus (0: by each "
       "shape's radius against the scene's diagonal, 16 to 128)"},
      {"shading", &S::shading,
       "render.png and solution.ply: smooth (one value per vertex and surface, continuous "
       "across leaves) or flat (each leaf its own constant)"},
      {"exposure", &S::exposure,
       "render.png's exposure in stops over the automatic exposure (+1: twice as bright)"},
  };
  return table;
}

OptionType type_of(const Member& m) {
  constexpr OptionType kByIndex[] = {OptionType::Int, OptionType::UInt64, OptionType::Double,
                                     OptionType::String};
  return kByIndex[m.index()];
}

std::string canonical(std::string_view key) {
  std::string k(key);
  for (char& c : k)
    if (c == '.' || c == '-') c = '_';
  return k;
}

const Row* find_row(std::string_view key) {
  for (const Row& r : rows())
    if (key == r.name) return &r;
  return nullptr;
}

[[noreturn]] void unknown_key(std::string_view source, std::string_view key) {
  std::string hint;
  const std::string c = canonical(key);
  if (c != key && find_row(c)) hint = fmt::format(" (did you mean '{}'?)", c);
  throw std::invalid_argument(fmt::format("{}: unknown option key '{}'{}; valid keys: {}", source,
                                          key, hint, option_key_list()));
}

template <class T>
bool parse_number(std::string_view text, T& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end && !text.empty();
}

// Text -> typed value. Returns false when the whole text is not a valid value.
bool parse_value(std::string_view text, int& out) { return parse_number(text, out); }
bool parse_value(std::string_view text, std::uint64_t& out) { return parse_number(text, out); }
bool parse_value(std::string_view text, double& out) {
  return parse_number(text, out) && std::isfinite(out);
}
bool parse_value(std::string_view text, std::string& out) {
  out = std::string(text);
  return true;
}

// JSON -> typed value, strict: no float for an integer, no string for a number.
bool from_json_value(const nlohmann::json& j, int& out) {
  if (j.is_number_unsigned()) {
    const auto v = j.get<std::uint64_t>();
    if (v > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) return false;
    out = static_cast<int>(v);
    return true;
  }
  if (!j.is_number_integer()) return false;
  const auto v = j.get<std::int64_t>();
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) return false;
  out = static_cast<int>(v);
  return true;
}
bool from_json_value(const nlohmann::json& j, std::uint64_t& out) {
  if (j.is_number_unsigned()) {
    out = j.get<std::uint64_t>();
    return true;
  }
  return false;  // negative integers and floats
}
bool from_json_value(const nlohmann::json& j, double& out) {
  if (!j.is_number()) return false;
  out = j.get<double>();
  return std::isfinite(out);
}
bool from_json_value(const nlohmann::json& j, std::string& out) {
  if (!j.is_string()) return false;
  out = j.get<std::string>();
  return true;
}

template <class T>
void check_syntax(const Row& r, const T& value, std::string_view source) {
  if constexpr (std::is_same_v<T, std::string>) {
    if (!r.check_text) return;
    try {
      r.check_text(value);
    } catch (const std::invalid_argument& e) {
      // With a source, the style of the type errors; without, that of the range errors.
      throw std::invalid_argument(
          source.empty()
              ? fmt::format("option {} = '{}': {}", r.name, brief_text(value), e.what())
              : fmt::format("{}: option '{}' = '{}': {}", source, r.name, brief_text(value),
                            e.what()));
    }
  }
}

void check(bool ok, const char* key, const std::string& value, const char* rule) {
  if (!ok)
    throw std::invalid_argument(
        fmt::format("option {} = {} is out of range: it must be {}", key, value, rule));
}

}  // namespace

const char* option_type_name(OptionType t) {
  switch (t) {
    case OptionType::Int: return "integer";
    case OptionType::UInt64: return "unsigned integer";
    case OptionType::Double: return "number";
    case OptionType::String: return "string";
  }
  return "?";
}

const std::vector<OptionInfo>& option_table() {
  static const std::vector<OptionInfo> table = [] {
    std::vector<OptionInfo> t;
    for (const Row& r : rows()) {
      std::string help = r.help;
      if (r.names) help += fmt::format(": {}", fmt::join(r.names(), ", "));
      t.push_back({r.name, type_of(r.member), std::move(help)});
    }
    return t;
  }();
  return table;
}

const OptionInfo* find_option(std::string_view key) {
  const std::string c = canonical(key);
  for (const OptionInfo& i : option_table())
    if (i.name == c) return &i;
  return nullptr;
}

std::string option_key_list() {
  std::string s;
  for (const Row& r : rows()) s += (s.empty() ? "" : ", ") + std::string(r.name);
  return s;
}

nlohmann::json options_to_json(const SolverOptions& o) {
  nlohmann::json j = nlohmann::json::object();
  for (const Row& r : rows())
    std::visit([&](auto member) { j[r.name] = o.*member; }, r.member);
  return j;
}

std::string option_value_string(const SolverOptions& o, std::string_view key) {
  const Row* r = find_row(canonical(key));
  if (!r) unknown_key("option_value_string", key);
  return std::visit(
      [&](auto member) -> std::string {
        const auto& v = o.*member;
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::string>)
          return v;
        else
          return fmt::format("{}", v);
      },
      r->member);
}

void apply_options_json(SolverOptions& o, const nlohmann::json& j, const std::string& source) {
  if (!j.is_object())
    throw std::invalid_argument(fmt::format(
        "{}: the configuration must be a JSON object of option keys, not a {}", source,
        j.type_name()));
  for (const auto& item : j.items()) {
    // Named references, not a structured binding: clang 14 cannot capture those.
    const std::string& key = item.key();
    const nlohmann::json& value = item.value();
    const Row* r = find_row(key);
    if (!r) unknown_key(source, key);
    std::visit(
        [&](auto member) {
          auto parsed = o.*member;
          if (!from_json_value(value, parsed))
            throw std::invalid_argument(fmt::format(
                "{}: option '{}' expects {} {}, got {} {}", source, key,
                type_of(r->member) == OptionType::Int ? "an" : "a",
                option_type_name(type_of(r->member)), value.type_name(), brief_json(value)));
          check_syntax(*r, parsed, source);
          o.*member = parsed;
        },
        r->member);
  }
}

void apply_option_value(SolverOptions& o, std::string_view key, std::string_view value,
                        std::string_view source) {
  const Row* r = find_row(canonical(key));
  if (!r) unknown_key(source, key);
  std::visit(
      [&](auto member) {
        auto parsed = o.*member;
        if (!parse_value(value, parsed))
          throw std::invalid_argument(
              fmt::format("{}: option '{}' expects {} {}, got '{}'", source, r->name,
                          type_of(r->member) == OptionType::Int ? "an" : "a",
                          option_type_name(type_of(r->member)), brief_text(value)));
        check_syntax(*r, parsed, source);
        o.*member = parsed;
      },
      r->member);
}

void apply_option_assignment(SolverOptions& o, const std::string& key_eq_value) {
  const auto eq = key_eq_value.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument(fmt::format(
        "--set {}: expected key=value (valid keys: {})", key_eq_value, option_key_list()));
  apply_option_value(o, std::string_view(key_eq_value).substr(0, eq),
                     std::string_view(key_eq_value).substr(eq + 1), "--set " + key_eq_value);
}

void validate_options(const SolverOptions& o) {
  const auto str = [](auto v) { return fmt::format("{}", v); };
  check(!o.scheduler.empty(), "scheduler", "\"\"", "a scheduler name");
  check(o.block_size >= 1, "block_size", str(o.block_size), ">= 1");
  check(o.threads >= 1, "threads", str(o.threads), ">= 1");
  check(!o.oracle.empty(), "oracle", "\"\"", "an oracle name");
  check(std::isfinite(o.eps) && o.eps > 0, "eps", str(o.eps), "a finite number > 0");
  check(std::isfinite(o.min_area) && o.min_area >= 0, "min_area", str(o.min_area),
        "a finite number >= 0");
  check(o.iterations >= 1, "iterations", str(o.iterations), ">= 1");
  check(o.visibility_rays >= 0, "visibility_rays", str(o.visibility_rays), ">= 0");
  check(o.pin == "none" || o.pin == "compact" || o.pin == "scatter" ||
            o.pin == "node-round-robin",
        "pin", o.pin, "one of none, compact, scatter, node-round-robin");
  check(o.placement == "first-touch" || o.placement == "interleave" || o.placement == "node0",
        "placement", o.placement, "one of first-touch, interleave, node0");
  check(o.pool_order == "submitted" || o.pool_order == "address" || o.pool_order == "subtree",
        "pool_order", o.pool_order, "one of submitted, address, subtree");
  check(std::isfinite(o.gather_tolerance) && o.gather_tolerance > 0, "gather_tolerance",
        str(o.gather_tolerance), "a finite number > 0");
  check(o.max_gather_sweeps >= 1, "max_gather_sweeps", str(o.max_gather_sweeps), ">= 1");
  check(o.max_memory_gb >= 0, "max_memory_gb", str(o.max_memory_gb), ">= 0");
  check(o.cluster_model == "isotropic" || o.cluster_model == "directional", "cluster_model",
        o.cluster_model, "isotropic or directional");
  check(o.cluster_receiver == "isotropic" || o.cluster_receiver == "cosine", "cluster_receiver",
        o.cluster_receiver, "isotropic or cosine");
  check(o.row_sums == "keep" || o.row_sums == "clamp" || o.row_sums == "normalize", "row_sums",
        o.row_sums, "one of keep, clamp, normalize");
  check(o.row_sum_rays >= 1, "row_sum_rays", str(o.row_sum_rays), ">= 1");
  check(o.locks_pool >= 0, "locks_pool", str(o.locks_pool), ">= 0 (0: automatic)");
  check(o.image_width >= 8 && o.image_width <= 16384, "image_width", str(o.image_width),
        "between 8 and 16384");
  check(o.effects == "auto" || o.effects == "all", "effects", o.effects, "auto or all");
  check(o.shaft_culling == "on" || o.shaft_culling == "off", "shaft_culling", o.shaft_culling,
        "on or off");
  check(o.decision_rays == "shared" || o.decision_rays == "independent", "decision_rays",
        o.decision_rays, "shared or independent");
  check(o.sides == "auto" || o.sides == "one" || o.sides == "two", "sides", o.sides,
        "one of auto, one, two");
  check(o.segments == 0 || (o.segments >= 3 && o.segments <= 4096), "segments",
        str(o.segments), "0 (automatic) or between 3 and 4096");
  check(o.shading == "smooth" || o.shading == "flat", "shading", o.shading, "smooth or flat");
  check(std::isfinite(o.exposure) && std::abs(o.exposure) <= 64, "exposure", str(o.exposure),
        "a number of stops between -64 and 64");
  for (const Row& r : rows())
    if (r.check_text) std::visit([&](auto member) { check_syntax(r, o.*member, ""); }, r.member);
}

SceneLoadOptions scene_load_options(const SolverOptions& o) {
  return {parse_sides(o.sides), o.segments};
}

}  // namespace hrad
