#include "core/base/input_file.h"

#include "core/base/input_error.h"

#include <algorithm>
#include <string>
#include <system_error>

namespace hrad {

std::string without_bom(std::string text) {
  if (text.starts_with("\xEF\xBB\xBF")) text.erase(0, 3);
  return text;
}

std::string checked_text(std::string text, const std::string& file) {
  text = without_bom(std::move(text));
  if (const std::size_t at = text.find('\0'); at != std::string::npos) {
    const auto line =
        1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
    const std::size_t start = text.rfind('\n', at);
    const std::size_t column = at - (start == std::string::npos ? 0 : start + 1) + 1;
    throw InputError(
        file, static_cast<int>(line),
        "a NUL byte at column " + std::to_string(column) + ": this is not a text file");
  }
  return text;
}

void check_input_file(const std::filesystem::path& path, const std::string& what) {
  std::error_code ec;
  const std::filesystem::file_status s = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(s))
    throw InputError(path.string(), 0, what + " does not exist");
  if (!std::filesystem::is_regular_file(s))
    throw InputError(path.string(), 0,
                     what + " is not a regular file (" +
                         (std::filesystem::is_directory(s) ? "a folder"
                          : std::filesystem::is_fifo(s)    ? "a FIFO"
                          : std::filesystem::is_socket(s)  ? "a socket"
                                                           : "a device") +
                         "): give a file");
}

}  // namespace hrad
