// CSV as RFC 4180 writes it and pandas / R read it: comma-separated, a field quoted
// with "..." (inner quotes doubled) when it holds a comma, a quote, a line break or
// leading/trailing spaces; lines end with "\n". The reader reports a last line that
// was cut off (no final newline, or an open quote), which is how an interrupted
// experiment's runs.csv ends, so the caller can drop it.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace hrad::experiment {

/// One line, with its trailing "\n".
[[nodiscard]] std::string csv_line(const std::vector<std::string>& fields);

struct CsvText {
  std::vector<std::vector<std::string>> rows;  ///< complete lines only
  bool truncated = false;  ///< the text ended inside a line (that line is not in rows)
};

/// Parses CSV text. Empty lines are skipped.
[[nodiscard]] CsvText parse_csv(std::string_view text);

}  // namespace hrad::experiment
