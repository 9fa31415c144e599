// Reading JSON documents that people write (configurations, cost files, manifests):
// a bound on nesting, no repeated keys, and short error messages.
//
// nlohmann::json parses any depth, but printing a value (dump) recurses once per
// level: a configuration of 100,000 nested brackets crashed hrad where it echoed the
// offending value, and at 50,000 levels the message was 100 KB long. So a document is
// checked for depth (kMaxJsonDepth levels, far more than any hrad file needs) and for
// keys given twice in one object (the parser keeps the last silently) before it is
// parsed, and values are echoed in errors through brief_json, which cuts them to
// kMaxEchoedChars.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <string_view>

namespace hrad {

/// Deepest nesting of arrays and objects accepted in a JSON document.
inline constexpr int kMaxJsonDepth = 64;
/// Longest echo of a value (or of the parser's own message) in an error.
inline constexpr std::size_t kMaxEchoedChars = 120;

/// Throws std::invalid_argument "SOURCE:LINE: JSON nested deeper than 64 levels"
/// when `text` nests arrays and objects deeper than kMaxJsonDepth (brackets inside
/// strings and, with `comments`, inside // and /* */ comments do not count), and
/// "SOURCE:LINE: key 'K' appears twice in one object" for a repeated key (the parser
/// would keep the last one silently). Syntax is the parser's to check.
void check_json_depth(std::string_view text, const std::string& source, bool comments);

/// The JSON parser's message whole, but the input it quotes after "last read: '" cut
/// as brief_text cuts it (cutting the whole message at kMaxEchoedChars ended it mid-word:
/// "... - unexpected string... (22 more characters)").
std::string brief_parse_error(std::string_view message);

/// `text` cut to kMaxEchoedChars, with the number of characters left out.
std::string brief_text(std::string_view text);

/// A value for an error message: its JSON text, cut by brief_text.
template <class Json>
std::string brief_json(const Json& value) {
  return brief_text(value.dump());
}

/// Parses a whole document: depth checked first; a syntax error or a number beyond a
/// double becomes std::invalid_argument "SOURCE: not valid JSON: ..." (the parser's
/// message, the text it quotes cut: brief_parse_error).
template <class Json>
Json parse_json_document(const std::string& text, const std::string& source, bool comments) {
  check_json_depth(text, source, comments);
  try {
    return Json::parse(text, nullptr, true, comments);
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for a number beyond a double (1e99999).
    throw std::invalid_argument(source + ": not valid JSON: " + brief_parse_error(e.what()));
  }
}

}  // namespace hrad
