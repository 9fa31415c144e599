#include "experiments/harness/csv.h"

namespace hrad::experiment {

std::string csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const std::string& f = fields[i];
    if (i > 0) line += ',';
    const bool quote = f.find_first_of(",\"\r\n") != std::string::npos ||
                       (!f.empty() && (f.front() == ' ' || f.back() == ' '));
    if (!quote) {
      line += f;
      continue;
    }
    line += '"';
    for (char c : f) {
      if (c == '"') line += '"';
      line += c;
    }
    line += '"';
  }
  line += '\n';
  return line;
}

CsvText parse_csv(std::string_view text) {
  CsvText out;
  std::vector<std::string> row;
  std::string field;
  bool in_quotes = false, line_started = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_quotes) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        in_quotes = false;
      } else {
        field += c;
      }
      continue;
    }
    if (c == '"') {
      in_quotes = true;
      line_started = true;
    } else if (c == ',') {
      row.push_back(std::move(field));
      field.clear();
      line_started = true;
    } else if (c == '\n') {
      if (line_started || !field.empty()) {
        row.push_back(std::move(field));
        out.rows.push_back(std::move(row));
      }
      row.clear();
      field.clear();
      line_started = false;
    } else if (c != '\r') {
      field += c;
      line_started = true;
    }
  }
  out.truncated = in_quotes || line_started || !field.empty();
  return out;
}

}  // namespace hrad::experiment
