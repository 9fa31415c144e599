#include "core/parallel/trace.h"

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"
#include "core/base/input_file.h"

#include <bit>
#include <fstream>
#include <stdexcept>

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

void check_trace_target(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path.string(), 0, "trace: not a regular file; give a new file's name");
  std::ifstream in(path, std::ios::binary);
  std::string header(1 << 16, '\0');  // the header line, or its start
  in.read(header.data(), static_cast<std::streamsize>(header.size()));
  header.resize(static_cast<std::size_t>(in.gcount()));
  header = header.substr(0, header.find('\n'));
  if (header.find("\"hrad-trace\"") == std::string::npos)
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
  if (header.find("\"hrad-trace\"") == std::string::npos)
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
  if (header_json) *header_json = header;
  return records;
}

}  // namespace hrad
