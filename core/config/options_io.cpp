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

using S = SolverOptions;
// One alternative per field type; a mode (an enum with a table of names,
// core/base/enum_names.h) is written and read as its name.
using Member = std::variant<int S::*, std::uint64_t S::*, double S::*, std::string S::*,
                            PinPolicy S::*, MemBind S::*, PoolOrder S::*, ClusterModel S::*,
                            ClusterReceiver S::*, ClusterMembers S::*, RowSumMode S::*,
                            EffectsMode S::*, ShaftCulling S::*, DecisionRays S::*,
                            PushVisibility S::*, Sides S::*, EmitterSides S::*, Shading S::*>;

template <class T>
constexpr bool kIsMode = std::is_enum_v<T>;

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
  if (!text.empty() && !is_auto_camera(text) && !automatic_camera_up(text))
    (void)parse_camera_spec(text);
}

const std::vector<Row>& rows() {
  static const std::vector<Row> table = {
      {"scheduler", &S::scheduler, "refinement scheduler (task order), by name", nullptr,
       &scheduler_names},
      {"block_size", &S::block_size,
       "tasks a refiner takes (and buffers) per scheduler visit; 0: guided (half the pool's "
       "share per refiner, between 1 and 1024)"},
      {"threads", &S::threads, "refiner threads"},
      {"oracle", &S::oracle, "refinement oracle, by name", nullptr, &oracle_names},
      {"eps", &S::eps, "oracle threshold, relative to the total emitted power"},
      {"min_area", &S::min_area, "smallest element area, relative to the total scene area"},
      {"iterations", &S::iterations, "refinement iterations (the paper uses 4)"},
      {"visibility_rays", &S::visibility_rays,
       "rays per link for the visibility estimate (0: no rays)"},
      {"pin", &S::pin, "thread pinning"},
      {"placement", &S::placement, "memory placement"},
      {"pool_order", &S::pool_order, "how central pools sort each submitted batch"},
      {"seed", &S::seed, "mixed into every per-link random number"},
      {"gather_tolerance", &S::gather_tolerance,
       "the last iteration's propagation stops when the estimated remaining change is "
       "below this fraction of the largest radiosity (earlier iterations at max(this, 1e-3))"},
      {"max_gather_sweeps", &S::max_gather_sweeps,
       "hard cap on gather + push-pull sweeps per iteration"},
      {"cluster_model", &S::cluster_model, "cluster projected areas"},
      {"cluster_receiver", &S::cluster_receiver,
       "how a cluster hands what it gathers to its members"},
      {"cluster_members", &S::cluster_members,
       "whether a cluster's members share and show its light by their exposure within it "
       "(cluster_receiver = cosine)"},
      {"row_sums", &S::row_sums, "leaf row-sum rescale, for studies"},
      {"row_sum_rays", &S::row_sum_rays,
       "rays per leaf that measure its covered share when row_sums = normalize"},
      {"locks_pool", &S::locks_pool, "hashed locks per lock class (0: twice the refiner count)"},
      {"trace", &S::trace, "file to record a task trace to (empty: none)"},
      {"image_width", &S::image_width, "render.png width in pixels (height: 3/4 of it)"},
      {"image_samples", &S::image_samples,
       "render.png's samples per pixel side: N x N stratified rays per pixel (1: one ray "
       "through the centre, stair-stepped edges)"},
      {"effects", &S::effects, "which effects are computed"},
      {"shaft_culling", &S::shaft_culling, "visibility without rays where a shaft is empty"},
      {"decision_rays", &S::decision_rays, "which rays an accepted link's visibility is from"},
      {"decision_visibility_rays", &S::decision_visibility_rays,
       "rays of a decision that depends on the visibility (the oracles' test of an occluded "
       "link with a cluster end; 0: visibility_rays); the link's own estimate has "
       "visibility_rays"},
      {"push_visibility", &S::push_visibility,
       "the visibility a push weight gives each child for a partly visible link"},
      {"max_memory_gb", &S::max_memory_gb,
       "a run stops with an error when loading or preparing the scene, or the refinement's "
       "elements and links, take more than this many GB (0: 3/4 of the machine's physical "
       "memory)"},
      {"camera", &S::camera,
       "render.png's camera: eye=X,Y,Z:look=X,Y,Z[:up=X,Y,Z][:fov=DEG], auto, or empty (the "
       "scene's own, else automatic)",
       &check_camera_text},
      {"sides", &S::sides, "back faces for two-sided materials"},
      {"emitter_sides", &S::emitter_sides, "whether the back face of a two-sided emitter emits"},
      {"segments", &S::segments,
       "divisions of a full circle for MGF sph, cyl, cone, ring and torus (0: by each "
       "shape's radius against the scene's diagonal, 16 to 128)"},
      {"shading", &S::shading, "how render.png and solution.ply shade the leaves"},
      {"exposure", &S::exposure,
       "render.png's exposure in stops over the automatic exposure (+1: twice as bright)"},
  };
  return table;
}

