// A fraction as a person reads it, in percent with three significant digits, as
// `hrad compare` prints its errors: 0.005 -> "0.5 %", 0.01 -> "1 %". Result files
// (CSV, JSON) keep fractions; this is for what is printed.
#pragma once

#include <fmt/format.h>

#include <string>

namespace hrad {

[[nodiscard]] inline std::string percent_text(double fraction) {
  return fmt::format("{:.3g} %", 100 * fraction);
}

}  // namespace hrad
