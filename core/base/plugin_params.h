// Parameters of a plug-in (a scheduler, an oracle): each plug-in declares its own at
// registration (ParamSpec: key, type, default, range, meaning), the user sets them as
// option keys KIND.NAME.KEY (`--set scheduler.stealing.victims=2`, or the same key in a
// config file), and the plug-in reads them through PluginParams when it is created.
// Whatever was given and not read is an error (pbrt's ReportUnused), so a parameter is
// never silently ignored: core/config/options_io.cpp refuses keys no plug-in declares
// and parameters of a plug-in that is not the one selected, and the registries report
// what their plug-in's factory did not read.
#pragma once

#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hrad {

struct ParamSpec {
  enum class Type { Int, Double };
  const char* key;
  Type type;
  double fallback;   ///< the default
  double lo, hi;     ///< allowed range, inclusive
  const char* help;  ///< one line: meaning and unit, without default or range
};

/// Parameter values as given, by key (without the KIND.NAME. prefix): the text of the
/// value, already checked against its spec by options_io (or raw, from code and tests).
using ParamValues = std::map<std::string, std::string, std::less<>>;

/// `value` as `spec`'s type within its range, as canonical text ("2", "0.25"); throws
/// std::invalid_argument "WHAT = VALUE: ..." naming the type or the range otherwise.
[[nodiscard]] std::string check_param_value(const ParamSpec& spec, std::string_view value,
                                            std::string_view what);

/// "victims (integer 0 ... 4096, default 0): other refiners ..." — for --help.
[[nodiscard]] std::string describe_param(const ParamSpec& spec);

/// What a factory reads its parameters from.
class PluginParams {
 public:
  /// `owner` ("scheduler stealing") starts every error message.
  PluginParams(std::string owner, std::span<const ParamSpec> specs, const ParamValues& values);

  /// The value of a declared parameter, or its default; std::logic_error for a key the
  /// plug-in did not declare (a plug-in bug). Marks the key as read.
  [[nodiscard]] int get_int(std::string_view key) const;
  [[nodiscard]] double get_double(std::string_view key) const;

  /// Throws std::invalid_argument for any given value that is undeclared, or declared
  /// and not read: "OWNER: parameter 'KEY' ... (parameters: ...)".
  void report_unused() const;

 private:
  const ParamSpec& spec(std::string_view key, ParamSpec::Type type) const;
  std::string owner_;
  std::span<const ParamSpec> specs_;
  ParamValues values_;
  mutable std::vector<std::string> read_;
};

}  // namespace hrad
