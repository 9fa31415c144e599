// Running the plot scripts (plots/<name>.py RESULT_DIR) after an experiment. They need
// Python 3 with matplotlib (Debian: python3-matplotlib); the interpreter is the first
// of $HRAD_PYTHON, `python3` on the PATH and /usr/bin/python3 that can import
// matplotlib. When none can, plotting is skipped with a warning, not an error: the
// result files are what matters, and the plots can be drawn later by hand.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace hrad::experiment {

/// The folder holding the plot scripts: $HRAD_PLOTS_DIR, else the source tree's
/// plots/ (known at build time), else ./plots.
[[nodiscard]] std::filesystem::path default_plots_dir();

/// A Python interpreter that imports matplotlib, or "" when there is none.
[[nodiscard]] std::string find_plot_python();

/// Throws std::invalid_argument naming the first of `names` without a script in
/// `plots_dir`: checked before an experiment runs, not after (a misspelt plot was
/// reported only once every run had finished).
void require_plot_scripts(const std::vector<std::string>& names,
                          const std::filesystem::path& plots_dir);

/// Runs each plots/<name>.py on `result_dir` (with `extra_args` appended), echoing the
/// scripts' output to the terminal. Returns false (after printing why on `log`) when a
/// script is missing or fails; prints a warning and returns true when no interpreter
/// with matplotlib was found.
bool run_plots(const std::vector<std::string>& names, const std::filesystem::path& result_dir,
               const std::filesystem::path& plots_dir, const std::vector<std::string>& extra_args,
               std::FILE* log);

/// `text` quoted for /bin/sh ('...' with embedded quotes escaped).
[[nodiscard]] std::string shell_quote(const std::string& text);

}  // namespace hrad::experiment
