#include "core/base/atomic_file.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace hrad {

namespace {

/// What the C library said about the failed call (errno, or `saved` when the call that
/// failed came before others that reset it), or a generic reason.
std::string reason(int saved = 0) {
  const int e = saved != 0 ? saved : errno;
  return e != 0 ? std::strerror(e) : std::string("the stream failed");
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
    // The first failure's errno is the reason (a full disk: "No space left on device");
    // the calls after it may reset errno. Closing writes the rest of the buffer, so it
    // is checked too.
    int failed = out ? 0 : errno;
    if (out) out.flush();
    if (!out && failed == 0) failed = errno;
    if (out) out.close();
    if (!out) {
      const std::string why = reason(failed);
      if (out.is_open()) out.close();
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
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
