#include "core/scene/builtin_scenes.h"

#include "core/base/input_error.h"
#include "core/base/parse_number.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

namespace hrad {

namespace {

constexpr std::string_view kPrefix = "builtin:";
// builtin:NAME,k=v,k=v (no shell quoting needed) or builtin:NAME?k=v&k=v (the URL-like
// form, which the shell splits at '&' unless quoted). The two may be mixed.
constexpr std::string_view kListStart = ",?";
constexpr std::string_view kListSeparators = ",&";

struct Entry {
  BuiltinInfo (*info)();
  Scene (*make)(const builtin::Args&);
};

const std::vector<Entry>& entries() {
  static const std::vector<Entry> e = {
      {builtin::cornell_info, builtin::make_cornell},
      {builtin::furnace_info, builtin::make_furnace},
      {builtin::office_info, builtin::make_office},
      {builtin::lab_info, builtin::make_lab},
      {builtin::cabin_info, builtin::make_cabin},
  };
  return e;
}

std::string known_scenes() {
  std::string s;
  for (const BuiltinInfo& i : builtin_scenes()) s += (s.empty() ? "" : ", ") + i.name;
  return s;
}

std::string known_params(const BuiltinInfo& info) {
  std::string s;
  for (const BuiltinParam& p : info.params) s += (s.empty() ? "" : ", ") + p.name;
  return s.empty() ? "(none)" : s;
}

}  // namespace

namespace builtin {

double Args::get(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end())
    throw std::logic_error("builtin scene asks for undeclared parameter '" + name + "'");
  return it->second;
}

int Args::get_int(const std::string& name) const {
  return static_cast<int>(std::lround(get(name)));
}

}  // namespace builtin

const std::vector<BuiltinInfo>& builtin_scenes() {
  static const std::vector<BuiltinInfo> infos = [] {
    std::vector<BuiltinInfo> v;
    for (const Entry& e : entries()) v.push_back(e.info());
    return v;
  }();
  return infos;
}

bool is_builtin_spec(std::string_view spec) { return spec.starts_with(kPrefix); }

std::string builtin_base(std::string_view spec) {
  if (!is_builtin_spec(spec)) return std::string(spec);
  const std::size_t q = spec.find_first_of(kListStart, kPrefix.size());
  return std::string(spec.substr(0, q));
}

std::string normal_builtin_spec(std::string_view spec) {
  std::string s(spec);
  if (!is_builtin_spec(spec)) return s;
  for (std::size_t i = kPrefix.size(); i < s.size(); ++i)
    if (s[i] == '?' || s[i] == '&') s[i] = ',';
  return s;
}

std::vector<std::string> split_scene_list(std::string_view list) {
  // A piece "identifier=..." right after a builtin spec is one of its parameters.
  auto is_param = [](std::string_view piece) {
    const std::size_t eq = piece.find('=');
    if (eq == 0 || eq == std::string_view::npos) return false;
    for (const char c : piece.substr(0, eq))
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
  };
  std::vector<std::string> scenes;
  bool in_builtin = false;
  std::size_t pos = 0;
  while (pos <= list.size()) {
    const std::size_t comma = std::min(list.find(',', pos), list.size());
    const std::string_view piece = list.substr(pos, comma - pos);
    pos = comma + 1;
    if (piece.empty()) {
      in_builtin = false;
      continue;
    }
    if (in_builtin && is_param(piece)) {
      (scenes.back() += ',') += piece;
      continue;
    }
    scenes.emplace_back(piece);
    in_builtin = is_builtin_spec(piece);
  }
  return scenes;
}

namespace {

struct ParsedSpec {
  std::size_t which = 0;  ///< index into entries() and builtin_scenes()
  std::map<std::string, double> values;
};

ParsedSpec parse_spec(const std::string& spec) {
  auto fail = [&](const std::string& what) { return InputError(spec, 0, what); };
  if (!is_builtin_spec(spec))
    throw fail(fmt::format("not a builtin scene spec (it must start with '{}')", kPrefix));
  const std::string_view rest = std::string_view(spec).substr(kPrefix.size());
  const std::size_t q = rest.find_first_of(kListStart);
  const std::string name(rest.substr(0, q));
  const std::string_view query = q == std::string_view::npos ? "" : rest.substr(q + 1);

  const auto& list = entries();
  std::size_t which = list.size();
  for (std::size_t i = 0; i < list.size(); ++i)
    if (builtin_scenes()[i].name == name) which = i;
  if (which == list.size())
    throw fail(fmt::format("unknown builtin scene '{}' (known: {})", name, known_scenes()));
  const BuiltinInfo& info = builtin_scenes()[which];

  std::map<std::string, double> values;
  for (const BuiltinParam& p : info.params) values[p.name] = p.default_value;
  std::map<std::string, bool> given;
  std::size_t pos = 0;
  while (q != std::string_view::npos && pos <= query.size()) {
    const std::size_t amp = std::min(query.find_first_of(kListSeparators, pos), query.size());
    const std::string_view item = query.substr(pos, amp - pos);
    pos = amp + 1;
    const std::size_t eq = item.find('=');
    if (item.empty()) throw fail("empty parameter (a stray ',', '?' or '&')");
    if (eq == std::string_view::npos || eq == 0)
      throw fail(fmt::format("parameter '{}' is not of the form name=value", item));
    const std::string key(item.substr(0, eq));
    const std::string_view text = item.substr(eq + 1);
    const BuiltinParam* param = nullptr;
    for (const BuiltinParam& p : info.params)
      if (p.name == key) param = &p;
    if (param == nullptr)
      throw fail(fmt::format("unknown parameter '{}' for builtin scene '{}' (valid: {})", key, name,
                             known_params(info)));
    if (given[key]) throw fail(fmt::format("parameter '{}' is given twice", key));
    given[key] = true;
    double v = 0;
    if (!parse_finite_number(text, v))
      throw fail(fmt::format("parameter '{}': '{}' is not a number", key, text));
    if (param->integer && v != std::floor(v))
      throw fail(fmt::format("parameter '{}': '{}' is not an integer", key, text));
    if (v < param->min_value || v > param->max_value)
      throw fail(fmt::format("parameter '{}': {} is outside [{}, {}]", key, text, param->min_value,
                             param->max_value));
    values[key] = v;
  }
  return {which, std::move(values)};
}

}  // namespace

Scene make_builtin(const std::string& spec) {
  ParsedSpec p = parse_spec(spec);
  return entries()[p.which].make(builtin::Args(spec, std::move(p.values)));
}

void check_builtin_spec(const std::string& spec) { (void)parse_spec(spec); }

}  // namespace hrad