template <class T>
constexpr OptionType type_of_field() {
  if constexpr (std::is_same_v<T, int>) return OptionType::Int;
  if constexpr (std::is_same_v<T, std::uint64_t>) return OptionType::UInt64;
  if constexpr (std::is_same_v<T, double>) return OptionType::Double;
  return OptionType::String;  // strings, and modes by name
}

OptionType type_of(const Member& m) {
  return std::visit(
      [](auto member) {
        using T = std::remove_reference_t<decltype(std::declval<S&>().*member)>;
        return type_of_field<T>();
      },
      m);
}

/// The value names of a mode's row; empty for other rows.
std::vector<std::string> choices_of(const Member& m) {
  return std::visit(
      [](auto member) {
        using T = std::remove_reference_t<decltype(std::declval<S&>().*member)>;
        std::vector<std::string> names;
        if constexpr (kIsMode<T>)
          for (const auto& n : enum_names(T{})) names.emplace_back(n.name);
        return names;
      },
      m);
}

/// Help for a mode's row: its values with their meanings; "" for other rows.
std::string choices_help(const Member& m) {
  return std::visit(
      [](auto member) {
        using T = std::remove_reference_t<decltype(std::declval<S&>().*member)>;
        if constexpr (kIsMode<T>)
          return enum_help_list<T>();
        else
          return std::string();
      },
      m);
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

// A plug-in's declared parameter as an option key: KIND.NAME.KEY.
struct PluginRow {
  std::string key;     ///< "scheduler.stealing.victims"
  std::string kind;    ///< "scheduler" or "oracle"
  std::string plugin;  ///< "stealing"
  ParamSpec spec;
};

// Built on first use, from the registries (filled during static initialisation).
const std::vector<PluginRow>& plugin_rows() {
  static const std::vector<PluginRow> table = [] {
    std::vector<PluginRow> t;
    for (const std::string& n : scheduler_names())
      for (const ParamSpec& p : scheduler_params(n))
        t.push_back({fmt::format("scheduler.{}.{}", n, p.key), "scheduler", n, p});
    for (const std::string& n : oracle_names())
      for (const ParamSpec& p : oracle_params(n))
        t.push_back({fmt::format("oracle.{}.{}", n, p.key), "oracle", n, p});
    return t;
  }();
  return table;
}

// A plug-in key as written ('-' for '_' allowed; the dots are its separators).
const PluginRow* find_plugin_row(std::string_view key) {
  std::string k(key);
  for (char& c : k)
    if (c == '-') c = '_';
  for (const PluginRow& r : plugin_rows())
    if (k == r.key) return &r;
  return nullptr;
}

const std::string& selected(const SolverOptions& o, const PluginRow& r) {
  return r.kind == "scheduler" ? o.scheduler : o.oracle;
}

// Checks and stores one plug-in parameter's value (text).
void set_plugin_value(SolverOptions& o, const PluginRow& r, std::string_view value,
                      std::string_view source) {
  o.plugin_params[r.key] =
      check_param_value(r.spec, value, fmt::format("{}: option '{}'", source, r.key));
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

// What reading a value gave: the value, text of another type, or a whole number beyond
// what the key's integer type holds (told as out of range, not as "not an integer").
enum class Parsed { kOk, kBad, kBeyond };

Parsed parsed(bool ok) { return ok ? Parsed::kOk : Parsed::kBad; }

// A whole number as an integer of type T: in range, kOk and `out` set; kBeyond when it
// is finite and whole but T cannot hold it; kBad when it is not whole (or not finite).
template <class T>
Parsed whole_number_as(double d, T& out) {
  if (!std::isfinite(d) || d != std::trunc(d)) return Parsed::kBad;
  // 2^63 and 2^64 are exact doubles; the bounds of int are exact too.
  const double hi = std::is_same_v<T, int> ? std::numeric_limits<int>::max() : 0x1p64;
  const double lo = std::is_same_v<T, int> ? std::numeric_limits<int>::min() : 0;
  if (d < lo || (std::is_same_v<T, int> ? d > hi : d >= hi)) return Parsed::kBeyond;
  out = static_cast<T>(d);
  return Parsed::kOk;
}

// An integer key takes digits, or a whole number in any other form a number may be
// written in (1e9, 2.5e3): "1e9" for threads is out of range, not "not an integer", and
// "-1" for the seed is out of range too (it was refused as not an unsigned integer on
// the command line, and wrapped to 2^64 - 1 where a flag read it).
template <class T>
Parsed parse_integer(std::string_view text, T& out) {
  if (parse_number(text, out)) return Parsed::kOk;
  double d = 0;
  if (!parse_number(text, d)) return Parsed::kBad;
  return whole_number_as(d, out);
}

// Text -> typed value: kOk when the whole text is a valid value.
Parsed parse_value(std::string_view text, int& out) { return parse_integer(text, out); }
Parsed parse_value(std::string_view text, std::uint64_t& out) { return parse_integer(text, out); }
Parsed parse_value(std::string_view text, double& out) {
  return parsed(parse_number(text, out) && std::isfinite(out));
}
Parsed parse_value(std::string_view text, std::string& out) {
  out = std::string(text);
  return Parsed::kOk;
}
template <NamedEnum E>
Parsed parse_value(std::string_view text, E& out) {
  const std::optional<E> v = enum_from_name<E>(text);
  if (v) out = *v;
  return parsed(v.has_value());
}

// JSON -> typed value, strict: no fraction for an integer, no string for a number.
template <class T>
Parsed integer_from_json(const nlohmann::json& j, T& out) {
  if (!j.is_number()) return Parsed::kBad;
  if (j.is_number_unsigned()) {
    const auto v = j.get<std::uint64_t>();
    if (std::is_same_v<T, int> && v > static_cast<std::uint64_t>(std::numeric_limits<int>::max()))
      return Parsed::kBeyond;
    out = static_cast<T>(v);
    return Parsed::kOk;
  }
  if (j.is_number_integer()) {  // a negative integer (JSON's others are unsigned)
    const auto v = j.get<std::int64_t>();
    if (!std::is_same_v<T, int> || v < std::numeric_limits<int>::min()) return Parsed::kBeyond;
    out = static_cast<T>(v);
    return Parsed::kOk;
  }
  return whole_number_as(j.get<double>(), out);  // 1e9 is a float in JSON
}
Parsed from_json_value(const nlohmann::json& j, int& out) { return integer_from_json(j, out); }
Parsed from_json_value(const nlohmann::json& j, std::uint64_t& out) {
  return integer_from_json(j, out);
}
Parsed from_json_value(const nlohmann::json& j, double& out) {
  if (!j.is_number()) return Parsed::kBad;
  out = j.get<double>();
  return parsed(std::isfinite(out));
}
Parsed from_json_value(const nlohmann::json& j, std::string& out) {
  if (!j.is_string()) return Parsed::kBad;
  out = j.get<std::string>();
  return Parsed::kOk;
}
template <NamedEnum E>
Parsed from_json_value(const nlohmann::json& j, E& out) {
  return j.is_string() ? parse_value(j.get<std::string>(), out) : Parsed::kBad;
}

/// The range error of an integer key given a whole number its type cannot hold
/// (`text`, negative or not): the key's own rule, as validate_ranges words it for the
/// nearest value the type holds, else the type's bounds.
template <class T>
[[noreturn]] void beyond_type(const Row& r, T S::*member, std::string_view text, bool negative,
                              std::string_view source) {
  std::string rule = fmt::format("an integer between {} and {}", std::numeric_limits<T>::min(),
                                 std::numeric_limits<T>::max());
  SolverOptions o;
  o.*member = negative ? std::numeric_limits<T>::min() : std::numeric_limits<T>::max();
  try {
    validate_ranges(o);
  } catch (const std::invalid_argument& e) {
    const std::string_view what = e.what(), at = ": it must be ";
    if (what.find(fmt::format("option {} = ", r.name)) == 0 && what.find(at) != what.npos)
      rule = std::string(what.substr(what.find(at) + at.size()));
  }
  throw std::invalid_argument(fmt::format("{}{}option {} = {} is out of range: it must be {}",
                                          source, source.empty() ? "" : ": ", r.name,
                                          brief_text(text), rule));
}

/// What a value of this row must be, for a type error: "an integer", "a string", or
/// for a mode "one of none, compact, ...".
template <class T>
std::string expected(const Row& r) {
  if constexpr (kIsMode<T>)
    return fmt::format("one of {}", enum_name_list<T>());
  else {
    const OptionType t = type_of(r.member);
    return fmt::format("{} {}", t == OptionType::Int || t == OptionType::UInt64 ? "an" : "a",
                       option_type_name(t));
  }
}

/// A field's value as JSON (a mode by its name).
template <class T>
nlohmann::json to_json_value(const T& v) {
  if constexpr (kIsMode<T>)
    return enum_name(v);
  else
    return v;
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
          source.empty() ? fmt::format("option {} = '{}': {}", r.name, brief_text(value), e.what())
                         : fmt::format("{}: option '{}' = '{}': {}", source, r.name,
                                       brief_text(value), e.what()));
    }
  }
}

