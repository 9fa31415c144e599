#include "core/run_stats.h"

#include <sys/resource.h>

namespace hrad {

std::uint64_t peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<std::uint64_t>(u.ru_maxrss) * 1024u;  // Linux reports KiB
}

}  // namespace hrad
