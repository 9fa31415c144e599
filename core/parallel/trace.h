// Task traces (option `trace`): one record per refinement task, for replaying a
// run on more processors than this machine has (the experiments' simulator).
//
// File format (little-endian): one line of JSON (the header: format, version,
// record size, field list, run facts), then `records` fixed-size records:
//
// | field       | type   | meaning                                                     |
// |-------------|--------|-------------------------------------------------------------|
// | id          | uint64 | task id: (creating worker + 1) << 48 | iteration << 40 |     |
// |             |        | sequence; initial tasks: iteration << 40 | index              |
// | first_child | uint64 | id of the first task it created; the others follow (+1 ...) |
// | start_ns    | uint64 | start, in ns since the start of the refinement stage        |
// | duration_ns | uint32 | time spent on the task; the top bit marks the first task of |
// |             |        | a block (a scheduler take)                                  |
// | children    | uint16 | number of tasks it created                                  |
// | worker      | uint8  | refiner (OpenMP thread number)                              |
// | iteration   | uint8  | refinement iteration, 1-based                               |
//
// 32 bytes a task: the built-in office's 1.4 million tasks make about 45 MB.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hrad {

struct TraceRecord {
  std::uint64_t id = 0;
  std::uint64_t first_child = 0;
  std::uint64_t start_ns = 0;
  std::uint32_t duration_ns = 0;
  std::uint16_t children = 0;
  std::uint8_t worker = 0;
  std::uint8_t iteration = 0;

  static constexpr std::uint32_t kBlockStart = 0x80000000u;
};
static_assert(sizeof(TraceRecord) == 32, "the file format is these 32 bytes");

/// Writes records (any order) atomically to `path`, with `header_json` (one JSON
/// object, no newline) as the first line.
void write_trace(const std::filesystem::path& path, const std::string& header_json,
                 const std::vector<TraceRecord>& records);

/// Throws InputError unless `path` may take a trace: it does not exist yet, or it is an
/// hrad trace already (`--set trace=FILE` overwrote any file, the input scene
/// included, and only after the whole run). Called before anything is made.
void check_trace_target(const std::filesystem::path& path);

/// Reads a file written by write_trace; throws std::runtime_error naming the file
/// when it is not one, or when its header does not match its body (check_trace_body).
std::vector<TraceRecord> read_trace(const std::filesystem::path& path, std::string* header_json);

/// Throws std::runtime_error naming `file` unless the header (JSON) says version 1 and,
/// where it gives them, the record size, the number of records and a thread count
/// above every record's refiner.
void check_trace_body(const std::string& file, const std::string& header,
                      const std::vector<TraceRecord>& records);

}  // namespace hrad