void check(bool ok, const char* key, const std::string& value, std::string_view rule) {
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
      // A plug-in key lists the plug-ins' own parameters (the keys KIND.NAME.KEY).
      std::string params;
      for (const PluginRow& p : plugin_rows())
        if (p.kind == r.name)
          params +=
              fmt::format("{}{}.{}", params.empty() ? "" : "; ", p.plugin, describe_param(p.spec));
      if (!params.empty())
        help += fmt::format("; parameters (--set {}.NAME.KEY=VALUE): {}", r.name, params);
      const std::string modes = choices_help(r.member);
      if (!modes.empty()) help += ": " + modes;
      t.push_back({r.name, type_of(r.member), std::move(help), choices_of(r.member)});
    }
    for (const PluginRow& r : plugin_rows())
      t.push_back({r.key,
                   r.spec.type == ParamSpec::Type::Int ? OptionType::Int : OptionType::Double,
                   fmt::format("{} {}'s parameter: {}", r.kind, r.plugin, describe_param(r.spec)),
                   {}});
    return t;
  }();
  return table;
}

const OptionInfo* find_option(std::string_view key) {
  const std::string c = canonical(key);
  const PluginRow* p = find_plugin_row(key);
  for (const OptionInfo& i : option_table())
    if (i.name == c || (p && i.name == p->key)) return &i;
  return nullptr;
}

