#include "core/base/json_input.h"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <vector>

namespace hrad {

void check_json_depth(std::string_view text, const std::string& source, bool comments) {
  // One entry per open array or object: whether it is an object, and its keys so far.
  struct Level {
    bool object = false;
    std::set<std::string_view> keys;
  };
  std::vector<Level> open;
  int line = 1;
  std::string_view last_string;  // the last string closed, a key if a ':' follows
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') ++line;
    if (comments && c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
      continue;
    }
    if (comments && c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      for (i += 2;
           i < text.size() && !(text[i] == '*' && i + 1 < text.size() && text[i + 1] == '/'); ++i)
        if (text[i] == '\n') ++line;
      ++i;
      continue;
    }
    if (c == '"') {
      const std::size_t start = ++i;
      for (; i < text.size() && text[i] != '"'; ++i) {
        if (text[i] == '\\')
          ++i;  // the escaped character does not end the string
        else if (text[i] == '\n')
          ++line;
      }
      last_string = text.substr(start, std::min(i, text.size()) - start);
    } else if (c == ':') {
      if (!open.empty() && open.back().object && !open.back().keys.insert(last_string).second)
        throw std::invalid_argument(fmt::format("{}:{}: key '{}' appears twice in one object",
                                                source, line, brief_text(last_string)));
    } else if (c == '[' || c == '{') {
      if (static_cast<int>(open.size()) >= kMaxJsonDepth)
        throw std::invalid_argument(
            fmt::format("{}:{}: JSON nested deeper than {} levels", source, line, kMaxJsonDepth));
      open.push_back(Level{c == '{', {}});
    } else if ((c == ']' || c == '}') && !open.empty()) {
      open.pop_back();
    }
  }
}

std::string brief_parse_error(std::string_view message) {
  constexpr std::string_view kQuote = "last read: '";
  const std::size_t at = message.find(kQuote);
  const std::size_t end = message.rfind('\'');
  if (at == std::string_view::npos || end == std::string_view::npos || end <= at + kQuote.size())
    return std::string(message);
  const std::size_t from = at + kQuote.size();
  return std::string(message.substr(0, from)) + brief_text(message.substr(from, end - from)) +
         std::string(message.substr(end));
}

std::string brief_text(std::string_view text) {
  if (text.size() <= kMaxEchoedChars) return std::string(text);
  return fmt::format("{}... ({} more characters)", text.substr(0, kMaxEchoedChars),
                     text.size() - kMaxEchoedChars);
}

}  // namespace hrad
