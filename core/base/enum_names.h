// One table of names per enumerated option: every enum that a user names (an option
// value, a CLI choice) declares, next to its definition, the function
//
//   constexpr std::span<const EnumName<E>> enum_names(E) { return kTable; }
//
// (found by argument-dependent lookup), and parsing, printing, validation, --help and the
// "allowed" column of docs/configuration.md (checked by tests/options_io_test.cpp) all
// come from it. A new value is one row of its table.
#pragma once

#include <fmt/format.h>

#include <concepts>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

namespace hrad {

template <class E>
struct EnumName {
  E value;
  const char* name;
  /// What the value means, for --help ("" when the option's own help says it).
  const char* meaning = "";
};

template <class E>
concept NamedEnum = std::is_enum_v<E> && requires(E e) {
  { enum_names(e) } -> std::convertible_to<std::span<const EnumName<E>>>;
};

/// The value named `text`, exactly (case-sensitive); nullopt when none is.
template <NamedEnum E>
[[nodiscard]] constexpr std::optional<E> enum_from_name(std::string_view text) {
  for (const EnumName<E>& n : enum_names(E{}))
    if (text == n.name) return n.value;
  return std::nullopt;
}

/// The name of `v` ("?" for a value outside the table, which a cast could make).
template <NamedEnum E>
[[nodiscard]] constexpr const char* enum_name(E v) {
  for (const EnumName<E>& n : enum_names(E{}))
    if (n.value == v) return n.name;
  return "?";
}

/// "none, compact, scatter, node-round-robin": the names in table order.
template <NamedEnum E>
[[nodiscard]] std::string enum_name_list() {
  std::string s;
  for (const EnumName<E>& n : enum_names(E{})) s += (s.empty() ? "" : ", ") + std::string(n.name);
  return s;
}

/// The names with their meanings: "isotropic (A/4 ...), directional (...)".
template <NamedEnum E>
[[nodiscard]] std::string enum_help_list() {
  std::string s;
  for (const EnumName<E>& n : enum_names(E{})) {
    s += (s.empty() ? "" : ", ") + std::string(n.name);
    if (*n.meaning) s += fmt::format(" ({})", n.meaning);
  }
  return s;
}

/// enum_from_name, or std::invalid_argument "WHAT: unknown value 'TEXT' (allowed: ...)".
template <NamedEnum E>
[[nodiscard]] E parse_enum(std::string_view text, std::string_view what) {
  if (const std::optional<E> v = enum_from_name<E>(text)) return *v;
  throw std::invalid_argument(
      fmt::format("{}: unknown value '{}' (allowed: {})", what, text, enum_name_list<E>()));
}

}  // namespace hrad

/// fmt prints a named enum by its name.
template <hrad::NamedEnum E>
struct fmt::formatter<E> : fmt::formatter<std::string_view> {
  template <class Context>
  auto format(E v, Context& ctx) const {
    return fmt::formatter<std::string_view>::format(hrad::enum_name(v), ctx);
  }
};
