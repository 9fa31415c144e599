#include "experiments/harness/run_rows.h"

#include "core/iteration_fields.h"
#include "core/options_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hrad::experiment {
namespace {

constexpr const char* kIdentity[] = {"config", "point", "repetition", "scene", "swept"};

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

// The figures of a row, each with its column name, written in one place: the headers
// are the names collected while flattening an empty run, so a header and its rows
// cannot disagree.
class Cells {
 public:
  explicit Cells(std::vector<std::string>* names = nullptr) : names_(names) {}
  void add(const char* name, std::string value) {
    if (names_) names_->push_back(name);
    values_.push_back(std::move(value));
  }
  [[nodiscard]] Row take() { return std::move(values_); }

 private:
  std::vector<std::string>* names_;
  Row values_;
};

std::string num(const FieldValue& v) { return v.integer ? num(v.count) : num(v.real); }

void iteration_figures(Cells& c, const IterationStats& it) {
  for (const IterationField& f : iteration_fields()) c.add(f.column, num(f.get(it)));
}

void run_figures(Cells& c, const RunStats& stats, const std::string& started_at,
                 const AccuracyFigures* accuracy) {
  const IterationTotals sums = sum_iterations(stats.iterations);
  const RunTotals& t = stats.totals;
  const auto probe = [accuracy](double AccuracyFigures::*f) {
    return accuracy ? num(accuracy->*f) : std::string();
  };
  c.add("wall_s", num(t.wall_s));
  c.add("refine_wall_s", num(t.refine_wall_s));
  c.add("refine_cpu_s", num(t.refine_cpu_s));
  c.add("refine_thread_cpu_s", num(t.refine_thread_cpu_s));
  c.add("task_cpu_ns", num(t.task_cpu_ns));
  c.add("propagate_wall_s", num(sums.propagate_wall_s));
  c.add("links", num(t.links));
  c.add("elements", num(t.elements));
  c.add("links_created", num(sums.links_created));
  c.add("rays_cast", num(t.rays_cast));
  c.add("rays_skipped", num(t.rays_skipped));
  c.add("peak_rss_bytes", num(t.peak_rss_bytes));
  c.add("bytes_elements", num(get(sums.bytes, "elements")));
  c.add("bytes_links", num(get(sums.bytes, "links")));
  c.add("bytes_total", num(sum(sums.bytes)));
  c.add("tasks", num(sums.tasks));
  c.add("scheduler_ops", num(sums.scheduler_ops));
  c.add("steals", num(sums.steals));
  c.add("idle_s", num(sums.idle_s));
  c.add("lock_wait_scheduler_s", num(get(sums.lock_wait_s, "scheduler")));
  c.add("lock_wait_element_s", num(get(sums.lock_wait_s, "element")));
  c.add("lock_wait_link_s", num(get(sums.lock_wait_s, "link")));
  c.add("lock_wait_total_s", num(sum(sums.lock_wait_s)));
  c.add("peak_parallelism", num(sums.peak_parallelism));
  c.add("local_access_ratio", num(sums.local_access_ratio));
  c.add("gather_sweeps", num(sums.gather_sweeps));
  c.add("iterations_run", num(static_cast<int>(stats.iterations.size())));
  c.add("started_at", started_at);
  c.add("probe_err_mean", probe(&AccuracyFigures::mean));
  c.add("probe_err_max", probe(&AccuracyFigures::max));
  c.add("probe_err_rms", probe(&AccuracyFigures::rms));
  c.add("probe_s", probe(&AccuracyFigures::probe_s));
}

}  // namespace

const std::vector<std::string>& run_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> c = with_identity_and_options();
    Cells cells(&c);
    run_figures(cells, RunStats{}, "", nullptr);
    return c;
  }();
  return columns;
}

const std::vector<std::string>& iteration_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> c = with_identity_and_options();
    Cells cells(&c);
    iteration_figures(cells, IterationStats{});
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
  for (const IterationStats& it : stats.iterations) {
    Cells c;
    iteration_figures(c, it);
    Row r = prefix;
    const Row figures = c.take();
    r.insert(r.end(), figures.begin(), figures.end());
    out.iterations.push_back(std::move(r));
  }
  Cells c;
  run_figures(c, stats, started_at, accuracy);
  out.run = prefix;
  const Row figures = c.take();
  out.run.insert(out.run.end(), figures.begin(), figures.end());
  return out;
}

}  // namespace hrad::experiment
