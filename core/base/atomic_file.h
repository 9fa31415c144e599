// Result files are written atomically: to a temporary name in the same folder,
// then renamed, so a reader (or a crash) never sees a half-written file.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>

namespace hrad {

/// Calls `write` with a stream on "<path>.tmp-<pid>", flushes, checks the stream,
/// and renames over `path`. Throws std::runtime_error naming the path on failure
/// (and removes the temporary).
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write);

/// Same for binary content already in memory.
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace hrad
