// CLI11's parse errors in hrad's words. CLI11 says "The following arguments were not
// expected: 1 --bogus", "Value x not in range 1 to 1048576", "--out: 1 required DIR
// missing" or, for `hrad --bogus`, "A subcommand is required"; hrad names the option
// and what is wrong with it: "solve: unknown option --bogus (see hrad solve --help)".
// Messages CLI11 may give that are not listed here pass through unchanged.
#include "experiments/commands.h"

#include "core/config/options_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <regex>
#include <system_error>

namespace hrad::cli {
namespace {

bool is_number(const std::string& text) {
  double v = 0;
  const char* end = text.data() + text.size();
  const auto r = std::from_chars(text.data(), end, v);
  return !text.empty() && r.ec == std::errc() && r.ptr == end && std::isfinite(v);
}

/// A word that CLI11 would take as an option: "-x", "--name" or "--name=value", not a
/// negative number.
bool is_option_word(const std::string& word) {
  return word.size() > 1 && word[0] == '-' && !is_number(word);
}

std::string option_name(const std::string& word) { return word.substr(0, word.find('=')); }

/// "1048576" for 1048576.000000 (CLI11 writes its bounds with std::to_string), "0.5".
std::string number_text(const std::string& text) {
  if (!is_number(text)) return text;
  const double v = std::stod(text);
  if (v == std::floor(v) && std::abs(v) < 1e15) return fmt::format("{}", static_cast<long long>(v));
  return fmt::format("{:g}", v);
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

/// " (did you mean --threads?)" for "--thread": the command's closest long option when
/// it is at most two edits away; else "".
std::string option_hint(const CLI::App& command, const std::string& word) {
  if (word.rfind("--", 0) != 0) return "";
  const std::string name = option_name(word).substr(2);
  std::string best;
  std::size_t best_d = 3;
  for (const CLI::Option* o : command.get_options())
    for (const std::string& l : o->get_lnames()) {
      const std::size_t d = edit_distance(name, l);
      if (d < best_d && l != name) best_d = d, best = l;
    }
  return best.empty() || name.size() < 3 ? "" : fmt::format(" (did you mean --{}?)", best);
}

/// " (KEY is a configuration key without a flag of its own: use --set KEY=VALUE)" for
/// an unknown flag that names a configuration key, in the commands that take --set.
std::string config_key_hint(const std::string& command, const std::string& word) {
  if (word.rfind("--", 0) != 0 || (command != "solve" && command != "experiment")) return "";
  std::string key = option_name(word).substr(2);
  std::replace(key.begin(), key.end(), '-', '_');
  if (find_option(key) == nullptr) return "";
  return fmt::format(" ({} is a configuration key without a flag of its own: use --set {}=VALUE)",
                     key, key);
}

/// "unknown option --a", "unknown options --a, --b", "unexpected argument 'x'": the
/// words CLI11 could not place, in command-line order (its message lists them last
/// first), unknown options first (a stray word after one is most likely its value).
std::string extras_text(const CLI::App& command, const std::string& command_name,
                        const std::vector<std::string>& words) {
  std::vector<std::string> options, others;
  for (const std::string& w : words) (is_option_word(w) ? options : others).push_back(w);
  if (!options.empty()) {
    std::string text = options.size() == 1 ? "unknown option " : "unknown options ";
    for (std::size_t i = 0; i < options.size(); ++i)
      text += (i > 0 ? ", " : "") + option_name(options[i]);
    for (const std::string& o : options) {
      const std::string hint = config_key_hint(command_name, o);
      text += hint.empty() ? option_hint(command, o) : hint;
    }
    return text;
  }
  std::string text = others.size() == 1 ? "unexpected argument " : "unexpected arguments ";
  for (std::size_t i = 0; i < others.size(); ++i)
    text += fmt::format("{}'{}'", i > 0 ? ", " : "", others[i]);
  return text;
}

std::vector<std::string> words_after_colon(const std::string& what) {
  std::vector<std::string> words;
  const std::size_t colon = what.find(": ");
  if (colon == std::string::npos) return words;
  std::string rest = what.substr(colon + 2);
  for (std::size_t pos = 0; pos <= rest.size();) {
    const std::size_t space = std::min(rest.find(' ', pos), rest.size());
    if (space > pos) words.push_back(rest.substr(pos, space - pos));
    pos = space + 1;
  }
  std::reverse(words.begin(), words.end());  // CLI11 joins them last first
  return words;
}

/// "'x' is not a whole number" and the like for a value CLI11 could not convert to the
/// option's type.
std::string conversion_text(const CLI::App& command, const std::string& name,
                            const std::string& value) {
  const CLI::Option* o = command.get_option_no_throw(name);
  const std::string type = o == nullptr ? "" : o->get_type_name();
  if (type.rfind("INT", 0) == 0 || type.rfind("UINT", 0) == 0)
    return fmt::format("{}: '{}' is not a whole number", name, value);
  if (type.rfind("FLOAT", 0) == 0) return fmt::format("{}: '{}' is not a number", name, value);
  return fmt::format("{}: '{}' is not a valid value", name, value);
}

template <class Error>
bool is_a(const CLI::ParseError& e) {
  return dynamic_cast<const Error*>(&e) != nullptr;
}

/// The message in hrad's words, without the command's name and the help hint.
std::string translate(const CLI::ParseError& e, const CLI::App& command,
                      const std::string& command_name, const std::vector<std::string>& argv) {
  // By type, not by e.get_name(): an ExtrasError thrown by a subcommand carries the
  // subcommand's name there.
  const std::string what = e.what();
  std::smatch m;
  if (is_a<CLI::ExtrasError>(e)) return extras_text(command, command_name, words_after_colon(what));
  if (is_a<CLI::RequiredError>(e)) {
    // `hrad --bogus`: CLI11 misses the command before it looks at the options.
    if (what.find("subcommand") != std::string::npos) {
      std::vector<std::string> options;
      for (std::size_t i = 1; i < argv.size(); ++i)
        if (is_option_word(argv[i])) options.push_back(argv[i]);
      return options.empty() ? "no command given" : extras_text(command, "", options);
    }
    // `hrad experiment --bogus`: an unknown option says more than the missing
    // positional it displaced.
    std::vector<std::string> unknown;
    for (std::size_t i = 1; i < argv.size(); ++i)
      if (argv[i] != command_name && is_option_word(argv[i]) &&
          command.get_option_no_throw(option_name(argv[i])) == nullptr)
        unknown.push_back(argv[i]);
    if (!unknown.empty()) return extras_text(command, command_name, unknown);
    if (std::regex_match(what, m, std::regex("(.+) is required")))
      return fmt::format("{} is missing", m[1].str());
    return what;
  }
  if (is_a<CLI::ArgumentMismatch>(e)) {
    // "--out: 1 required DIR missing"; the type may carry a validator's range after ':'.
    if (std::regex_match(what, m, std::regex(R"((\S+): (\d+) required (.*) missing)"))) {
      const std::string type = m[3].str().substr(0, m[3].str().find(':'));
      const std::string shown = type.empty() ? "" : " (" + type + ")";
      return m[2] == "1" ? fmt::format("{} needs a value{}", m[1].str(), shown)
                         : fmt::format("{} needs {} values{}", m[1].str(), m[2].str(), shown);
    }
    if (std::regex_match(what, m,
                         std::regex(R"(Expected exactly (\d+) arguments? to (\S+), got (\d+))")))
      return fmt::format("{} takes {} value{}, not {}", m[2].str(), m[1].str(),
                         m[1] == "1" ? "" : "s", m[3].str());
    if (std::regex_match(what, m,
                         std::regex(R"((\S+): At Most (\d+) required but received (\d+))")))
      return fmt::format("{} takes at most {} value{}, not {}", m[1].str(), m[2].str(),
                         m[2] == "1" ? "" : "s", m[3].str());
    if (std::regex_match(what, m, std::regex(R"((\S+) was given a disallowed flag override)")))
      return fmt::format("{} takes no value", m[1].str());
    return what;
  }
  if (is_a<CLI::ValidationError>(e)) {
    // "NAME: MESSAGE" with MESSAGE from a validator (hrad's own are already in words).
    if (std::regex_match(what, m, std::regex(R"((\S+): Value (.*) not in range (\S+) to (\S+))"))) {
      const std::string range = number_text(m[3]) + ".." + number_text(m[4]);
      const std::string value = m[2].str();
      if (!is_number(value))
        return fmt::format("{}: '{}' is not a number in {}", m[1].str(), value, range);
      return fmt::format("{}: {} is outside {}", m[1].str(), value, range);
    }
    if (std::regex_match(what, m, std::regex(R"((\S+): (.*) not in \{(.*)\})")))
      return fmt::format("{}: '{}' is not one of {}", m[1].str(), m[2].str(),
                         std::regex_replace(m[3].str(), std::regex(","), ", "));
    return what;
  }
  if (is_a<CLI::ConversionError>(e)) {
    if (std::regex_match(what, m, std::regex(R"(Could not convert: (\S+) = (.*))")))
      return conversion_text(command, m[1], m[2]);
    if (std::regex_match(what, m,
                         std::regex(R"(The value (.*) is not an allowed value for (\S+))")))
      return fmt::format("{}: '{}' is not an allowed value", m[2].str(), m[1].str());
    if (std::regex_match(what, m, std::regex(R"((\S+): too many inputs for a flag)")) ||
        std::regex_match(what, m, std::regex(R"((\S+): Should be true/false or a number)")))
      return fmt::format("{} takes no value", m[1].str());
    return what;
  }
  if (is_a<CLI::ExcludesError>(e) &&
      std::regex_match(what, m, std::regex(R"((\S+) excludes (\S+))")))
    return fmt::format("{} and {} cannot be given together", m[1].str(), m[2].str());
  return what;
}

}  // namespace

std::string parse_error_text(const CLI::ParseError& e, const CLI::App& app,
                             const std::vector<std::string>& argv) {
  // The command: the first word that names one (`hrad --bogus solve` has one too).
  std::string command_name;
  const CLI::App* command = &app;
  const auto subs = app.get_subcommands([](const CLI::App*) { return true; });
  for (std::size_t i = 1; i < argv.size() && command_name.empty(); ++i)
    for (const CLI::App* sub : subs)
      if (sub->get_name() == argv[i]) command = sub, command_name = argv[i];
  const std::string text = translate(e, *command, command_name, argv);
  return fmt::format("{}{} (see hrad {}--help)", command_name.empty() ? "" : command_name + ": ",
                     text, command_name.empty() ? "" : command_name + " ");
}

}  // namespace hrad::cli
