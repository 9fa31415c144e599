#include "core/parallel/trace.h"

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"
#include "core/base/input_file.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <bit>
#include <fstream>
#include <stdexcept>
#include <string_view>

namespace hrad {

static_assert(std::endian::native == std::endian::little,
              "trace files are little-endian; add byte swapping for this platform");

void write_trace(const std::filesystem::path& path, const std::string& header_json,
                 const std::vector<TraceRecord>& records) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << header_json << '\n';
    out.write(reinterpret_cast<const char*>(records.data()),
              static_cast<std::streamsize>(records.size() * sizeof(TraceRecord)));
  });
}

namespace {

// Whether a file's first line (or its start) is a trace's header.
bool is_trace_header(std::string_view first_line) {
  return first_line.find("\"hrad-trace\"") != std::string_view::npos;
}

}  // namespace

void check_trace_target(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path.string(), 0, "trace: not a regular file; give a new file's name");
  std::ifstream in(path, std::ios::binary);
  std::string header(1 << 16, '\0');  // the header line, or its start
  in.read(header.data(), static_cast<std::streamsize>(header.size()));
  header.resize(static_cast<std::size_t>(in.gcount()));
  if (!is_trace_header(std::string_view(header).substr(0, header.find('\n'))))
    throw InputError(path.string(), 0,
                     "trace: the file exists and is not an hrad trace: not overwritten (give a "
                     "new file's name)");
}

std::vector<TraceRecord> read_trace(const std::filesystem::path& path, std::string* header_json) {
  check_input_file(path, "the trace");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open trace");
  std::string header;
  std::getline(in, header);
  if (!is_trace_header(header))
    throw std::runtime_error(path.string() + ": not an hrad trace (bad header)");
  const auto body_start = in.tellg();
  in.seekg(0, std::ios::end);
  const auto bytes = static_cast<std::size_t>(in.tellg() - body_start);
  if (bytes % sizeof(TraceRecord) != 0)
    throw std::runtime_error(path.string() + ": truncated trace");
  std::vector<TraceRecord> records(bytes / sizeof(TraceRecord));
  in.seekg(body_start);
  in.read(reinterpret_cast<char*>(records.data()), static_cast<std::streamsize>(bytes));
  if (!in) throw std::runtime_error(path.string() + ": read error");
  check_trace_body(path.string(), header, records);
  if (header_json) *header_json = header;
  return records;
}

void check_trace_body(const std::string& file, const std::string& header,
                      const std::vector<TraceRecord>& records) {
  const nlohmann::json h = nlohmann::json::parse(header, nullptr, false);
  const auto bad = [&](const std::string& what) {
    throw std::runtime_error(
        fmt::format("{}: the trace's header does not match its body: {}", file, what));
  };
  if (!h.is_object()) bad("the header is not a JSON object");
  const auto number = [&](const char* key) -> const nlohmann::json* {
    const auto it = h.find(key);
    if (it == h.end()) return nullptr;
    if (!it->is_number_unsigned()) bad(fmt::format("'{}' is not a count", key));
    return &*it;
  };
  if (const auto v = h.find("version"); v == h.end() || *v != 1)
    bad(fmt::format("version {} (this hrad reads version 1)",
                    v == h.end() ? std::string("missing") : v->dump()));
  if (const auto* b = number("record_bytes"); b && b->get<std::uint64_t>() != sizeof(TraceRecord))
    bad(fmt::format("records of {} bytes (they are {})", b->get<std::uint64_t>(),
                    sizeof(TraceRecord)));
  if (const auto* n = number("records"); n && n->get<std::uint64_t>() != records.size())
    bad(fmt::format("it says {} records, the body holds {} (cut short, or another trace's?)",
                    n->get<std::uint64_t>(), records.size()));
  if (const auto* t = number("threads")) {
    const std::uint64_t threads = t->get<std::uint64_t>();
    for (std::size_t i = 0; i < records.size(); ++i)
      if (records[i].worker >= threads)
        bad(fmt::format("record {} ran on refiner {}, but the run had {} thread{}", i,
                        records[i].worker, threads, threads == 1 ? "" : "s"));
  }
}

}  // namespace hrad