std::string option_key_list() {
  std::string s;
  for (const Row& r : rows()) s += (s.empty() ? "" : ", ") + std::string(r.name);
  for (const PluginRow& r : plugin_rows()) s += ", " + r.key;
  return s;
}

nlohmann::json options_to_json(const SolverOptions& o) {
  nlohmann::json j = nlohmann::json::object();
  for (const Row& r : rows())
    std::visit([&](auto member) { j[r.name] = to_json_value(o.*member); }, r.member);
  // The selected plug-ins' parameters, given or default, so that the object is a
  // complete configuration of the run.
  for (const PluginRow& r : plugin_rows())
    if (selected(o, r) == r.plugin) {
      const auto it = o.plugin_params.find(r.key);
      const double v = it != o.plugin_params.end() ? std::stod(it->second) : r.spec.fallback;
      if (r.spec.type == ParamSpec::Type::Int)
        j[r.key] = static_cast<long long>(v);
      else
        j[r.key] = v;
    }
  return j;
}

std::string option_value_string(const SolverOptions& o, std::string_view key) {
  const Row* r = find_row(canonical(key));
  if (!r) {
    // A plug-in's parameter: its value when its plug-in is the selected one, else "".
    const PluginRow* p = find_plugin_row(key);
    if (!p) unknown_key("option_value_string", key);
    if (selected(o, *p) != p->plugin) return "";
    const auto it = o.plugin_params.find(p->key);
    return it != o.plugin_params.end() ? it->second : fmt::format("{}", p->spec.fallback);
  }
  return std::visit(
      [&](auto member) -> std::string {
        const auto& v = o.*member;
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::string>)
          return v;
        else if constexpr (kIsMode<T>)
          return enum_name(v);
        else
          return fmt::format("{}", v);
      },
      r->member);
}

