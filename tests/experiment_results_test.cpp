// CSV writing and reading, and the result files' resume logic: a pre-existing partial
// runs.csv (a cut-off last line, iterations of a run that never got its runs.csv row)
// is cleaned up so that exactly the finished runs remain.
#include "experiments/harness/csv.h"
#include "experiments/harness/result_files.h"
#include "tests/experiment_test_util.h"
#include "tests/read_text.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace hrad::experiment {
namespace {

namespace fs = std::filesystem;

using test::read_text;

struct TempDir : test::ScratchFolder {
  explicit TempDir(const char* name) : ScratchFolder(name, true) {}
};

TEST(ExperimentCsv, QuotesOnlyWhenNeeded) {
  EXPECT_EQ(csv_line({"a", "1.5", ""}), "a,1.5,\n");
  EXPECT_EQ(csv_line({"x,y", "say \"hi\"", " pad"}), "\"x,y\",\"say \"\"hi\"\"\",\" pad\"\n");
  EXPECT_EQ(csv_line({"builtin:office?desks=2&lights=1"}), "builtin:office?desks=2&lights=1\n");
  // A scene's comma-form parameters stay in its one field.
  EXPECT_EQ(csv_line({"builtin:office,desks=2,lights=1", "x"}),
            "\"builtin:office,desks=2,lights=1\",x\n");
  EXPECT_EQ(parse_csv(csv_line({"builtin:office,desks=2", "x"})).rows,
            (std::vector<std::vector<std::string>>{{"builtin:office,desks=2", "x"}}));
}

TEST(ExperimentCsv, RoundTripAndTruncation) {
  const std::vector<std::vector<std::string>> rows = {
      {"h1", "h2", "h3"}, {"a,b", "line\nbreak", "q\"uote"}, {"", "2", "3"}};
  std::string text;
  for (const auto& r : rows) text += csv_line(r);
  CsvText parsed = parse_csv(text);
  EXPECT_FALSE(parsed.truncated);
  EXPECT_EQ(parsed.rows, rows);
  // Cut anywhere inside the last line: that line is dropped and reported.
  const std::size_t last = text.size() - csv_line(rows.back()).size();
  for (std::size_t cut = last + 1; cut < text.size(); ++cut) {
    parsed = parse_csv(std::string_view(text).substr(0, cut));
    EXPECT_TRUE(parsed.truncated) << cut;
    EXPECT_EQ(parsed.rows.size(), 2u) << cut;
  }
  // Cut inside a quoted line break: the open quote is noticed.
  parsed = parse_csv(text.substr(0, text.find("break")));
  EXPECT_TRUE(parsed.truncated);
  EXPECT_EQ(parsed.rows.size(), 1u);
  EXPECT_EQ(parse_csv("a,b\r\nc,d\r\n").rows,
            (std::vector<std::vector<std::string>>{{"a", "b"}, {"c", "d"}}));
}

// A synthetic row of the given columns for run (point, repetition).
Row row_for(const std::vector<std::string>& columns, int point, int rep, const std::string& fill) {
  Row r(columns.size(), fill);
  r[column_index(columns, "point")] = std::to_string(point);
  r[column_index(columns, "repetition")] = std::to_string(rep);
  return r;
}

RunRows rows_for(int point, int rep, int iterations) {
  RunRows r;
  r.run = row_for(run_columns(), point, rep, "r");
  for (int i = 0; i < iterations; ++i)
    r.iterations.push_back(row_for(iteration_columns(), point, rep, "i"));
  return r;
}

TEST(ExperimentResultFiles, NewFolderGetsHeadersAndAppends) {
  TempDir d("hrad_results_new");
  {
    ResultFiles f(d.path);
    EXPECT_TRUE(f.done().empty());
    f.append({0, 0}, rows_for(0, 0, 2));
    f.append({0, 1}, rows_for(0, 1, 2));
    EXPECT_EQ(f.done().size(), 2u);
    // Flushed at once: a reader sees both rows while the files are still open.
    const CsvText runs = parse_csv(read_text(d.path / "runs.csv"));
    ASSERT_EQ(runs.rows.size(), 3u);
    EXPECT_EQ(runs.rows[0], run_columns());
    EXPECT_EQ(parse_csv(read_text(d.path / "iterations.csv")).rows.size(), 5u);
  }
  ResultFiles again(d.path);
  EXPECT_EQ(again.done().size(), 2u);
  EXPECT_TRUE(again.done().count({0, 1}));
}

TEST(ExperimentResultFiles, PartialFilesAreCleanedOnResume) {
  TempDir d("hrad_results_partial");
  // An interrupted experiment: runs (0,0) and (1,0) finished; (2,0) wrote its
  // iterations but was killed while writing its runs.csv row.
  std::string runs = csv_line(run_columns()) + csv_line(row_for(run_columns(), 0, 0, "r")) +
                     csv_line(row_for(run_columns(), 1, 0, "r"));
  const std::string cut = csv_line(row_for(run_columns(), 2, 0, "r"));
  runs += cut.substr(0, cut.size() / 2);
  std::string its = csv_line(iteration_columns());
  for (int p = 0; p < 3; ++p)
    for (int i = 0; i < 2; ++i) its += csv_line(row_for(iteration_columns(), p, 0, "i"));
  std::ofstream(d.path / "runs.csv", std::ios::binary) << runs;
  std::ofstream(d.path / "iterations.csv", std::ios::binary) << its;

  ResultFiles f(d.path);
  EXPECT_EQ(f.done().size(), 2u);
  EXPECT_TRUE(f.done().count({0, 0}));
  EXPECT_TRUE(f.done().count({1, 0}));
  EXPECT_FALSE(f.done().count({2, 0}));
  EXPECT_EQ(parse_csv(read_text(d.path / "runs.csv")).rows.size(), 3u);
  EXPECT_FALSE(parse_csv(read_text(d.path / "runs.csv")).truncated);
  EXPECT_EQ(parse_csv(read_text(d.path / "iterations.csv")).rows.size(), 1u + 4u);  // orphans gone
  // Redo (2,0): it appears once in each file.
  f.append({2, 0}, rows_for(2, 0, 2));
  const CsvText after = parse_csv(read_text(d.path / "runs.csv"));
  EXPECT_EQ(after.rows.size(), 4u);
  EXPECT_FALSE(after.truncated);
  EXPECT_EQ(parse_csv(read_text(d.path / "iterations.csv")).rows.size(), 1u + 6u);
}

TEST(ExperimentResultFiles, OutOfOrderRunsAreSortedIntoRunOrder) {
  TempDir d("hrad_results_sort");
  const auto its_of = [](const CsvText& t) {
    std::vector<std::pair<std::string, std::string>> ids;
    const std::size_t p = column_index(iteration_columns(), "point");
    const std::size_t r = column_index(iteration_columns(), "repetition");
    for (std::size_t i = 1; i < t.rows.size(); ++i) ids.emplace_back(t.rows[i][p], t.rows[i][r]);
    return ids;
  };
  {
    // As MPI ranks finish: (1,0), (0,1), then (0,0); reopened, (2,0) lands last.
    ResultFiles f(d.path);
    f.append({1, 0}, rows_for(1, 0, 2));
    f.append({0, 1}, rows_for(0, 1, 1));
    f.append({0, 0}, rows_for(0, 0, 3));
  }
  ResultFiles f(d.path);
  f.append({2, 0}, rows_for(2, 0, 1));
  const std::string unsorted = read_text(d.path / "runs.csv");
  f.sort_by_run();
  const CsvText runs = parse_csv(read_text(d.path / "runs.csv"));
  ASSERT_EQ(runs.rows.size(), 5u);
  const std::size_t p = column_index(run_columns(), "point");
  const std::size_t r = column_index(run_columns(), "repetition");
  std::vector<std::pair<std::string, std::string>> ids;
  for (std::size_t i = 1; i < runs.rows.size(); ++i)
    ids.emplace_back(runs.rows[i][p], runs.rows[i][r]);
  const std::vector<std::pair<std::string, std::string>> order = {
      {"0", "0"}, {"0", "1"}, {"1", "0"}, {"2", "0"}};
  EXPECT_EQ(ids, order);
  EXPECT_NE(read_text(d.path / "runs.csv"), unsorted);
  const auto it_ids = its_of(parse_csv(read_text(d.path / "iterations.csv")));
  const std::vector<std::pair<std::string, std::string>> it_order = {
      {"0", "0"}, {"0", "0"}, {"0", "0"}, {"0", "1"}, {"1", "0"}, {"1", "0"}, {"2", "0"}};
  EXPECT_EQ(it_ids, it_order);
  // Still open for appending after the rewrite; sorted files are left as they are.
  f.append({3, 0}, rows_for(3, 0, 1));
  const std::string sorted = read_text(d.path / "runs.csv");
  f.sort_by_run();
  EXPECT_EQ(read_text(d.path / "runs.csv"), sorted);
  EXPECT_EQ(parse_csv(sorted).rows.size(), 6u);
}

TEST(ExperimentResultFiles, ForeignFilesAreRejected) {
  TempDir d("hrad_results_foreign");
  std::ofstream(d.path / "runs.csv") << "a,b,c\n1,2,3\n";
  try {
    ResultFiles f(d.path);
    ADD_FAILURE() << "accepted a foreign header";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("header"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_text(d.path / "runs.csv"), "a,b,c\n1,2,3\n");  // left alone
  // A row of the wrong width names its line.
  std::ofstream(d.path / "runs.csv") << csv_line(run_columns()) << "1,2\n";
  try {
    ResultFiles f(d.path);
    ADD_FAILURE() << "accepted a short row";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("runs.csv:2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hrad::experiment
