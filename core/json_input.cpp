#include "core/json_input.h"

#include <fmt/format.h>

#include <stdexcept>

namespace hrad {

void check_json_depth(std::string_view text, const std::string& source, bool comments) {
  int depth = 0, line = 1;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') ++line;
    if (in_string) {
      if (c == '\\') {
        ++i;  // the escaped character (a quote or a backslash) does not end the string
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (comments && c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
      continue;
    }
    if (comments && c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      for (i += 2; i < text.size() && !(text[i] == '*' && i + 1 < text.size() && text[i + 1] == '/'); ++i)
        if (text[i] == '\n') ++line;
      ++i;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw std::invalid_argument(fmt::format("{}:{}: JSON nested deeper than {} levels",
                                                source, line, kMaxJsonDepth));
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

std::string brief_text(std::string_view text) {
  if (text.size() <= kMaxEchoedChars) return std::string(text);
  return fmt::format("{}... ({} more characters)", text.substr(0, kMaxEchoedChars),
                     text.size() - kMaxEchoedChars);
}

}  // namespace hrad
