#include "experiments/harness/run_rows.h"

#include "core/options_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hrad::experiment {
namespace {

constexpr const char* kIdentity[] = {"config", "point", "repetition", "scene", "swept"};
constexpr const char* kLockClasses[] = {"scheduler", "element", "link"};

// Per-iteration figures, in column order (after "iteration").
constexpr const char* kIterationFigures[] = {
    "refine_wall_s", "refine_cpu_s", "propagate_wall_s", "links_created", "links",
    "elements", "bytes_elements", "bytes_links", "bytes_total", "peak_rss_bytes", "tasks",
    "scheduler_ops", "steals", "idle_s", "lock_wait_scheduler_s", "lock_wait_element_s",
    "lock_wait_link_s", "lock_wait_total_s", "peak_parallelism", "local_access_ratio",
    "rays_cast", "rays_skipped", "gather_sweeps", "max_change"};

constexpr const char* kRunFigures[] = {
    "wall_s", "refine_wall_s", "refine_cpu_s", "propagate_wall_s", "links", "elements",
    "links_created", "rays_cast", "rays_skipped", "peak_rss_bytes", "bytes_elements",
    "bytes_links", "bytes_total", "tasks", "scheduler_ops", "steals", "idle_s",
    "lock_wait_scheduler_s", "lock_wait_element_s", "lock_wait_link_s", "lock_wait_total_s",
    "peak_parallelism", "local_access_ratio", "gather_sweeps", "iterations_run", "started_at",
    "probe_err_mean", "probe_err_max", "probe_err_rms", "probe_s"};

std::vector<std::string> with_identity_and_options() {
  std::vector<std::string> c(std::begin(kIdentity), std::end(kIdentity));
  for (const OptionInfo& o : option_table()) c.push_back(o.name);
  return c;
}

std::string num(double v) { return std::isfinite(v) ? fmt::format("{}", v) : ""; }
std::string num(std::uint64_t v) { return fmt::format("{}", v); }
std::string num(int v) { return fmt::format("{}", v); }

template <class V>
V get(const std::map<std::string, V>& m, const std::string& key) {
  const auto it = m.find(key);
  return it == m.end() ? V{} : it->second;
}

template <class V>
V sum(const std::map<std::string, V>& m) {
  V s{};
  for (const auto& [k, v] : m) s += v;
  return s;
}

Row identity_and_options(const std::string& config_name, const SweepPoint& point,
                         int repetition) {
  Row r = {config_name, num(point.index), num(repetition), point.scene, describe_point(point)};
  for (const OptionInfo& o : option_table()) r.push_back(option_value_string(point.options, o.name));
  return r;
}

}  // namespace

const std::vector<std::string>& run_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> c = with_identity_and_options();
    c.insert(c.end(), std::begin(kRunFigures), std::end(kRunFigures));
    return c;
  }();
  return columns;
}

const std::vector<std::string>& iteration_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> c = with_identity_and_options();
    c.push_back("iteration");
    c.insert(c.end(), std::begin(kIterationFigures), std::end(kIterationFigures));
    return c;
  }();
  return columns;
}

std::size_t column_index(const std::vector<std::string>& columns, const std::string& name) {
  const auto it = std::find(columns.begin(), columns.end(), name);
  if (it == columns.end()) throw std::logic_error("no column " + name);
  return static_cast<std::size_t>(it - columns.begin());
}

RunRows make_run_rows(const std::string& config_name, const SweepPoint& point, int repetition,
                      const RunStats& stats, const std::string& started_at,
                      const AccuracyFigures* accuracy) {
  RunRows out;
  const Row prefix = identity_and_options(config_name, point, repetition);

  double propagate = 0, idle = 0, lock_total = 0;
  std::map<std::string, double> lock;
  std::uint64_t created = 0, tasks = 0, ops = 0, steals = 0, local = 0, located = 0;
  int peak_par = 0, sweeps = 0;
  for (const IterationStats& it : stats.iterations) {
    Row r = prefix;
    const double it_lock_total = sum(it.lock_wait_s);
    r.push_back(num(it.iteration));
    r.push_back(num(it.refine_wall_s));
    r.push_back(num(it.refine_cpu_s));
    r.push_back(num(it.propagate_wall_s));
    r.push_back(num(it.links_created));
    r.push_back(num(it.links));
    r.push_back(num(it.elements));
    r.push_back(num(get(it.bytes, "elements")));
    r.push_back(num(get(it.bytes, "links")));
    r.push_back(num(sum(it.bytes)));
    r.push_back(num(it.peak_rss_bytes));
    r.push_back(num(it.tasks));
    r.push_back(num(it.scheduler_ops));
    r.push_back(num(it.steals));
    r.push_back(num(it.idle_s));
    for (const char* cls : kLockClasses) r.push_back(num(get(it.lock_wait_s, cls)));
    r.push_back(num(it_lock_total));
    r.push_back(num(it.peak_parallelism));
    r.push_back(num(it.local_access_ratio));
    r.push_back(num(it.rays_cast));
    r.push_back(num(it.rays_skipped));
    r.push_back(num(it.gather_sweeps));
    r.push_back(num(it.max_change));
    out.iterations.push_back(std::move(r));

    propagate += it.propagate_wall_s;
    idle += it.idle_s;
    lock_total += it_lock_total;
    for (const char* cls : kLockClasses) lock[cls] += get(it.lock_wait_s, cls);
    created += it.links_created;
    tasks += it.tasks;
    ops += it.scheduler_ops;
    steals += it.steals;
    peak_par = std::max(peak_par, it.peak_parallelism);
    for (const RefinerStats& rs : it.refiners) {
      local += rs.tasks_local;
      located += rs.tasks_local + rs.tasks_remote;
    }
    sweeps += it.gather_sweeps;
  }

  const RunTotals& t = stats.totals;
  static const IterationStats kNone;
  const IterationStats& last = stats.iterations.empty() ? kNone : stats.iterations.back();
  Row r = prefix;
  r.push_back(num(t.wall_s));
  r.push_back(num(t.refine_wall_s));
  r.push_back(num(t.refine_cpu_s));
  r.push_back(num(propagate));
  r.push_back(num(t.links));
  r.push_back(num(t.elements));
  r.push_back(num(created));
  r.push_back(num(t.rays_cast));
  r.push_back(num(t.rays_skipped));
  r.push_back(num(t.peak_rss_bytes));
  r.push_back(num(get(last.bytes, "elements")));
  r.push_back(num(get(last.bytes, "links")));
  r.push_back(num(sum(last.bytes)));
  r.push_back(num(tasks));
  r.push_back(num(ops));
  r.push_back(num(steals));
  r.push_back(num(idle));
  for (const char* cls : kLockClasses) r.push_back(num(lock[cls]));
  r.push_back(num(lock_total));
  r.push_back(num(peak_par));
  r.push_back(located == 0 ? std::string() : num(static_cast<double>(local) / static_cast<double>(located)));
  r.push_back(num(sweeps));
  r.push_back(num(static_cast<int>(stats.iterations.size())));
  r.push_back(started_at);
  r.push_back(accuracy ? num(accuracy->mean) : std::string());
  r.push_back(accuracy ? num(accuracy->max) : std::string());
  r.push_back(accuracy ? num(accuracy->rms) : std::string());
  r.push_back(accuracy ? num(accuracy->probe_s) : std::string());
  out.run = std::move(r);
  return out;
}

}  // namespace hrad::experiment
