// The hrad command-line tool is a CLI11 app with one subcommand per file:
//   solve       cmd_solve.cpp       solve one scene, write the result files
//   scenes      cmd_scenes.cpp      list the built-in scenes and their parameters
//   topology    cmd_topology.cpp    print the machine's topology as hwloc sees it
//   experiment  cmd_experiment.cpp  run an experiment configuration (experiments/harness/)
//   simulate    cmd_simulate.cpp    replay a task trace on more processors (experiments/sim/)
//   reference   cmd_reference.cpp   Monte Carlo path-traced probe irradiance
//   compare     cmd_compare.cpp     error metrics between two results
//   render      cmd_render.cpp      a new picture of a solved scene from its solution.ply
// Each register_* adds its subcommand to `app`; when that subcommand is chosen, its
// callback runs the command and stores the process exit status in `ctx.status`.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace hrad::cli {

/// hrad's version; the git revision is taken at every build (experiments/git_revision.cmake).
inline constexpr const char* kVersion = "0.1.0";

struct CommandContext {
  std::vector<std::string> argv;  ///< the whole command line, for stats.json
  int status = 0;                 ///< exit status of the command that ran
};

/// "hrad 0.1.0 (git abc1234)".
std::string version_string();
/// The git revision this binary was built from ("unknown" outside a git checkout).
std::string git_revision();

/// Creates the output folder `out` (and its parents); `created` says whether it did not
/// exist before. On failure prints "hrad: cannot create the output folder: ..." and
/// returns false.
bool make_output_folder(const std::filesystem::path& out, bool& created);

/// Check for an option that takes a number > 0 (CLI11's PositiveNumber printed its
/// upper bound, a 309-digit number, in its message).
CLI::Validator positive_number();
/// A finite number (no nan, inf or wrap-around of "-1" into an unsigned option) between
/// lo and hi inclusive, checked on the text before CLI11 converts it.
CLI::Validator number_in(double lo, double hi);
/// An integer between lo and hi inclusive, for integer options (add it with
/// `->transform`: it rewrites the text as digits). A whole number in exponent form
/// (1e6) is taken as that integer; one beyond the bounds (1e30, -1) is out of range, not
/// "not an integer", and "-1" never wraps into an unsigned option.
CLI::Validator integer_in(std::uint64_t lo, std::uint64_t hi);

/// A command-line parse error in hrad's words, naming the command and the option:
/// "solve: unknown option --bogus (see hrad solve --help)", "reference:
/// --random-probes: 'x' is not a number in 1..1048576 (see hrad reference --help)",
/// "solve: --out needs a value (DIR) (see hrad solve --help)" (cli_errors.cpp).
std::string parse_error_text(const CLI::ParseError& e, const CLI::App& app,
                             const std::vector<std::string>& argv);

/// Prints "hrad: MESSAGE" to stderr, MESSAGE cut to kMaxErrorChars (a message that
/// echoes a huge input value stays readable).
void print_error(std::string_view message);
inline constexpr std::size_t kMaxErrorChars = 2000;

void register_solve(CLI::App& app, CommandContext& ctx);
void register_scenes(CLI::App& app, CommandContext& ctx);
void register_topology(CLI::App& app, CommandContext& ctx);
void register_experiment(CLI::App& app, CommandContext& ctx);
void register_simulate(CLI::App& app, CommandContext& ctx);
void register_reference(CLI::App& app, CommandContext& ctx);
void register_compare(CLI::App& app, CommandContext& ctx);
void register_render(CLI::App& app, CommandContext& ctx);

}  // namespace hrad::cli
