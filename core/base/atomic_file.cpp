#include "core/base/atomic_file.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace hrad {

namespace {

/// What the C library said about the last failed call, or a generic reason.
std::string reason() {
  return errno != 0 ? std::strerror(errno) : std::string("the stream failed");
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write) {
  std::filesystem::path tmp = path;
  tmp += fmt::format(".tmp-{}", static_cast<long>(::getpid()));
  {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    // Errors name the file the user asked for, and say why (the temporary name is
    // an implementation detail).
    if (!out) throw std::runtime_error(fmt::format("cannot write {}: {}", path.string(), reason()));
    try {
      write(out);
    } catch (...) {
      out.close();
      std::filesystem::remove(tmp);
      throw;
    }
    errno = 0;
    out.flush();
    if (!out) {
      const std::string why = reason();
      out.close();
      std::filesystem::remove(tmp);
      throw std::runtime_error(fmt::format("error while writing {}: {}", path.string(), why));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw std::runtime_error(fmt::format("cannot write {}: {}", path.string(), ec.message()));
  }
}

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace hrad
