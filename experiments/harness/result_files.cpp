#include "experiments/harness/result_files.h"

#include "core/base/atomic_file.h"
#include "core/base/input_file.h"
#include "experiments/harness/csv.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <sstream>
#include <stdexcept>

namespace hrad::experiment {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  check_input_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path.string()));
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int to_int(const std::string& text, const fs::path& path, std::size_t line, const char* what) {
  int v = -1;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size() || v < 0)
    throw std::runtime_error(fmt::format("{}:{}: {} '{}' is not a non-negative integer",
                                         path.string(), line, what, text));
  return v;
}

// Whether a result CSV's first row is `columns`.
bool header_is(const CsvText& csv, const std::vector<std::string>& columns) {
  return !csv.rows.empty() && csv.rows[0] == columns;
}

// Reads a result CSV: checks the header, returns the complete rows (the header excluded).
std::vector<Row> read_rows(const fs::path& path, const std::vector<std::string>& columns) {
  const CsvText csv = parse_csv(read_text(path));
  if (csv.rows.empty()) return {};  // only a cut-off header: start again
  if (!header_is(csv, columns))
    throw std::runtime_error(fmt::format(
        "{}: the header differs from this hrad's columns (written by another version?); "
        "resume into a new folder",
        path.string()));
  std::vector<Row> rows;
  for (std::size_t i = 1; i < csv.rows.size(); ++i) {
    if (csv.rows[i].size() != columns.size())
      throw std::runtime_error(fmt::format("{}:{}: {} fields, expected {}", path.string(), i + 1,
                                           csv.rows[i].size(), columns.size()));
    rows.push_back(csv.rows[i]);
  }
  return rows;
}

void write_all(const fs::path& path, const std::vector<std::string>& columns,
               const std::vector<Row>& rows) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << csv_line(columns);
    for (const Row& r : rows) out << csv_line(r);
  });
}

}  // namespace

bool runs_header_matches(const fs::path& dir) {
  std::ifstream in(dir / ResultFiles::kRuns, std::ios::binary);
  std::string header;
  if (!std::getline(in, header)) return false;
  return header_is(parse_csv(header + "\n"), run_columns());
}

ResultFiles::ResultFiles(const fs::path& dir) : dir_(dir) {
  const fs::path runs = dir / kRuns, iterations = dir / kIterations;
  const auto& rc = run_columns();
  const auto& ic = iteration_columns();
  std::vector<Row> kept_runs, kept_iterations;
  if (fs::exists(runs)) {
    const std::size_t point = column_index(rc, "point"), rep = column_index(rc, "repetition");
    std::size_t line = 1;
    for (Row& r : read_rows(runs, rc)) {
      ++line;
      const RunId id{to_int(r[point], runs, line, "point"),
                     to_int(r[rep], runs, line, "repetition")};
      if (done_.count(id))
        throw std::runtime_error(fmt::format("{}:{}: point {} repetition {} appears twice",
                                             runs.string(), line, id.point, id.repetition));
      kept_runs.push_back(r);
      order_.push_back(id);
      done_.emplace(id, std::move(r));
    }
  }
  if (fs::exists(iterations)) {
    const std::size_t point = column_index(ic, "point"), rep = column_index(ic, "repetition");
    std::size_t line = 1;
    for (Row& r : read_rows(iterations, ic)) {
      ++line;
      const RunId id{to_int(r[point], iterations, line, "point"),
                     to_int(r[rep], iterations, line, "repetition")};
      if (done_.count(id)) kept_iterations.push_back(std::move(r));
    }
  }
  // Both files now hold exactly the finished runs, whatever state they were left in.
  write_all(iterations, ic, kept_iterations);
  write_all(runs, rc, kept_runs);
  open_for_append();
}

void ResultFiles::open_for_append() {
  runs_.open(dir_ / kRuns, std::ios::app | std::ios::binary);
  iterations_.open(dir_ / kIterations, std::ios::app | std::ios::binary);
  if (!runs_ || !iterations_)
    throw std::runtime_error(
        fmt::format("{}: cannot open the result files for appending", dir_.string()));
}

void ResultFiles::sort_by_run() {
  if (std::is_sorted(order_.begin(), order_.end())) return;
  runs_.close();
  iterations_.close();
  const fs::path iterations = dir_ / kIterations;
  const auto& ic = iteration_columns();
  const std::size_t point = column_index(ic, "point"), rep = column_index(ic, "repetition");
  // Every row on disk belongs to a run in done_ (the constructor and append keep it so).
  std::map<RunId, std::vector<Row>> by_run;
  std::size_t line = 1;
  for (Row& r : read_rows(iterations, ic)) {
    ++line;
    const RunId id{to_int(r[point], iterations, line, "point"),
                   to_int(r[rep], iterations, line, "repetition")};
    by_run[id].push_back(std::move(r));
  }
  std::vector<Row> runs, iteration_rows;
  for (const auto& [id, row] : done_) {
    runs.push_back(row);
    for (Row& r : by_run[id]) iteration_rows.push_back(std::move(r));
  }
  write_all(iterations, ic, iteration_rows);
  write_all(dir_ / kRuns, run_columns(), runs);
  order_.clear();
  for (const auto& [id, row] : done_) order_.push_back(id);
  open_for_append();
}

void ResultFiles::append(const RunId& id, const RunRows& rows) {
  for (const Row& r : rows.iterations) iterations_ << csv_line(r);
  iterations_.flush();
  if (!iterations_)
    throw std::runtime_error(fmt::format("{}: write failed", (dir_ / kIterations).string()));
  runs_ << csv_line(rows.run);
  runs_.flush();
  if (!runs_) throw std::runtime_error(fmt::format("{}: write failed", (dir_ / kRuns).string()));
  done_.emplace(id, rows.run);
  order_.push_back(id);
}

}  // namespace hrad::experiment
