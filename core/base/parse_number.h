// Strict number parsing for text the user wrote (scene specs, camera specs): the whole
// text must be one finite number, in the C locale.
#pragma once

#include <charconv>
#include <cmath>
#include <string_view>
#include <system_error>

namespace hrad {

/// A finite number spelled in full (no leading or trailing junk, no inf or nan): true
/// and `out` set, else false.
inline bool parse_finite_number(std::string_view text, double& out) {
  if (text.empty()) return false;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end && std::isfinite(out);
}

}  // namespace hrad
