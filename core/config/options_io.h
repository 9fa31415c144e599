// Reading and writing SolverOptions: the JSON config file, `--set key=value` and the
// CLI flags all go through one table of keys (options_io.cpp), so every key has
// exactly one name, one type and one help text, and a typo is always an error that
// names it (never silently ignored).
//
// Key names are the field names of SolverOptions (core/config/options.h). In `--set` (and
// apply_option_value) a key may also be written with '.' or '-' instead of '_'
// ("locks.pool", "block-size"); JSON config files use the canonical names only.
// A plug-in's own parameters (core/base/plugin_params.h) are keys too, one per declared
// parameter of every registered scheduler and oracle: KIND.NAME.KEY
// ("scheduler.stealing.victims", "oracle.bf.dark_floor"; '-' may replace '_' in
// `--set`). They are listed after the fields, typed and range-checked by their
// declaration, and only the selected plug-in's may be set.
#pragma once

#include "core/config/options.h"
#include "core/scene/scene_loader.h"

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace hrad {

enum class OptionType { Int, UInt64, Double, String };

/// Human name of a type, as used in error messages: "integer", "unsigned integer",
/// "number", "string".
[[nodiscard]] const char* option_type_name(OptionType t);

/// One row of the key table (without the accessors, which stay private).
struct OptionInfo {
  std::string name;
  OptionType type;
  std::string help;  ///< one line: meaning and unit, without the default
  /// A mode's value names, from its enum's table (core/base/enum_names.h), in table
  /// order; empty for other keys. Such a key is a string in JSON, and any other text
  /// is an error naming these.
  std::vector<std::string> choices;
};

/// Every key in table order (the order of core/config/options.h). The scheduler and oracle
/// help lists the registries' names, so the table is built on first use: not during
/// static initialisation, when plug-ins may still be registering.
[[nodiscard]] const std::vector<OptionInfo>& option_table();

/// The row for a key (canonical name or alias); nullptr when there is none.
[[nodiscard]] const OptionInfo* find_option(std::string_view key);

/// "scheduler, block_size, ..." — for error and help messages.
[[nodiscard]] std::string option_key_list();

/// Every key with its current value; apply_options_json of the result restores `o`.
[[nodiscard]] nlohmann::json options_to_json(const SolverOptions& o);

/// A key's current value as text ("4", "1e-04", "stack").
[[nodiscard]] std::string option_value_string(const SolverOptions& o, std::string_view key);

/// Applies the keys present in `j` (a JSON object) to `o`; absent keys are left alone.
/// `source` (a file name) starts every error message. Throws std::invalid_argument
/// for a non-object, an unknown key (listing the valid ones) or a value of the wrong
/// type (naming key and expected type), and for a value out of range once the file is
/// applied (validate_ranges, with `source` and a word on numbers that underflow to 0).
void apply_options_json(SolverOptions& o, const nlohmann::json& j, const std::string& source);

/// Parses `value` as the key's type and stores it. `source` ("--set", "--threads")
/// starts every error message. Throws std::invalid_argument for an unknown key or an
/// unparsable value (whole text must parse; integers must fit their type).
void apply_option_value(SolverOptions& o, std::string_view key, std::string_view value,
                        std::string_view source);

/// `--set key=value`: splits at the first '=' and calls apply_option_value.
void apply_option_assignment(SolverOptions& o, const std::string& key_eq_value);

/// Range checks (threads >= 1, eps > 0, ...). Throws std::invalid_argument whose
/// message names the first offending option, its value and the allowed range.
void validate_options(const SolverOptions& o);
/// The same without the plug-in parameters' check against the selected plug-ins (which
/// a later source may select): what apply_options_json checks of a file's values.
void validate_ranges(const SolverOptions& o);

/// The selected plug-in's parameters, by KEY: the `kind` ("scheduler" or "oracle") keys
/// KIND.NAME.KEY of o.plugin_params whose NAME is o.scheduler (o.oracle).
[[nodiscard]] ParamValues plugin_params_of(const SolverOptions& o, std::string_view kind);

/// The scene options of a (validated) configuration: its `sides`, `emitter_sides` and
/// `segments` keys.
[[nodiscard]] SceneLoadOptions scene_load_options(const SolverOptions& o);

}  // namespace hrad