void apply_options_json(SolverOptions& o, const nlohmann::json& j, const std::string& source) {
  if (!j.is_object())
    throw std::invalid_argument(
        fmt::format("{}: the configuration must be a JSON object of option keys, not a {}", source,
                    j.type_name()));
  std::string underflow;  // the first key whose number read as 0 (1e-400 does)
  for (const auto& item : j.items()) {
    // Named references, not a structured binding: clang 14 cannot capture those.
    const std::string& key = item.key();
    const nlohmann::json& value = item.value();
    const Row* r = find_row(key);
    if (!r) {
      const PluginRow* p = find_plugin_row(key);
      if (!p || p->key != key) unknown_key(source, key);
      if (!value.is_number() && !value.is_string())
        throw std::invalid_argument(fmt::format("{}: option '{}' expects a number, got {} {}",
                                                source, key, value.type_name(), brief_json(value)));
      set_plugin_value(o, *p, value.is_string() ? value.get<std::string>() : value.dump(), source);
      continue;
    }
    std::visit(
        [&](auto member) {
          auto v = o.*member;
          const Parsed p = from_json_value(value, v);
          if constexpr (std::is_integral_v<decltype(v)>)
            if (p == Parsed::kBeyond)
              beyond_type(*r, member, brief_json(value), value.get<double>() < 0, source);
          if (p != Parsed::kOk)
            throw std::invalid_argument(fmt::format("{}: option '{}' expects {}, got {} {}", source,
                                                    key, expected<decltype(v)>(*r),
                                                    value.type_name(), brief_json(value)));
          check_syntax(*r, v, source);
          o.*member = v;
        },
        r->member);
    if (value.is_number_float() && value.get<double>() == 0 && underflow.empty()) underflow = key;
  }
  // The file's values in range, said with its name (the whole check comes later, when
  // the command line has been applied too).
  try {
    validate_ranges(o);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format(
        "{}: {}{}", source, e.what(),
        underflow.empty() || std::string_view(e.what()).find("option " + underflow + " ") != 0
            ? ""
            : fmt::format(" (the number given for '{}' reads as 0: a number below "
                          "about 1e-308 is too small for a double)",
                          underflow)));
  }
}

void apply_option_value(SolverOptions& o, std::string_view key, std::string_view value,
                        std::string_view source) {
  const Row* r = find_row(canonical(key));
  if (!r) {
    const PluginRow* p = find_plugin_row(key);
    if (!p) unknown_key(source, key);
    set_plugin_value(o, *p, value, source);
    return;
  }
  std::visit(
      [&](auto member) {
        auto v = o.*member;
        const Parsed p = parse_value(value, v);
        if constexpr (std::is_integral_v<decltype(v)>)
          if (p == Parsed::kBeyond) beyond_type(*r, member, value, value.starts_with('-'), source);
        if (p != Parsed::kOk)
          throw std::invalid_argument(fmt::format("{}: option '{}' expects {}, got '{}'", source,
                                                  r->name, expected<decltype(v)>(*r),
                                                  brief_text(value)));
        check_syntax(*r, v, source);
        o.*member = v;
      },
      r->member);
}

void apply_option_assignment(SolverOptions& o, const std::string& key_eq_value) {
  const auto eq = key_eq_value.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument(fmt::format("--set {}: expected key=value (valid keys: {})",
                                            key_eq_value, option_key_list()));
  apply_option_value(o, std::string_view(key_eq_value).substr(0, eq),
                     std::string_view(key_eq_value).substr(eq + 1), "--set " + key_eq_value);
}

