// MGF named contexts (colours, materials, vertices) and the `<kw> [id [= [tmpl]]]`
// rule they share:
//   kw              select the unnamed context, reset to the default (changes to it are
//                   not kept beyond the next bare `kw`)
//   kw id           reselect a defined context (undefined: InputError)
//   kw id =         (re)define id, cleared to the default
//   kw id = tmpl    (re)define id as a copy of the defined context tmpl
// Every change to a context's value takes a new `clock` from a counter shared by all
// tables, so (clock) identifies one exact value and caches keyed by it never go stale.
#pragma once

#include "core/base/geometry.h"
#include "core/base/input_error.h"
#include "core/scene/scene_builder.h"

#include <fmt/format.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>

namespace hrad {

/// CIE 1931 chromaticity; the default is equal-energy grey.
struct MgfColour {
  double x = 1.0 / 3.0;
  double y = 1.0 / 3.0;
  bool grey = true;  ///< within kGreyTolerance of (1/3, 1/3): converts to exact grey
};

struct MgfMaterial {
  double rd = 0;  ///< diffuse reflectance (luminous factor, 0..1)
  MgfColour rd_colour;
  double ed = 0;  ///< diffuse emittance, lm/m^2
  MgfColour ed_colour;
  int sides = 2;
};

struct MgfVertex {
  Vec3 p = Vec3::Zero();
  Vec3 n = Vec3::Zero();  ///< zero: no normal
};

template <class T>
struct MgfEntry {
  std::string name;  ///< empty for the unnamed context
  T value{};
  std::uint64_t clock = 0;
  // Materials only: the Scene material made for `clock` (UINT32_MAX: none yet).
  std::uint32_t built = UINT32_MAX;
  std::uint64_t built_clock = 0;
};

template <class T>
class MgfContextTable {
 public:
  MgfContextTable(std::string_view entity, std::string_view kind, std::uint64_t& clock)
      : entity_(entity), kind_(kind), clock_(&clock) {
    unnamed_.clock = ++*clock_;
  }
  MgfContextTable(const MgfContextTable&) = delete;
  MgfContextTable& operator=(const MgfContextTable&) = delete;

  MgfEntry<T>& current() { return *current_; }
  /// The context with this name; InputError at `at` when it was never defined.
  MgfEntry<T>& get(std::string_view name, const SourceLoc& at) {
    const auto it = named_.find(name);
    if (it == named_.end())
      throw InputError(at.file, at.line, fmt::format("undefined {} '{}'", kind_, name));
    return *it->second;
  }
  /// Marks the current context changed (call after modifying its value).
  void touch() { current_->clock = ++*clock_; }

  /// Applies `kw [id [= [tmpl]]]`; `args` excludes the keyword.
  void select(std::span<const std::string_view> args, const SourceLoc& at) {
    if (args.empty()) {
      unnamed_.value = T{};
      unnamed_.clock = ++*clock_;
      current_ = &unnamed_;
      return;
    }
    if (args[0] == "=" || args.size() > 3 || (args.size() >= 2 && args[1] != "="))
      throw InputError(at.file, at.line,
                       fmt::format("{}: expected '{} [id [= [template]]]'", entity_, entity_));
    if (args.size() == 1) {
      current_ = &get(args[0], at);
      return;
    }
    T value{};
    if (args.size() == 3) value = get(args[2], at).value;
    auto& slot = named_[std::string(args[0])];
    if (!slot) {
      slot = std::make_unique<MgfEntry<T>>();
      slot->name = std::string(args[0]);
    }
    slot->value = value;
    slot->clock = ++*clock_;
    current_ = slot.get();
  }

 private:
  std::string entity_, kind_;
  std::uint64_t* clock_;
  MgfEntry<T> unnamed_;
  MgfEntry<T>* current_ = &unnamed_;
  // unique_ptr: entries stay put when the table grows (current_ points into it).
  struct NameHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>()(s); }
  };
  std::unordered_map<std::string, std::unique_ptr<MgfEntry<T>>, NameHash, std::equal_to<>> named_;
};

}  // namespace hrad
