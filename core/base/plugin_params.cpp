#include "core/base/plugin_params.h"

#include "core/base/parse_number.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hrad {
namespace {

std::string key_list(std::span<const ParamSpec> specs) {
  std::string s;
  for (const ParamSpec& p : specs) s += (s.empty() ? "" : ", ") + std::string(p.key);
  return s.empty() ? "none" : s;
}

std::string number_text(double v) { return fmt::format("{}", v); }

}  // namespace

std::string check_param_value(const ParamSpec& spec, std::string_view value,
                              std::string_view what) {
  double v = 0;
  const bool integer = spec.type == ParamSpec::Type::Int;
  if (!parse_finite_number(value, v) || (integer && v != std::floor(v)))
    throw std::invalid_argument(
        fmt::format("{} = '{}': expected {}", what, value, integer ? "an integer" : "a number"));
  if (v < spec.lo || v > spec.hi)
    throw std::invalid_argument(fmt::format("{} = {} is out of range: it must be between {} and {}",
                                            what, value, number_text(spec.lo),
                                            number_text(spec.hi)));
  return integer ? fmt::format("{}", static_cast<long long>(v)) : number_text(v);
}

std::string describe_param(const ParamSpec& spec) {
  return fmt::format("{} ({} {} ... {}, default {}): {}", spec.key,
                     spec.type == ParamSpec::Type::Int ? "integer" : "number", number_text(spec.lo),
                     number_text(spec.hi), number_text(spec.fallback), spec.help);
}

PluginParams::PluginParams(std::string owner, std::span<const ParamSpec> specs,
                           const ParamValues& values)
    : owner_(std::move(owner)), specs_(specs), values_(values) {}

const ParamSpec& PluginParams::spec(std::string_view key, ParamSpec::Type type) const {
  const auto it =
      std::find_if(specs_.begin(), specs_.end(), [&](const ParamSpec& p) { return key == p.key; });
  if (it == specs_.end() || it->type != type)
    throw std::logic_error(fmt::format(
        "{}: reads parameter '{}', which it does not declare as that type", owner_, key));
  if (std::find(read_.begin(), read_.end(), key) == read_.end()) read_.emplace_back(key);
  return *it;
}

int PluginParams::get_int(std::string_view key) const {
  const ParamSpec& s = spec(key, ParamSpec::Type::Int);
  const auto it = values_.find(key);
  if (it == values_.end()) return static_cast<int>(s.fallback);
  return std::stoi(check_param_value(s, it->second, owner_ + " " + s.key));
}

double PluginParams::get_double(std::string_view key) const {
  const ParamSpec& s = spec(key, ParamSpec::Type::Double);
  const auto it = values_.find(key);
  if (it == values_.end()) return s.fallback;
  return std::stod(check_param_value(s, it->second, owner_ + " " + s.key));
}

void PluginParams::report_unused() const {
  for (const auto& item : values_) {
    // Named references, not a structured binding: clang 14 cannot capture those.
    const std::string& key = item.first;
    const std::string& value = item.second;
    const bool declared =
        std::any_of(specs_.begin(), specs_.end(), [&](const ParamSpec& p) { return key == p.key; });
    if (!declared)
      throw std::invalid_argument(fmt::format("{}: unknown parameter '{}' (parameters: {})", owner_,
                                              key, key_list(specs_)));
    if (std::find(read_.begin(), read_.end(), key) == read_.end())
      throw std::invalid_argument(
          fmt::format("{}: parameter '{}' = {} was given but never read", owner_, key, value));
  }
}

}  // namespace hrad