void validate_ranges(const SolverOptions& o) {
  const auto str = [](auto v) { return fmt::format("{}", v); };
  // Every number has an upper bound too, checked before anything is made: a thread
  // count of 100000 crashed the OpenMP runtime, a billion ran out of memory, and an
  // unbounded ray count made one task run for minutes (kMaxThreads and the others:
  // core/config/options.h).
  check(!o.scheduler.empty(), "scheduler", "\"\"", "a scheduler name");
  check(o.block_size >= 0 && o.block_size <= kMaxBlockSize, "block_size", str(o.block_size),
        fmt::format("between 0 (guided) and {}", kMaxBlockSize));
  check(o.threads >= 1 && o.threads <= kMaxThreads, "threads", str(o.threads),
        fmt::format("between 1 and {}", kMaxThreads));
  check(!o.oracle.empty(), "oracle", "\"\"", "an oracle name");
  check(std::isfinite(o.eps) && o.eps > 0, "eps", str(o.eps), "a finite number > 0");
  check(std::isfinite(o.min_area) && o.min_area >= 0 && o.min_area <= 1, "min_area",
        str(o.min_area), "a number between 0 and 1 (a fraction of the scene's area)");
  check(o.iterations >= 1 && o.iterations <= kMaxIterations, "iterations", str(o.iterations),
        fmt::format("between 1 and {}", kMaxIterations));
  check(o.visibility_rays >= 0 && o.visibility_rays <= kMaxRaysPerLink, "visibility_rays",
        str(o.visibility_rays), fmt::format("between 0 and {}", kMaxRaysPerLink));
  check(o.decision_visibility_rays >= 0 && o.decision_visibility_rays <= kMaxRaysPerLink,
        "decision_visibility_rays", str(o.decision_visibility_rays),
        fmt::format("between 0 and {}", kMaxRaysPerLink));
  check(std::isfinite(o.gather_tolerance) && o.gather_tolerance > 0 && o.gather_tolerance <= 1,
        "gather_tolerance", str(o.gather_tolerance), "a number > 0 and <= 1");
  check(o.max_gather_sweeps >= 1 && o.max_gather_sweeps <= kMaxGatherSweeps, "max_gather_sweeps",
        str(o.max_gather_sweeps), fmt::format("between 1 and {}", kMaxGatherSweeps));
  check(std::isfinite(o.max_memory_gb) && o.max_memory_gb >= 0 && o.max_memory_gb <= 1e9,
        "max_memory_gb", str(o.max_memory_gb), "a number of GB between 0 and 1e9");
  check(o.row_sum_rays >= 1 && o.row_sum_rays <= kMaxRowSumRays, "row_sum_rays",
        str(o.row_sum_rays), fmt::format("between 1 and {}", kMaxRowSumRays));
  check(o.locks_pool >= 0 && o.locks_pool <= kMaxLocksPool, "locks_pool", str(o.locks_pool),
        fmt::format("between 0 (automatic) and {}", kMaxLocksPool));
  check(o.image_width >= 8 && o.image_width <= 16384, "image_width", str(o.image_width),
        "between 8 and 16384");
  check(o.image_samples >= 1 && o.image_samples <= 16, "image_samples", str(o.image_samples),
        "between 1 and 16");
  check(o.segments == 0 || (o.segments >= 3 && o.segments <= 4096), "segments", str(o.segments),
        "0 (automatic) or between 3 and 4096");
  check(std::isfinite(o.exposure) && std::abs(o.exposure) <= 64, "exposure", str(o.exposure),
        "a number of stops between -64 and 64");
  for (const Row& r : rows())
    if (r.check_text) std::visit([&](auto member) { check_syntax(r, o.*member, ""); }, r.member);
}

void validate_options(const SolverOptions& o) {
  validate_ranges(o);
  // Plug-in parameters: declared, in range, and of the selected plug-in (nobody else
  // would read them).
  for (const auto& [key, value] : o.plugin_params) {
    const PluginRow* p = find_plugin_row(key);
    if (!p)
      throw std::invalid_argument(
          fmt::format("option {}: no scheduler or oracle declares it", key));
    (void)check_param_value(p->spec, value, fmt::format("option {}", key));
    if (selected(o, *p) != p->plugin)
      throw std::invalid_argument(fmt::format(
          "option {} = {}: the {} is {}, which does not read it (it is {} {}'s parameter)", key,
          value, p->kind, selected(o, *p), p->kind, p->plugin));
  }
}

ParamValues plugin_params_of(const SolverOptions& o, std::string_view kind) {
  const std::string prefix =
      fmt::format("{}.{}.", kind, kind == "scheduler" ? o.scheduler : o.oracle);
  ParamValues out;
  for (const auto& [key, value] : o.plugin_params)
    if (key.rfind(prefix, 0) == 0) out[key.substr(prefix.size())] = value;
  return out;
}

SceneLoadOptions scene_load_options(const SolverOptions& o) {
  return {o.sides, o.segments, o.emitter_sides};
}

}  // namespace hrad
