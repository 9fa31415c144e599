// hrad: the command-line front end. Subcommands live in cmd_*.cpp (see commands.h).
#include "experiments/commands.h"
#include "experiments/openmp_spin.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <csignal>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include "hrad_git_revision.h"  // HRAD_GIT_REVISION, written at every build

namespace hrad::cli {

std::string git_revision() { return HRAD_GIT_REVISION; }

std::string version_string() { return fmt::format("hrad {} (git {})", kVersion, git_revision()); }

CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        const char* end = text.data() + text.size();
        const auto r = std::from_chars(text.data(), end, v);
        if (r.ec != std::errc() || r.ptr != end || !std::isfinite(v))
          return "'" + text + "' is not a number";
        return v > 0 ? std::string() : "must be > 0, not " + text;
      },
      "> 0");
}

CLI::Validator number_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0;
        const char* end = text.data() + text.size();
        const auto r = std::from_chars(text.data(), end, v);
        if (r.ec != std::errc() || r.ptr != end || !std::isfinite(v))
          return fmt::format("'{}' is not a number in {:g}..{:g}", text, lo, hi);
        return v >= lo && v <= hi ? std::string()
                                  : fmt::format("{} is outside {:g}..{:g}", text, lo, hi);
      },
      fmt::format("{:g} .. {:g}", lo, hi));
}

CLI::Validator integer_in(std::uint64_t lo, std::uint64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        // The same words as number_in: "'x' is not an integer in 1..8", "0 is outside 1..8".
        const std::string range = fmt::format("{} is outside {}..{}", text, lo, hi);
        const char* end = text.data() + text.size();
        std::uint64_t v = 0;
        const auto r = std::from_chars(text.data(), end, v);
        if (r.ec == std::errc::result_out_of_range && r.ptr == end) return range;
        if (r.ec != std::errc() || r.ptr != end) {
          // Not plain digits: a whole number in another form (1e9), or a negative one.
          double d = 0;
          const auto rd = std::from_chars(text.data(), end, d);
          if (rd.ec == std::errc::result_out_of_range && rd.ptr == end) return range;
          if (rd.ec != std::errc() || rd.ptr != end || !std::isfinite(d) || d != std::trunc(d))
            return fmt::format("'{}' is not an integer in {}..{}", text, lo, hi);
          if (d < 0 || d >= 0x1p64) return range;
          v = static_cast<std::uint64_t>(d);
        }
        if (v < lo || v > hi) return range;
        text = std::to_string(v);  // digits, for CLI11's conversion
        return std::string();
      },
      fmt::format("{} .. {}", lo, hi));
}

void print_error(std::string_view message) {
  if (message.size() <= kMaxErrorChars) {
    fmt::print(stderr, "hrad: {}\n", message);
  } else {
    fmt::print(stderr, "hrad: {}... ({} more characters)\n", message.substr(0, kMaxErrorChars),
               message.size() - kMaxErrorChars);
  }
}

bool make_output_folder(const std::filesystem::path& out, bool& created) {
  created = false;
  try {
    if (std::filesystem::exists(out) && !std::filesystem::is_directory(out))
      throw std::runtime_error(fmt::format("{} exists and is not a directory", out.string()));
    created = std::filesystem::create_directories(out);
  } catch (const std::exception& e) {
    fmt::print(stderr, "hrad: cannot create the output folder: {}\n", e.what());
    return false;
  }
  return true;
}

}  // namespace hrad::cli

int main(int argc, char** argv) {
  using namespace hrad::cli;
  // Past a file-size limit (`ulimit -f`) a write raises SIGXFSZ, whose default action
  // ended hrad in the middle of render.png's temporary file, with solution.ply written
  // and no stats.json, and no message. Ignored, the write fails with EFBIG: the run says
  // "File too large" and removes what it wrote, as for a full disk.
  std::signal(SIGXFSZ, SIG_IGN);
  bound_openmp_spinning(argv);
  CommandContext ctx;
  ctx.argv.assign(argv, argv + argc);

  CLI::App app{"hrad: a testbed for parallel hierarchical radiosity with clustering.", "hrad"};
  app.set_version_flag("--version", version_string());
  app.require_subcommand(1);
  // SIGINT and SIGTERM: solve, reference and experiment, which write results as they
  // go, install handlers that stop them at a safe point (core/base/interrupt.h). The
  // others (compare, simulate, topology, scenes) write at most one file at their end,
  // atomically: the signal's default action ends them at once, leaving nothing
  // half-written.
  register_solve(app, ctx);
  register_experiment(app, ctx);
  register_simulate(app, ctx);
  register_scenes(app, ctx);
  register_topology(app, ctx);
  register_reference(app, ctx);
  register_compare(app, ctx);
  register_render(app, ctx);
  app.footer("Run 'hrad COMMAND --help' for the options of a command.");

  // A first word that is neither an option nor a command: say so (CLI11 would say
  // "A subcommand is required").
  if (argc > 1 && argv[1][0] != '-') {
    std::string known;
    bool found = false;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
      found = found || sub->get_name() == argv[1];
      known += (known.empty() ? "" : ", ") + sub->get_name();
    }
    if (!found) {
      print_error(
          fmt::format("unknown command '{}' (commands: {}; see hrad --help)", argv[1], known));
      return 1;
    }
  }
  if (argc == 1) {  // (CLI11 would say "A subcommand is required")
    fmt::print("{}", app.help());
    return 1;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    print_error(parse_error_text(e, app, ctx.argv));
    // A value out of range or not a number is bad input, as hrad's own checks say it
    // (status 1: `reference --threads 0` gave 105 where `solve --threads 0` gave 1);
    // CLI11's codes are kept for the command line's syntax (109: an unexpected argument).
    const int code = e.get_exit_code();
    if (code == static_cast<int>(CLI::ExitCodes::ValidationError) ||
        code == static_cast<int>(CLI::ExitCodes::ConversionError))
      return 1;
    return code;
  }
  return ctx.status;
}
