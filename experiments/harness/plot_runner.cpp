#include "experiments/harness/plot_runner.h"

#include <fmt/format.h>
#include <sys/wait.h>

#include <cstdlib>
#include <stdexcept>

#ifndef HRAD_SOURCE_DIR
#define HRAD_SOURCE_DIR ""
#endif

namespace hrad::experiment {
namespace {

namespace fs = std::filesystem;

bool imports_matplotlib(const std::string& python) {
  const std::string cmd =
      shell_quote(python) + " -c 'import matplotlib' >/dev/null 2>&1 </dev/null";
  const int rc = std::system(cmd.c_str());
  return rc != -1 && WIFEXITED(rc) && WEXITSTATUS(rc) == 0;
}

}  // namespace

std::string shell_quote(const std::string& text) {
  std::string q = "'";
  for (char c : text) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

fs::path default_plots_dir() {
  if (const char* env = std::getenv("HRAD_PLOTS_DIR"); env && *env) return env;
  const fs::path source = fs::path(HRAD_SOURCE_DIR) / "plots";
  std::error_code ec;
  if (!std::string(HRAD_SOURCE_DIR).empty() && fs::is_directory(source, ec)) return source;
  return "plots";
}

std::string find_plot_python() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("HRAD_PYTHON"); env && *env) candidates.emplace_back(env);
  candidates.emplace_back("python3");
  candidates.emplace_back("/usr/bin/python3");
  for (const std::string& c : candidates)
    if (imports_matplotlib(c)) return c;
  return "";
}

void require_plot_scripts(const std::vector<std::string>& names, const fs::path& plots_dir) {
  for (const std::string& name : names) {
    std::error_code ec;
    if (!fs::is_regular_file(plots_dir / (name + ".py"), ec))
      throw std::invalid_argument(
          fmt::format("plot '{}': no script {} (set HRAD_PLOTS_DIR or --plots-dir, or --no-plot)",
                      name, (plots_dir / (name + ".py")).string()));
  }
}

bool run_plots(const std::vector<std::string>& names, const fs::path& result_dir,
               const fs::path& plots_dir, const std::vector<std::string>& extra_args,
               std::FILE* log) {
  if (names.empty()) return true;
  const std::string python = find_plot_python();
  if (python.empty()) {
    fmt::print(log,
               "hrad: warning: no Python 3 with matplotlib found ($HRAD_PYTHON, python3, "
               "/usr/bin/python3): plots skipped; install python3-matplotlib and run "
               "'python3 {}/<plot>.py {}'\n",
               plots_dir.string(), result_dir.string());
    return true;
  }
  bool ok = true;
  for (const std::string& name : names) {
    const fs::path script = plots_dir / (name + ".py");
    std::error_code ec;
    if (!fs::is_regular_file(script, ec)) {
      fmt::print(log, "hrad: plot script {} not found (set HRAD_PLOTS_DIR or --plots-dir)\n",
                 script.string());
      ok = false;
      continue;
    }
    std::string cmd = shell_quote(python) + " " + shell_quote(script.string()) + " " +
                      shell_quote(result_dir.string());
    for (const std::string& a : extra_args) cmd += " " + shell_quote(a);
    std::fflush(log);
    const int rc = std::system(cmd.c_str());
    if (rc == -1 || !WIFEXITED(rc) || WEXITSTATUS(rc) != 0) {
      fmt::print(log, "hrad: plot {} failed: {}\n", name, cmd);
      ok = false;
    }
  }
  return ok;
}

}  // namespace hrad::experiment
