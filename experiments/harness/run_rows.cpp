#include "experiments/harness/run_rows.h"

#include "core/config/options_io.h"
#include "core/output/stat_fields.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

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

Row identity_and_options(const std::string& config_name, const SweepPoint& point, int repetition) {
  Row r = {config_name, num(point.index), num(repetition), point.scene, describe_point(point)};
  for (const OptionInfo& o : option_table())
    r.push_back(option_value_string(point.options, o.name));
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

void iteration_figures(Cells& c, const IterationStats& it, const RunOrigin& origin) {
  for (const IterationField& f : iteration_fields()) c.add(f.column, num(f.get(it)));
  c.add("host", origin.host);
  c.add("hrad_revision", origin.revision);
}

void run_figures(Cells& c, const RunStats& stats, const std::string& started_at,
                 const AccuracyFigures* accuracy, const RunOrigin& origin) {
  const IterationTotals sums = sum_iterations(stats.iterations);
  const auto probe = [accuracy](double AccuracyFigures::*f) {
    return accuracy ? num(accuracy->*f) : std::string();
  };
  for (const RunField& f : run_fields()) c.add(f.column, num(f.get(stats, sums)));
  c.add("started_at", started_at);
  c.add("probe_err_mean", probe(&AccuracyFigures::mean));
  c.add("probe_err_max", probe(&AccuracyFigures::max));
  c.add("probe_err_rms", probe(&AccuracyFigures::rms));
  c.add("probe_s", probe(&AccuracyFigures::probe_s));
  c.add("warnings", fmt::format("{}", fmt::join(stats.warnings, " | ")));
  c.add("host", origin.host);
  c.add("hrad_revision", origin.revision);
  c.add("cpu_model", origin.cpu_model);
  c.add("cores", origin.cores > 0 ? num(origin.cores) : std::string());
  c.add("load_avg", num(origin.load_avg));
}

}  // namespace

const std::vector<std::string>& run_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> c = with_identity_and_options();
    Cells cells(&c);
    run_figures(cells, RunStats{}, "", nullptr, RunOrigin{});
    return c;
  }();
  return columns;
}

const std::vector<std::string>& iteration_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> c = with_identity_and_options();
    Cells cells(&c);
    iteration_figures(cells, IterationStats{}, RunOrigin{});
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
                      const AccuracyFigures* accuracy, const RunOrigin& origin) {
  RunRows out;
  const Row prefix = identity_and_options(config_name, point, repetition);
  for (const IterationStats& it : stats.iterations) {
    Cells c;
    iteration_figures(c, it, origin);
    Row r = prefix;
    const Row figures = c.take();
    r.insert(r.end(), figures.begin(), figures.end());
    out.iterations.push_back(std::move(r));
  }
  Cells c;
  run_figures(c, stats, started_at, accuracy, origin);
  out.run = prefix;
  const Row figures = c.take();
  out.run.insert(out.run.end(), figures.begin(), figures.end());
  return out;
}

}  // namespace hrad::experiment
