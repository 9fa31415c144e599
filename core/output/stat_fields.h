// One description per statistic: its name, its unit and how to read it, for an
// iteration (IterationStats) and for a whole run (RunTotals and the sums over the
// iterations, sum_iterations). stats.json (core/output/stats_json.cpp) and the experiments'
// iterations.csv and runs.csv (experiments/harness/run_rows.cpp) are written from
// these tables, so a figure in one is the same figure in the other.
//
// A field's `path` is its place in stats.json's iteration object, "/" between a nested
// object and its key ("row_sums/min"); its CSV column is the path with "/" turned into
// "_" ("row_sums_min"). A field without a path is a CSV column only: the CSV's
// flattening of a by-name map that stats.json writes whole (bytes, lock_wait_s). What
// is not a scalar (the per-refiner list, per-node bytes, the placement check) is
// written by stats_json.cpp alone.
#pragma once

#include "core/output/run_stats.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hrad {

/// A figure: a count (written as an integer) or a real (non-finite: null in JSON,
/// empty in CSV).
struct FieldValue {
  bool integer = false;
  std::uint64_t count = 0;
  double real = 0;
};

struct IterationField {
  const char* path;    ///< stats.json path ("a" or "a/b"); nullptr: CSV only
  const char* column;  ///< CSV column (the path with "/" as "_", or its own name)
  const char* unit;    ///< "s", "ns", "bytes", "count", "" (a ratio or index)
  FieldValue (*get)(const IterationStats&);
};

/// Every scalar figure of an iteration, in the CSV's column order.
const std::vector<IterationField>& iteration_fields();

/// A figure of a whole run; `path` as above, in stats.json's `totals` (nullptr: in
/// runs.csv only, where the per-iteration figures are summed).
struct RunField {
  const char* path;
  const char* column;
  const char* unit;
  FieldValue (*get)(const RunStats&, const IterationTotals&);
};

/// Every figure of a run, in runs.csv's column order (before the experiment's own
/// columns: start time and probe errors).
const std::vector<RunField>& run_fields();

}  // namespace hrad
